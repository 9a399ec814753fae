#include <geom/isosurface/mesh_sdf.h>

#include <geom/core/errors.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>
#include <vector>

namespace geom {

namespace {

constexpr std::size_t kBlock = 8;

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
  if (a > b) std::swap(a, b);
  return (std::uint64_t(a) << 32) | b;
}

void require_closed(const SurfaceMesh& mesh) {
  if (mesh.n_faces() == 0)
    throw InvalidArgument("signed distance needs a closed mesh, got one without faces");
  std::size_t open = 0;
  Halfedge first;
  for (Halfedge h : mesh.halfedges())
    if (mesh.is_boundary(h)) {
      if (open++ == 0) first = h;
    }
  if (open > 0)
    throw InvalidArgument(
        "signed distance needs a closed mesh (an open surface has no inside); it has " +
        std::to_string(open) + " boundary edge" + (open == 1 ? "" : "s") +
        ", e.g. between vertices " + std::to_string(mesh.from_vertex(first).idx()) + " and " +
        std::to_string(mesh.to_vertex(first).idx()));
}

double corner_angle(const Point& p, const Point& a, const Point& b) {
  Eigen::Vector3d u = a - p, v = b - p;
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

}  // namespace

MeshSignedDistance::MeshSignedDistance(const SurfaceMesh& mesh) {
  require_closed(mesh);
  bvh_ = TriangleBvh(mesh);
  const auto& pos = bvh_.positions();
  const std::size_t n = bvh_.n_triangles();
  face_normals_.resize(n);
  edge_normals_.resize(n);
  vertex_normals_.assign(pos.size(), Eigen::Vector3d::Zero());
  std::unordered_map<std::uint64_t, Eigen::Vector3d> edge_sum;
  edge_sum.reserve(n * 2);
  for (std::uint32_t t = 0; t < n; ++t) {
    const auto& i = bvh_.triangle_indices(t);
    Eigen::Vector3d nrm = (pos[i[1]] - pos[i[0]]).cross(pos[i[2]] - pos[i[0]]);
    double len = nrm.norm();
    // A zero-area triangle has no direction to offer; its neighbours decide the sign.
    face_normals_[t] = len > 0 ? Eigen::Vector3d(nrm / len) : Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) {
      // try_emplace with an explicit zero: Eigen vectors are not zeroed by default.
      edge_sum.try_emplace(edge_key(i[k], i[(k + 1) % 3]), Eigen::Vector3d::Zero())
          .first->second += face_normals_[t];
      vertex_normals_[i[k]] +=
          corner_angle(pos[i[k]], pos[i[(k + 1) % 3]], pos[i[(k + 2) % 3]]) * face_normals_[t];
    }
  }
  for (std::uint32_t t = 0; t < n; ++t) {
    const auto& i = bvh_.triangle_indices(t);
    for (int k = 0; k < 3; ++k) edge_normals_[t][k] = edge_sum.at(edge_key(i[k], i[(k + 1) % 3]));
  }
}

Eigen::Vector3d MeshSignedDistance::pseudo_normal(std::uint32_t t, const Point& p) const {
  const auto& i = bvh_.triangle_indices(t);
  const auto& pos = bvh_.positions();
  const Eigen::Vector3d a = pos[i[0]], e0 = pos[i[1]] - a, e1 = pos[i[2]] - a, d = p - a;
  const double d00 = e0.dot(e0), d01 = e0.dot(e1), d11 = e1.dot(e1);
  const double det = d00 * d11 - d01 * d01;
  if (!(det > 0)) return face_normals_[t];  // degenerate: neighbours carry the sign
  const double d20 = d.dot(e0), d21 = d.dot(e1);
  double bary[3];
  bary[1] = (d11 * d20 - d01 * d21) / det;
  bary[2] = (d00 * d21 - d01 * d20) / det;
  bary[0] = 1.0 - bary[1] - bary[2];
  // The closest point is clamped onto an edge or a corner when it is there; the tolerance
  // only absorbs the rounding of recomputing its barycentric coordinates.
  constexpr double kEps = 1e-9;
  int zero = 0, corner = -1, edge = -1;
  for (int k = 0; k < 3; ++k)
    if (bary[k] < kEps) {
      ++zero;
      edge = (k + 1) % 3;  // the edge opposite corner k joins corners k+1, k+2
    } else {
      corner = k;
    }
  if (zero >= 2) return vertex_normals_[i[corner]];
  if (zero == 1) return edge_normals_[t][edge];
  return face_normals_[t];
}

MeshSignedDistance::Query MeshSignedDistance::query(const Eigen::Vector3d& p,
                                                    double max_distance) const {
  Query q;
  q.closest = bvh_.closest_point(p, max_distance);
  if (!q.closest.found()) return q;
  q.sign = (p - q.closest.point).dot(pseudo_normal(q.closest.triangle, q.closest.point)) < 0 ? -1 : 1;
  return q;
}

double MeshSignedDistance::operator()(const Eigen::Vector3d& p) const {
  Query q = query(p);
  return q.sign * std::sqrt(q.closest.distance_squared);
}

MeshSdf signed_distance_grid(const SurfaceMesh& mesh, const MeshSdfOptions& options) {
  return signed_distance_grid(MeshSignedDistance(mesh), options);
}

MeshSdf signed_distance_grid(const MeshSignedDistance& distance, const MeshSdfOptions& options) {
  const std::size_t n = options.resolution;
  if (n < 8 || n > 4096)
    throw InvalidArgument("signed distance grid resolution must be in [8, 4096], got " +
                          std::to_string(n));
  if (!std::isfinite(options.level))
    throw InvalidArgument("signed distance level must be finite");
  if (!std::isfinite(options.band_cells) || options.band_cells < 1)
    throw InvalidArgument("signed distance band_cells must be a finite number ≥ 1");
  const Eigen::AlignedBox3d& bounds = distance.bvh().bounds();
  const double grow = std::max(options.level, 0.0);
  const Eigen::Vector3d extent = bounds.sizes();
  // Margin of grow + 3 cells on each side, with n samples over the longest axis.
  const double h = std::max(extent.maxCoeff() + 2 * grow, 1e-300) / double(n - 7);
  GridDims dims;
  std::size_t* d[3] = {&dims.nx, &dims.ny, &dims.nz};
  GridGeometry geo;
  geo.spacing = Eigen::Vector3d::Constant(h);
  for (int k = 0; k < 3; ++k) {
    *d[k] = std::min<std::size_t>(n, std::size_t(std::ceil((extent[k] + 2 * grow) / h)) + 7);
    geo.origin[k] = bounds.center()[k] - 0.5 * h * double(*d[k] - 1);
  }
  MeshSdf out;
  out.grid = ScalarGrid(dims, geo, options.use_double);
  const double band = std::abs(options.level) + options.band_cells * h;
  const std::size_t bx = (dims.nx + kBlock - 1) / kBlock, by = (dims.ny + kBlock - 1) / kBlock,
                    bz = (dims.nz + kBlock - 1) / kBlock;
  std::atomic<std::size_t> exact{0}, near{0};
  const GridView view = out.grid.view();
  // One box of samples [lo, hi): bounded from its centre's distance when the box is farther
  // than the band, otherwise split once (8³ → 4³) and then evaluated sample by sample.
  auto fill = [&](auto* values) {
    using T = std::remove_pointer_t<decltype(values)>;
    // `hint`: a surface point found for a nearby box; the distance to it bounds this one's
    // search, which a far-away query otherwise spends most of its time without.
    auto box = [&](const std::array<std::size_t, 3>& lo, const std::array<std::size_t, 3>& hi,
                   bool split, Point& hint, auto& self) -> void {
      const Eigen::Vector3d p0 = view.position(lo[0], lo[1], lo[2]);
      const Eigen::Vector3d p1 = view.position(hi[0] - 1, hi[1] - 1, hi[2] - 1);
      const Eigen::Vector3d centre = 0.5 * (p0 + p1);
      const double radius = 0.5 * (p1 - p0).norm();
      const MeshSignedDistance::Query cq =
          distance.query(centre, std::isfinite(hint.x()) ? (centre - hint).norm() * (1 + 1e-9) + 1e-300
                                                         : std::numeric_limits<double>::infinity());
      hint = cq.closest.point;
      const double dc = std::sqrt(cq.closest.distance_squared);
      if (!options.exact_everywhere && dc > radius + band) {
        for (std::size_t z = lo[2]; z < hi[2]; ++z)
          for (std::size_t y = lo[1]; y < hi[1]; ++y)
            for (std::size_t x = lo[0]; x < hi[0]; ++x)
              values[dims.index(x, y, z)] = T(cq.sign * (dc - (view.position(x, y, z) - centre).norm()));
        return;
      }
      if (split) {
        ++near;
        for (int c = 0; c < 8; ++c) {
          std::array<std::size_t, 3> a, b;
          for (int k = 0; k < 3; ++k) {
            const std::size_t mid = std::min(lo[k] + kBlock / 2, hi[k]);
            a[k] = (c >> k) & 1 ? mid : lo[k];
            b[k] = (c >> k) & 1 ? hi[k] : mid;
          }
          if (a[0] < b[0] && a[1] < b[1] && a[2] < b[2]) self(a, b, false, hint, self);
        }
        return;
      }
      // The answer lies within dc + radius of the centre, and no farther than the previous
      // sample's closest point: a search bounded by the nearer of the two.
      Point last = cq.closest.point;
      for (std::size_t z = lo[2]; z < hi[2]; ++z)
        for (std::size_t y = lo[1]; y < hi[1]; ++y)
          for (std::size_t x = lo[0]; x < hi[0]; ++x) {
            const Eigen::Vector3d p = view.position(x, y, z);
            const double bound = std::min(dc + radius, (p - last).norm()) * (1 + 1e-9) + 1e-300;
            MeshSignedDistance::Query q = distance.query(p, bound);
            last = q.closest.point;
            values[dims.index(x, y, z)] = T(q.sign * std::sqrt(q.closest.distance_squared));
          }
      exact += (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
    };
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, bx * by * bz), [&](const auto& range) {
      Point hint = Point::Constant(std::numeric_limits<double>::infinity());
      for (std::size_t b = range.begin(); b != range.end(); ++b) {
        const std::array<std::size_t, 3> lo = {(b % bx) * kBlock, (b / bx % by) * kBlock,
                                               (b / (bx * by)) * kBlock};
        const std::array<std::size_t, 3> hi = {std::min(lo[0] + kBlock, dims.nx),
                                               std::min(lo[1] + kBlock, dims.ny),
                                               std::min(lo[2] + kBlock, dims.nz)};
        box(lo, hi, true, hint, box);
      }
    });
  };
  if (options.use_double)
    fill(out.grid.doubles().data());
  else
    fill(out.grid.floats().data());
  out.stats.samples = dims.size();
  out.stats.exact_samples = exact;
  out.stats.blocks = bx * by * bz;
  out.stats.near_blocks = near;
  return out;
}

}  // namespace geom
