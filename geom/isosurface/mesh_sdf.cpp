#include <geom/isosurface/mesh_sdf.h>

#include <geom/core/errors.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numbers>
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
  mark_folds();
}

void MeshSignedDistance::mark_folds() {
  // An edge whose two faces fold back onto each other (unit normals nearly cancelling:
  // dihedral within ~11° of a full fold) is where a hole-fill fan overlaps itself, and an
  // overlapping surface is not an embedding, so no pseudo-normal near it is trustworthy
  // (bunny_closed.off: samples 0.01 away got the wrong sign). A closest point on a face
  // touching such an edge's corners takes the winding number: a fan folds around its
  // centre, so its overlapping triangles all share that corner, not only the folded edge.
  constexpr double kFold = 0.2;
  std::vector<char> fold_vertex(bvh_.positions().size(), 0);
  for (std::uint32_t t = 0; t < bvh_.n_triangles(); ++t) {
    const auto& i = bvh_.triangle_indices(t);
    for (int k = 0; k < 3; ++k)
      if (edge_normals_[t][k].norm() < kFold && face_normals_[t].squaredNorm() > 0)
        fold_vertex[i[k]] = fold_vertex[i[(k + 1) % 3]] = 1;
  }
  near_fold_.assign(bvh_.n_triangles(), 0);
  for (std::uint32_t t = 0; t < bvh_.n_triangles(); ++t) {
    const auto& i = bvh_.triangle_indices(t);
    near_fold_[t] = fold_vertex[i[0]] || fold_vertex[i[1]] || fold_vertex[i[2]];
  }
}

Eigen::Vector3d MeshSignedDistance::pseudo_normal(std::uint32_t t, const Point& c) const {
  // Classify the closest point by its distance to the corners and edges, not by its
  // barycentric coordinates: on a sliver those amplify the rounding of c by the aspect
  // ratio, so a point on an edge reads as interior and gets the sliver's normal.
  const auto& i = bvh_.triangle_indices(t);
  const auto& pos = bvh_.positions();
  const Point v[3] = {pos[i[0]], pos[i[1]], pos[i[2]]};
  double longest = 0, scale = c.cwiseAbs().maxCoeff();
  for (int k = 0; k < 3; ++k) {
    longest = std::max(longest, (v[(k + 1) % 3] - v[k]).norm());
    scale = std::max(scale, v[k].cwiseAbs().maxCoeff());
  }
  // c carries rounding of ~ε·scale (and ~ε·longest on a sliver); the margin above it only
  // moves points within 1e-9 of an edge's length onto the edge, where the edge's
  // pseudo-normal still has a positive dot product with the face's normal.
  const double tol = 1e-9 * longest + 64 * std::numeric_limits<double>::epsilon() * scale;
  int corner = -1, edge = -1;
  double best_corner = tol * tol, best_edge = tol * tol;  // squared distances
  for (int k = 0; k < 3; ++k) {
    const double dv = (c - v[k]).squaredNorm();
    if (dv <= best_corner) best_corner = dv, corner = k;
    const Eigen::Vector3d e = v[(k + 1) % 3] - v[k];
    const double len2 = e.squaredNorm();
    const double s = len2 > 0 ? std::clamp((c - v[k]).dot(e) / len2, 0.0, 1.0) : 0.0;
    const double de = (c - v[k] - s * e).squaredNorm();
    if (de <= best_edge) best_edge = de, edge = k;
  }
  if (corner >= 0) return vertex_normals_[i[corner]];
  if (edge >= 0) return edge_normals_[t][edge];
  return face_normals_[t];
}

MeshSignedDistance::Query MeshSignedDistance::query(const Eigen::Vector3d& p, double max_distance,
                                                    SignMemo* memo) const {
  Query q;
  q.closest = bvh_.closest_point(p, max_distance);
  if (!q.closest.found()) return q;
  const Eigen::Vector3d off = p - q.closest.point;
  const Eigen::Vector3d n = pseudo_normal(q.closest.triangle, q.closest.point);
  const double s = off.dot(n);
  // An offset nearly perpendicular to the pseudo-normal is decided by rounding: as unsure
  // as a fold.
  const bool sure = !near_fold_[q.closest.triangle] && std::abs(s) > 1e-6 * off.norm() * n.norm();
  const double d = std::sqrt(q.closest.distance_squared);
  if (sure || d == 0) {
    q.sign = s < 0 ? -1 : 1;
  } else {
    // The open balls around p and a remembered point hold no surface; when they overlap,
    // their union joins the two without crossing it, so they share the winding number.
    // Neighbouring grid samples nearly always overlap, so few queries pay the O(F) sum.
    const auto known = [&] {
      if (memo)
        for (int k = 0; k < SignMemo::kSize; ++k)
          if (memo->sign[k] != 0 &&
              (p - memo->centre[k]).norm() < (d + memo->radius[k]) * (1 - 1e-9))
            return memo->sign[k];
      return 0;
    }();
    q.sign = known != 0 ? known : winding_number(p) > 0.5 ? -1 : 1;
  }
  if (memo && d > 0) {
    const int k = memo->next;
    memo->centre[k] = p, memo->radius[k] = d, memo->sign[k] = q.sign;
    memo->next = (k + 1) % SignMemo::kSize;
  }
  return q;
}

double MeshSignedDistance::winding_number(const Eigen::Vector3d& p) const {
  // Each triangle's signed solid angle is 2·atan2(num, den) (Van Oosterom, Strackee); atan2
  // keeps angles near ±2π (p close to a face) that a plain atan would wrap. Offsets and
  // their lengths are computed once per vertex, not once per corner.
  const auto& pos = bvh_.positions();
  std::vector<Eigen::Vector4d> rel(pos.size());
  for (std::size_t v = 0; v < pos.size(); ++v) {
    const Eigen::Vector3d r = pos[v] - p;
    rel[v] << r, r.norm();
  }
  double sum = 0;
  for (std::uint32_t t = 0; t < bvh_.n_triangles(); ++t) {
    const auto& i = bvh_.triangle_indices(t);
    const Eigen::Vector4d &ra = rel[i[0]], &rb = rel[i[1]], &rc = rel[i[2]];
    const Eigen::Vector3d a = ra.head<3>(), b = rb.head<3>(), c = rc.head<3>();
    const double num = a.dot(b.cross(c));
    const double den = ra[3] * rb[3] * rc[3] + a.dot(b) * rc[3] + b.dot(c) * ra[3] + c.dot(a) * rb[3];
    sum += std::atan2(num, den);
  }
  return sum / (2 * std::numbers::pi);
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
                   bool split, Point& hint, MeshSignedDistance::SignMemo& memo,
                   auto& self) -> void {
      const Eigen::Vector3d p0 = view.position(lo[0], lo[1], lo[2]);
      const Eigen::Vector3d p1 = view.position(hi[0] - 1, hi[1] - 1, hi[2] - 1);
      const Eigen::Vector3d centre = 0.5 * (p0 + p1);
      const double radius = 0.5 * (p1 - p0).norm();
      const MeshSignedDistance::Query cq =
          distance.query(centre, std::isfinite(hint.x()) ? (centre - hint).norm() * (1 + 1e-9) + 1e-300
                                                         : std::numeric_limits<double>::infinity(),
                         &memo);
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
          if (a[0] < b[0] && a[1] < b[1] && a[2] < b[2]) self(a, b, false, hint, memo, self);
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
            MeshSignedDistance::Query q = distance.query(p, bound, &memo);
            last = q.closest.point;
            values[dims.index(x, y, z)] = T(q.sign * std::sqrt(q.closest.distance_squared));
          }
      exact += (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
    };
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, bx * by * bz), [&](const auto& range) {
      Point hint = Point::Constant(std::numeric_limits<double>::infinity());
      MeshSignedDistance::SignMemo memo;
      for (std::size_t b = range.begin(); b != range.end(); ++b) {
        const std::array<std::size_t, 3> lo = {(b % bx) * kBlock, (b / bx % by) * kBlock,
                                               (b / (bx * by)) * kBlock};
        const std::array<std::size_t, 3> hi = {std::min(lo[0] + kBlock, dims.nx),
                                               std::min(lo[1] + kBlock, dims.ny),
                                               std::min(lo[2] + kBlock, dims.nz)};
        box(lo, hi, true, hint, memo, box);
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
