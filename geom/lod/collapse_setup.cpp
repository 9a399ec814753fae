// The engine's setup: the flat triangle arrays, per-vertex triangle lists, quadrics and the
// queue's first entries, built from a SurfaceMesh. Its sweeps run in parallel blocks whose
// results do not depend on the split: the engine starts from the same state, bit for bit,
// on any number of cores. And its read-out, extract().

#include <geom/lod/collapse.h>

#include <geom/core/from_triangles.h>
#include <geom/core/huge_pages.h>

#include <Eigen/Geometry>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <unordered_set>
#include <utility>

namespace geom::detail {

namespace {

std::uint64_t pair_key(Vertex a, Vertex b) {
  const std::uint64_t lo = std::min(a.idx(), b.idx()), hi = std::max(a.idx(), b.idx());
  return lo << 32 | hi;
}

// The first corner of a polygon whose fan diagonals are neither edges of the mesh nor
// diagonals of an earlier polygon: such a diagonal (two quads around a valence-2 vertex, say)
// would give that edge a third and fourth triangle. c.size() when none qualifies.
std::size_t fan_apex(const SurfaceMesh& mesh, const std::vector<Vertex>& c,
                     const std::unordered_set<std::uint64_t>& diagonals) {
  const std::size_t k = c.size();
  for (std::size_t apex = 0; k > 3 && apex < k; ++apex) {
    bool clear = true;
    for (std::size_t i = 2; i + 1 < k && clear; ++i) {
      const Vertex w = c[(apex + i) % k];
      clear = !mesh.find_edge(c[apex], w).is_valid() && !diagonals.count(pair_key(c[apex], w));
    }
    if (clear) return apex;
  }
  return k > 3 ? k : 0;
}

// body(begin, end) over the blocks of [0, n), on all cores. The setup's sweeps write each
// element from one block only, so their results do not depend on the split.
template <class Body>
void for_blocks(std::size_t n, std::size_t grain, const Body& body) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, grain),
                    [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); });
}

// prefault() on all cores: the kernel clears each fresh page on the thread that maps it.
void prefault_parallel(void* data, std::size_t bytes) {
  constexpr std::size_t kBlock = std::size_t{4} << 20;
  for_blocks((bytes + kBlock - 1) / kBlock, 1, [&](std::size_t begin, std::size_t end) {
    const std::size_t to = std::min(bytes, end * kBlock);
    prefault(static_cast<char*>(data) + begin * kBlock, to - begin * kBlock);
  });
}

// A triangle mesh without deleted faces (the usual input) goes to out as it is, in parallel;
// false (out left empty) when there are deleted faces or a polygon.
bool copy_triangles(const SurfaceMesh& mesh, const std::vector<std::uint32_t>& dense,
                    std::vector<std::array<std::uint32_t, 3>>& out) {
  if (mesh.n_faces() != mesh.faces_size()) return false;
  prefault_parallel(out.data(), mesh.faces_size() * sizeof(out[0]));
  out.resize(mesh.faces_size());
  std::atomic<bool> polygon{false};
  for_blocks(mesh.faces_size(), 16384, [&](std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f) {
      const Halfedge h0 = mesh.halfedge(Face(static_cast<std::uint32_t>(f)));
      const Halfedge h1 = mesh.next(h0), h2 = mesh.next(h1);
      if (mesh.next(h2) != h0) polygon.store(true, std::memory_order_relaxed);
      out[f] = {dense[mesh.to_vertex(h0).idx()], dense[mesh.to_vertex(h1).idx()],
                dense[mesh.to_vertex(h2).idx()]};
    }
  });
  if (polygon) out.clear();
  return !polygon;
}

// Every face to out, polygons as fans from the corner fan_apex() picks.
void fan_triangulate(const SurfaceMesh& mesh, const std::vector<std::uint32_t>& dense,
                     std::vector<std::array<std::uint32_t, 3>>& out) {
  std::vector<Vertex> corners;
  std::unordered_set<std::uint64_t> diagonals;
  for (Face f : mesh.faces()) {
    corners.clear();
    for (Vertex v : mesh.vertices(f)) corners.push_back(v);
    const std::size_t apex = fan_apex(mesh, corners, diagonals);
    const std::size_t k = corners.size();
    // (A fan would give an edge a third face; the result could not be a mesh again. Found by
    // fuzz_algorithms: a quad whose two diagonals are both edges, after build() split a
    // non-manifold file.)
    if (apex == k)
      throw InvalidArgument("face " + std::to_string(f.idx()) + " (" + std::to_string(k) +
                            " corners) has no fan whose diagonals are not already edges: every "
                            "triangulation of it leaves the mesh non-manifold; split it first");
    for (std::size_t i = 2; i + 1 < k; ++i)
      diagonals.insert(pair_key(corners[apex], corners[(apex + i) % k]));
    for (std::size_t i = 1; i + 1 < k; ++i)
      out.push_back({dense[corners[apex].idx()], dense[corners[(apex + i) % k].idx()],
                     dense[corners[(apex + i + 1) % k].idx()]});
  }
}

// How far the input's coordinates may be from the values they stand for, at the largest
// magnitude: half the step of the coarsest rounding they all fit (a number of decimal places,
// or of significant digits), else half a float32 ulp if they are float32 values, else half
// a double ulp. A sample of about 4096 vertices decides. A coordinate fits a step when it is
// within a float32 ulp of a multiple of it (decimals stored as float32 and printed again);
// only steps above four such ulps are tried, where an unrounded sample cannot fit by chance.
double coordinate_quantum(const std::vector<Point>& model, double max_abs) {
  if (model.empty() || !(max_abs > 0)) return 0.0;
  const std::size_t stride = std::max<std::size_t>(1, model.size() / 4096);
  const auto all = [&](auto&& fits) {
    for (std::size_t v = 0; v < model.size(); v += stride)
      for (int i = 0; i < 3; ++i)
        if (!fits(model[v][i])) return false;
    return true;
  };
  const auto near_multiple = [](double x, double step) {
    return std::abs(x - std::nearbyint(x / step) * step) <= std::ldexp(std::abs(x), -23);
  };
  const double smallest_step = 4.0 * std::ldexp(max_abs, -23);
  for (int k = 0; k <= 15; ++k) {
    const double step = std::pow(10.0, -k);
    if (step <= smallest_step) break;
    if (all([&](double x) { return near_multiple(x, step); })) return 0.5 * step;
  }
  const double top = std::floor(std::log10(max_abs));
  for (int digits = 1; digits <= 6; ++digits) {
    const auto step_at = [&](double e) { return std::pow(10.0, e - digits + 1); };
    if (all([&](double x) {
          return x == 0 || near_multiple(x, step_at(std::floor(std::log10(std::abs(x)))));
        }))
      return 0.5 * step_at(top);
  }
  const double f32_half_ulp = std::ldexp(1.0, std::ilogb(max_abs) - 24);
  // Float32 values, possibly printed with more places than they hold (fandisk: 10).
  const auto float32 = [&](double x) {
    return std::abs(static_cast<double>(static_cast<float>(x)) - x) <=
           1e-9 * std::abs(x) + 1e-10 * max_abs;
  };
  if (all(float32)) return f32_half_ulp;
  return std::ldexp(1.0, std::ilogb(max_abs) - 53);
}

}  // namespace

CollapseEngine::CollapseEngine(const SurfaceMesh& mesh, const SimplifyOptions& options,
                               bool record, std::size_t parallel_min_triangles)
    : options_(options), record_(record) {
  if (!(options.ratio >= 0.0 && options.ratio <= 1.0))
    throw InvalidArgument("simplify: ratio must be in [0, 1], got " + std::to_string(options.ratio));
  if (std::isnan(options.max_error) || options.max_error < 0)
    throw InvalidArgument("simplify: max_error must be >= 0, got " +
                          std::to_string(options.max_error));
  if (!(options.boundary_weight >= 0) || !std::isfinite(options.boundary_weight))
    throw InvalidArgument("simplify: boundary_weight must be finite and >= 0");
  if (options.refit_iterations < -1)
    throw InvalidArgument("simplify: refit_iterations must be >= -1 (-1: automatic), got " +
                          std::to_string(options.refit_iterations));

  // Dense numbering of the vertices that faces use, in their order: counted per block of
  // vertices, then numbered from each block's offset.
  const auto used = [&](std::size_t v) {
    return !mesh.is_deleted(Vertex(static_cast<std::uint32_t>(v))) &&
           !mesh.is_isolated(Vertex(static_cast<std::uint32_t>(v)));
  };
  constexpr std::size_t kVertexBlock = 16384;
  const std::size_t n_blocks = (mesh.vertices_size() + kVertexBlock - 1) / kVertexBlock;
  std::vector<std::uint32_t> block_start(n_blocks + 1, 0);
  std::vector<std::uint8_t> block_open(n_blocks, 0);
  for_blocks(n_blocks, 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k)
      for (std::size_t v = k * kVertexBlock; v < std::min(mesh.vertices_size(), (k + 1) * kVertexBlock); ++v)
        if (used(v)) {
          ++block_start[k + 1];
          block_open[k] |= mesh.is_boundary(Vertex(static_cast<std::uint32_t>(v)));
        }
  });
  for (std::size_t k = 0; k < n_blocks; ++k) block_start[k + 1] += block_start[k];
  const bool closed = std::find(block_open.begin(), block_open.end(), 1) == block_open.end();
  const std::size_t n = block_start[n_blocks];
  std::vector<std::uint32_t> dense(mesh.vertices_size(), kNone);
  vertex_of_.resize(n);
  reserve_huge(original_positions_, n);
  original_positions_.resize(n);
  for_blocks(n_blocks, 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) {
      std::uint32_t i = block_start[k];
      for (std::size_t v = k * kVertexBlock; v < std::min(mesh.vertices_size(), (k + 1) * kVertexBlock); ++v)
        if (used(v)) {
          const Vertex vh(static_cast<std::uint32_t>(v));
          dense[v] = i;
          vertex_of_[i] = vh;
          original_positions_[i++] = mesh.position(vh);
        }
    }
  });
  triangles_.reserve(mesh.n_faces() * 2);
  advise_huge_pages(triangles_.data(), triangles_.capacity() * sizeof(triangles_[0]));
  if (!copy_triangles(mesh, dense, triangles_)) fan_triangulate(mesh, dense, triangles_);
  if (record_) original_triangles_ = triangles_;
  tri_alive_.assign(triangles_.size(), 1);
  alive_triangles_ = triangles_.size();

  // Work in a box of unit diagonal centred at the origin, so that quadric coefficients and
  // tolerances mean the same at 1e-9 and at 1e9.
  Eigen::AlignedBox3d box;
  box.setEmpty();
  // A NaN or infinite position would poison every quadric it touches and every cost compared
  // with them; name it instead.
  for (std::size_t i = 0; i < n; ++i) {
    const Point& p = original_positions_[i];
    if (!p.allFinite())
      throw InvalidArgument("simplify: vertex " + std::to_string(vertex_of_[i].idx()) +
                            " has a non-finite position");
    box.extend(p);
  }
  if (n > 0) {
    center_ = box.center();
    const double diag = box.diagonal().norm();
    scale_ = diag > 0 && std::isfinite(diag) ? diag : 1.0;
  }
  // Only a progressive mesh needs the input positions once collapses start.
  model_ = record_ ? original_positions_ : std::move(original_positions_);
  // Huge pages: the main loop reads these arrays at random, one neighbourhood per collapse.
  vd_.reserve(n);
  advise_huge_pages(vd_.data(), n * sizeof(VertexData));
  prefault_parallel(vd_.data(), n * sizeof(VertexData));
  vd_.resize(n);
  // The sweeps over all triangles below read a compact copy of the positions: through vd_,
  // each corner would bring in a 128-byte record for 24 bytes.
  std::vector<Point> pos;
  reserve_huge(pos, n);
  pos.resize(n);
  for_blocks(n, 4096, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) vd_[i].p = pos[i] = (model_[i] - center_) / scale_;
  });

  if (options.refit_iterations != 0 && !record_) {
    merged_into_.assign(n, kNone);
    vertex_area_.resize(n);
  }
  stamp_.assign(n, 0);
  for (Vertex v : options.locked)
    if (mesh.is_valid(v) && dense[v.idx()] != kNone) vd_[dense[v.idx()]].locked = 1;

  std::vector<std::uint32_t> count(n, 0);
  for (const auto& t : triangles_)
    for (std::uint32_t v : t) ++count[v];
  std::uint32_t offset = 0;
  for (std::size_t v = 0; v < n; ++v) {
    vd_[v].ref_begin = offset;
    vd_[v].ref_size = count[v];
    offset += std::exchange(count[v], offset);
  }
  refs_capacity_ = 3 * static_cast<std::size_t>(offset) + 64;
  refs_.reset(new std::uint32_t[refs_capacity_]);
  advise_huge_pages(refs_.get(), refs_capacity_ * sizeof(std::uint32_t));
  prefault_parallel(refs_.get(), std::size_t{offset} * sizeof(std::uint32_t));
  // count[v] is now v's fill cursor: a dense array, where vd_ has a record of two lines.
  for (std::uint32_t t = 0; t < triangles_.size(); ++t)
    for (std::uint32_t v : triangles_[t]) refs_[count[v]++] = t;

  // Each face's plane is weighted by its area plus a quarter of the mean area. Pure area
  // weights (the integral of squared distance) give the best RMS error, but let small
  // triangles vanish: a spike or crease of tiny faces costs almost nothing to remove, however
  // far it sticks out, and it then sets the Hausdorff error. The floor keeps every face
  // counting, as CGAL's unweighted planes do, while large faces still count for more.
  struct Plane {
    Eigen::Vector3d unit;
    double len;  // twice the area; unit is meaningless unless it is positive and finite
  };
  // Not cleared first: the sweep writes every element, on all cores, faulting its pages in.
  const std::unique_ptr<Plane[]> planes(new Plane[triangles_.size()]);
  advise_huge_pages(planes.get(), triangles_.size() * sizeof(Plane));
  for_blocks(triangles_.size(), 8192, [&](std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f) {
      const auto& t = triangles_[f];
      const Point &a = pos[t[0]], &b = pos[t[1]], &c = pos[t[2]];
      const double len = (b - a).cross(c - a).norm();
      planes[f] = {(b - a).cross(c - a) / len, len};
    }
  });
  double total_area = 0;  // summed in face order: the floor, and so every quadric, stays the same
  for (std::size_t f = 0; f < triangles_.size(); ++f)
    if (planes[f].len > 0 && std::isfinite(planes[f].len)) total_area += 0.5 * planes[f].len;
  const double floor_area = triangles_.empty() ? 0.0 : 0.25 * total_area / triangles_.size();
  pinv_tolerance_ = pseudo_inverse_tolerance(
      n > 0 ? std::max(box.min().cwiseAbs().maxCoeff(), box.max().cwiseAbs().maxCoeff()) : 0.0,
      total_area);
  // Each vertex gathers the planes of its triangles in their order (its list is sorted), the
  // order in which a sweep over the triangles would add them: the same sums, bit for bit,
  // and no two threads write one vertex.
  for_blocks(n, 2048, [&](std::size_t begin, std::size_t end) {
    for (std::size_t v = begin; v < end; ++v) {
      VertexData& d = vd_[v];
      double area2 = 0;  // twice the area of v's triangles, normalised units
      for (std::uint32_t i = d.ref_begin; i < d.ref_begin + d.ref_size; ++i) {
        const Plane& pl = planes[refs_[i]];
        if (!(pl.len > 0) || !std::isfinite(pl.len)) continue;
        const double weight = 0.5 * pl.len + floor_area;
        // Each vertex's quadric is stored relative to its own position (see place()).
        d.q += Quadric::plane(pl.unit, pl.unit.dot(pos[v] - pos[triangles_[refs_[i]][0]]), weight);
        d.weight += weight;
        area2 += pl.len;
      }
      if (!vertex_area_.empty()) vertex_area_[v] = area2 / 6 * scale_ * scale_;
    }
  });

  // Boundary edges: a→b with no triangle b→a around a. Each gets a constraint plane
  // through the edge, perpendicular to its face, weighted like an area (length²). A closed
  // mesh has none (its polygons' fans pair every edge), so the search is skipped there.
  if (!closed) boundary_length2_.assign(n, 0.0);
  for (std::uint32_t a = 0; a < n && !closed; ++a) {
    for (std::uint32_t i = vd_[a].ref_begin; i < vd_[a].ref_begin + vd_[a].ref_size; ++i) {
      const auto& t = triangles_[refs_[i]];
      const int k = t[0] == a ? 0 : t[1] == a ? 1 : 2;
      const std::uint32_t b = t[(k + 1) % 3];
      bool twin = false;
      for (std::uint32_t j = vd_[a].ref_begin; j < vd_[a].ref_begin + vd_[a].ref_size && !twin; ++j) {
        const auto& s = triangles_[refs_[j]];
        const int m = s[0] == a ? 0 : s[1] == a ? 1 : 2;
        twin = s[(m + 2) % 3] == b;
      }
      if (twin) continue;
      vd_[a].boundary = vd_[b].boundary = 1;
      const Eigen::Vector3d e = vd_[b].p - vd_[a].p;
      const Eigen::Vector3d fn = e.cross(vd_[t[(k + 2) % 3]].p - vd_[a].p);
      Eigen::Vector3d cn = e.cross(fn);
      const double len = cn.norm();
      if (options.boundary_weight > 0 && len > 0 && std::isfinite(len)) {
        cn /= len;
        const double w = options.boundary_weight * e.squaredNorm();
        vd_[a].q += Quadric::plane(cn, 0.0, w);
        vd_[b].q += Quadric::plane(cn, cn.dot(e), w);
        boundary_length2_[a] += e.squaredNorm();
        boundary_length2_[b] += e.squaredNorm();
      }
    }
  }
  if (options.lock_boundary)
    for (std::size_t v = 0; v < n; ++v) vd_[v].locked |= vd_[v].boundary;
  if (options.attributes.any() && !record_) init_attributes(mesh);
  // A progressive mesh records one global order: it stays serial, as do meshes too small to
  // repay the barriers. Attribute data keeps to the parts (a wedge belongs to one vertex, a
  // corner's wedge to its triangle; see collapse_loop.cpp).
  if (!record_ && triangles_.size() >= parallel_min_triangles &&
      n >= 64 * kParts)
    partition(pos);

  // The queue starts with every edge once, from its lower end a, in the order of a walk over
  // a's triangles, vertex by vertex. Blocks of vertices list and cost their edges in
  // parallel, in arrays of their own that the queue then takes in block order: the same
  // entries, in the same order, as one serial walk.
  constexpr std::size_t kEdgeBlock = 4096;
  std::vector<EdgeBlock> blocks((n + kEdgeBlock - 1) / kEdgeBlock);
  for_blocks(blocks.size(), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) {
      const std::size_t first = k * kEdgeBlock, last = std::min(n, first + kEdgeBlock);
      std::size_t room = 0;  // each triangle at a adds at most two edges
      for (std::size_t a = first; a < last; ++a) room += 2 * std::size_t{vd_[a].ref_size};
      EdgeBlock& block = blocks[k];
      block.edges.reset(new Candidate[room]);  // not cleared: only the written part is read
      for (std::size_t a = first; a < last; ++a)
        block.size += higher_edges(static_cast<std::uint32_t>(a), block.edges.get() + block.size);
      set_costs(block.edges.get(), block.size);
    }
  });
  // The walks above used no marks; the tokens go on from where a marking walk would leave them.
  start_workers(blocks, static_cast<std::uint32_t>(n), offset);
}

std::vector<Point> CollapseEngine::normalised_positions() const {
  std::vector<Point> p(vd_.size());
  for (std::size_t v = 0; v < vd_.size(); ++v) p[v] = vd_[v].p;
  return p;
}

SurfaceMesh CollapseEngine::extract(std::vector<Vertex>* out_origin, std::vector<Vertex>* out_survivor,
                                    std::vector<std::uint32_t>* out_triangle) const {
  std::vector<std::uint32_t> index(vd_.size(), kNone);
  std::vector<Point> positions;
  positions.reserve(vd_.size());
  if (out_origin) out_origin->clear();
  for (std::size_t v = 0; v < vd_.size(); ++v) {
    if (vd_[v].ref_size == 0) continue;
    index[v] = static_cast<std::uint32_t>(positions.size());
    positions.push_back(model(v));
    if (out_origin) out_origin->push_back(vertex_of_[v]);
  }
  std::vector<std::array<std::uint32_t, 3>> kept;
  kept.reserve(alive_triangles_);
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    if (!tri_alive_[t]) continue;
    const auto& tri = triangles_[t];
    kept.push_back({index[tri[0]], index[tri[1]], index[tri[2]]});
    if (out_triangle) out_triangle->push_back(static_cast<std::uint32_t>(t));
  }
  if (out_survivor && !merged_into_.empty()) {
    // Follow each chain of collapses to its live end, shortening it on the way (halving).
    std::vector<std::uint32_t> root = merged_into_;
    for (std::size_t v = 0; v < root.size(); ++v) {
      std::uint32_t r = static_cast<std::uint32_t>(v);
      while (root[r] != kNone) {
        if (root[root[r]] != kNone) root[r] = root[root[r]];
        r = root[r];
      }
      if (index[r] != kNone) (*out_survivor)[vertex_of_[v].idx()] = Vertex(index[r]);
    }
  }
  SurfaceMesh out = mesh_from_triangles(positions, kept);
  if (attributes_) write_attributes(out);
  return out;
}

std::vector<double> CollapseEngine::input_vertex_areas(std::size_t input_vertices) const {
  std::vector<double> area;
  if (vertex_area_.empty()) return area;
  area.assign(input_vertices, 0.0);
  for_blocks(vertex_area_.size(), 16384, [&](std::size_t begin, std::size_t end) {
    for (std::size_t v = begin; v < end; ++v) area[vertex_of_[v].idx()] = vertex_area_[v];
  });
  return area;
}

std::uint32_t CollapseEngine::higher_edges(std::uint32_t a, Candidate* out) const {
  std::uint32_t k = 0;
  const bool locked = vd_[a].locked;
  for (std::uint32_t i = vd_[a].ref_begin; i < vd_[a].ref_begin + vd_[a].ref_size; ++i)
    for (std::uint32_t b : triangles_[refs_[i]]) {
      if (b <= a || (locked && vd_[b].locked)) continue;
      // A neighbour appears in two of a's triangles: a short scan of what a has so far.
      std::uint32_t j = 0;
      while (j < k && out[j].b != b) ++j;
      if (j == k) out[k++] = {0.0f, a, b, 0};
    }
  return k;
}

// Eigenvalues of a quadric below this fraction of its largest could come from the input's
// rounding alone: the pseudo-inverse treats their directions as free. A flat region's planes
// differ only by their corners' rounding, each coordinate by up to δ, so a corner by up to
// √3·δ across the plane; the worst tilt this gives a triangle of the mean area A (taken
// equilateral, height h, h² = √3·A) is 2·√3·δ / h, with one corner raised and the others
// lowered, and planes tilted by θ give in-plane eigenvalues θ² of the largest. The default
// 1e-7 was above that on fandisk (float32 data: 3.6e-11 here), dropping the in-plane
// directions of its 10°-tilted sides: the optimum then often cost more than an endpoint and
// the noisy input vertex stayed (RMS 1.053x CGAL's at 50%, which inverts unless the
// determinant is 0). On the 9-mesh matrix, this bound and 3 times it lose no case that 1e-7
// did not, except amo at 50% by 0.05-0.2% of RMS (already a loss, by 0.01%); a third of it
// and less lets collapses slide vertices along fandisk's creases and tilt long triangles
// off the surface (Hausdorff 1.39x CGAL's at 10%; sampling each new fan triangle's inside
// against the old surface stops that, but cost 3-4.5% of simplify()'s time).
double CollapseEngine::pseudo_inverse_tolerance(double max_abs, double total_area) const {
  if (triangles_.empty() || !(total_area > 0)) return kSolverRoundOff;
  const double delta = coordinate_quantum(model_, max_abs) / scale_;
  const double height2 = std::sqrt(3.0) * total_area / static_cast<double>(triangles_.size());
  return std::max(kSolverRoundOff, 12.0 * delta * delta / height2);
}

}  // namespace geom::detail
