#include <geom/lod/refit.h>

#include <geom/core/errors.h>
#include <geom/spatial/bvh.h>

#include <Eigen/Dense>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace geom {

namespace {

// A weighted point of the original surface (weight = the area it stands for).
struct Sample {
  Point p;
  double w;
  Vertex vertex{};  ///< the original vertex it is, if any
  Vertex seed{};    ///< an original vertex of its triangle: where its search starts
};

// Area (in each face's fan triangulation from its first corner) of the triangles of
// face(h) that have h's origin as a corner; degenerate ones count nothing.
double corner_area(const SurfaceMesh& mesh, Halfedge h) {
  const Halfedge h0 = mesh.halfedge(mesh.face(h));
  const Vertex v = mesh.from_vertex(h);
  const Point& a = mesh.position(mesh.to_vertex(h0));
  const bool at_a = mesh.to_vertex(h0) == v;
  double sum = 0;
  for (Halfedge k = mesh.next(h0); mesh.next(k) != h0; k = mesh.next(k)) {
    const Vertex b = mesh.to_vertex(k), c = mesh.to_vertex(mesh.next(k));
    if (!at_a && b != v && c != v) continue;
    const double area = 0.5 * (mesh.position(b) - a).cross(mesh.position(c) - a).norm();
    if (area > 0) sum += area;
  }
  return sum;
}

// A third of the area of each vertex's triangles, gathered around each vertex so that the
// vertices are independent (on all cores).
std::vector<double> vertex_areas(const SurfaceMesh& mesh) {
  std::vector<double> area(mesh.vertices_size(), 0.0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.vertices_size(), 4096),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i < range.end(); ++i) {
                        const Vertex v(static_cast<std::uint32_t>(i));
                        if (mesh.is_deleted(v) || mesh.is_isolated(v)) continue;
                        double sum = 0;
                        for (Halfedge h : mesh.outgoing(v))
                          if (!mesh.is_boundary(h)) sum += corner_area(mesh, h);
                        area[i] = sum / 3;
                      }
                    });
  return area;
}

// Fill out with count(b, e) items per block [b, e) of [0, n), each block writing its own
// range through fill(b, e, first): blocks count, then fill, on all cores, in serial order.
template <class T, class Count, class Fill>
void fill_by_blocks(std::vector<T>& out, std::size_t n, std::size_t block, Count count, Fill fill) {
  const std::size_t blocks = (n + block - 1) / block;
  std::vector<std::size_t> start(blocks + 1, 0);
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
    start[b + 1] = count(b * block, std::min(n, (b + 1) * block));
  });
  for (std::size_t b = 0; b < blocks; ++b) start[b + 1] += start[b];
  const std::size_t base = out.size();
  out.resize(base + start[blocks]);
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
    fill(b * block, std::min(n, (b + 1) * block), out.data() + base + start[b]);
  });
}

// The original surface as weighted points: every vertex carries a third of its triangles'
// area, and optional interior points share each triangle's area once more. Polygons are
// fan-triangulated, as everywhere else. Interior points come first, in face order, then the
// vertices in index order.
std::vector<Sample> sample_original(const SurfaceMesh& mesh, int per_triangle,
                                    std::span<const double> given_area) {
  std::vector<Sample> out;
  if (per_triangle > 0) {
    // Calls f(a, b, c, area) for each non-degenerate fan triangle of the faces [begin, end).
    const auto triangles = [&](std::size_t begin, std::size_t end, auto&& f) {
      for (std::size_t i = begin; i < end; ++i) {
        const Face face(static_cast<std::uint32_t>(i));
        if (mesh.is_deleted(face)) continue;
        const Halfedge h0 = mesh.halfedge(face);
        const Vertex a = mesh.to_vertex(h0);
        for (Halfedge k = mesh.next(h0); mesh.next(k) != h0; k = mesh.next(k)) {
          const Point &pa = mesh.position(a), &pb = mesh.position(mesh.to_vertex(k)),
                      &pc = mesh.position(mesh.to_vertex(mesh.next(k)));
          const double area = 0.5 * (pb - pa).cross(pc - pa).norm();
          if (area > 0) f(a, pa, pb, pc, area);
        }
      }
    };
    fill_by_blocks(
        out, mesh.faces_size(), 4096,
        [&](std::size_t begin, std::size_t end) {
          std::size_t n = 0;
          triangles(begin, end, [&](Vertex, const Point&, const Point&, const Point&, double) { n += per_triangle; });
          return n;
        },
        [&](std::size_t begin, std::size_t end, Sample* o) {
          triangles(begin, end, [&](Vertex a, const Point& pa, const Point& pb, const Point& pc, double area) {
            // A fixed R2 (Roberts) sequence folded into the triangle: evenly spread, deterministic.
            for (int s = 0; s < per_triangle; ++s) {
              double u = std::fmod(0.5 + 0.7548776662 * (s + 1), 1.0);
              double t = std::fmod(0.5 + 0.5698402910 * (s + 1), 1.0);
              if (u + t > 1) u = 1 - u, t = 1 - t;
              *o++ = {pa + u * (pb - pa) + t * (pc - pa), area / per_triangle, Vertex(), a};
            }
          });
        });
  }
  std::vector<double> own_area;
  if (given_area.empty()) own_area = vertex_areas(mesh), given_area = own_area;
  const std::span<const double> area = given_area;
  fill_by_blocks(
      out, mesh.vertices_size(), 16384,
      [&](std::size_t begin, std::size_t end) {
        return static_cast<std::size_t>(
            std::count_if(area.begin() + begin, area.begin() + end, [](double a) { return a > 0; }));
      },
      [&](std::size_t begin, std::size_t end, Sample* o) {
        for (std::size_t i = begin; i < end; ++i) {
          const Vertex v(static_cast<std::uint32_t>(i));
          if (area[i] > 0) *o++ = {mesh.position(v), area[i], v, v};
        }
      });
  return out;
}

// Barycentric coordinates of q (on or near triangle a, b, c); a degenerate triangle gives
// its first corner everything, which only weakens that sample's pull.
std::array<double, 3> barycentric(const Point& q, const Point& a, const Point& b, const Point& c) {
  const Vector3 e0 = b - a, e1 = c - a, d = q - a;
  const double d00 = e0.dot(e0), d01 = e0.dot(e1), d11 = e1.dot(e1);
  const double d20 = d.dot(e0), d21 = d.dot(e1);
  const double den = d00 * d11 - d01 * d01;
  if (!(den > 1e-300)) return {1, 0, 0};
  const double v = std::clamp((d11 * d20 - d01 * d21) / den, 0.0, 1.0);
  const double w = std::clamp((d00 * d21 - d01 * d20) / den, 0.0, 1.0 - v);
  return {1 - v - w, v, w};
}

double quality(const Point& a, const Point& b, const Point& c) {
  const double l = (b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm();
  return l > 0 ? 2 * std::sqrt(3.0) * (b - a).cross(c - a).norm() / l : 0;
}

// A sample's closest simplified triangle (index into Refitter::tri_), point and barycentrics.
struct Hit {
  std::uint32_t t;
  Point q;
  std::array<double, 3> beta;
};

// One sample's pull on one corner of its closest simplified triangle.
struct Pull {
  std::uint32_t sample;
  double beta;
  const Vector3& n;
};

constexpr std::uint32_t kNoTriangle = 0xffffffffu;

// What the move of one vertex works with (one per thread).
struct Scratch {
  struct Residual {
    double r, beta;  // the pull's residual at v's current position, and its weight on v
    const Vector3* n;
  };
  std::vector<Residual> residual;  // of v's pulls (copied: the guard reads them per try)
  // v's pulls that are original vertices: where they are, and which (apart: probe() scans
  // the positions once per probe).
  std::vector<Point> vertex_points;
  std::vector<Vertex> vertex_ids;
  struct Probe {
    Point other;  // the neighbour whose edge midpoint it is (unused for v itself)
    Vertex near;  // original vertex whose fan measures it
    double near_d2, before;  // before < 0: not measured yet
    std::uint32_t fan, fan_end;  // near's fan in fan_points (empty: not copied yet)
    std::uint32_t closest;       // its triangle nearest to the probe before the move
  };
  std::vector<Point> fan_points;  // near, then (b, c) per triangle, for each probe
  std::vector<Probe> probes;  // of the vertex being moved, probed (still at its old place)
  Vertex probed;
};

class Refitter {
 public:
  Refitter(SurfaceMesh& mesh, const SurfaceMesh& original, const RefitOptions& options,
           std::span<const Vertex> fixed, std::span<const Vertex> survivor,
           std::span<const detail::RefitLine> lines)
      : mesh_(mesh), original_(original), options_(options), survivor_(survivor),
        free_(mesh.vertices_size(), kFree) {
    if (!lines.empty()) line_.assign(free_.size(), Vector3::Zero());
    for (const detail::RefitLine& l : lines) {
      if (l.vertex.idx() >= free_.size()) continue;
      // Without a direction (a degenerate fan's zero normal) the vertex stays.
      const bool valid = l.direction.allFinite() && l.direction.squaredNorm() > 0;
      free_[l.vertex.idx()] = valid ? kOnLine : 0;
      if (valid) line_[l.vertex.idx()] = l.direction.normalized();
    }
    for (Vertex v : fixed)
      if (v.idx() < free_.size()) free_[v.idx()] = 0;
    // Boundary vertices stay: the simplifier promised to keep boundaries where they are.
    for (Vertex v : mesh.vertices())
      if (mesh.is_isolated(v) || mesh.is_boundary(v)) free_[v.idx()] = 0;
    // Flat triangles (polygons fanned) and each vertex's triangles: the walk reads them often.
    const std::size_t nv = mesh.vertices_size();
    fan_start_.assign(nv + 1, 0);
    tri_.reserve(mesh.n_faces());
    for (Face f : mesh.faces()) {
      const Halfedge h0 = mesh.halfedge(f);
      for (Halfedge h = mesh.next(h0); mesh.next(h) != h0; h = mesh.next(h))
        tri_.push_back({mesh.from_vertex(h0).idx(), mesh.from_vertex(h).idx(), mesh.to_vertex(h).idx()});
    }
    for (const auto& t : tri_)
      for (std::uint32_t v : t) ++fan_start_[v + 1];
    for (std::size_t v = 0; v < nv; ++v) fan_start_[v + 1] += fan_start_[v];
    fan_.resize(fan_start_[nv]);
    std::vector<std::uint32_t> fill(fan_start_.begin(), fan_start_.end() - 1);
    for (std::uint32_t t = 0; t < tri_.size(); ++t)
      for (std::uint32_t v : tri_[t]) fan_[fill[v]++] = t;
    plan_blocks();
  }

  void iterate(const std::vector<Sample>& samples) {
    assign(samples);
    // Even blocks, then odd ones: blocks of one parity share no edge (plan_blocks()).
    for (std::size_t parity = 0; parity < 2; ++parity)
      tbb::parallel_for(std::size_t{0}, (block_start_.size() - parity) / 2, [&](std::size_t k) {
        Scratch scratch;
        const std::size_t b = 2 * k + parity;
        for (std::uint32_t i = block_start_[b]; i < block_start_[b + 1]; ++i)
          move(Vertex(inner_[i]), samples, scratch);
      });
    Scratch scratch;
    for (std::uint32_t v : seam_) move(Vertex(v), samples, scratch);
  }

 private:
  // Blocks of consecutive vertices move in parallel, each in index order: first the
  // even-numbered blocks, then the odd ones, so that neighbouring blocks never move at once.
  // A vertex with a free neighbour in a block further away (the seam) waits for a serial pass
  // after them. The result does not depend on the schedule, and each block keeps the serial
  // order's locality (colour classes, which sweep the whole mesh once per colour, made the
  // moves 65% slower on one core). It pays when the input's vertex order is spatially
  // coherent, as the simplifier's output keeps it (torus 1M at 10%: 387 seam vertices of 50k,
  // against 5008 when a neighbour in any other block counted). Where it is not (amo.ply's
  // order is random: most of it was seam, and its moves ran serially), the blocks are cut
  // from the vertices sorted along a Morton curve instead, and the moves go in that order.
  void plan_blocks() {
    const std::size_t nv = mesh_.vertices_size();
    std::vector<std::uint32_t> order(nv);
    for (std::uint32_t v = 0; v < nv; ++v) order[v] = v;
    const std::size_t free = plan_blocks_in(order);
    if (seam_.size() * 4 > free) plan_blocks_in(morton_order());
  }

  // Plan the blocks over the vertices in this order (all of them, each once); returns the
  // number of free vertices.
  std::size_t plan_blocks_in(const std::vector<std::uint32_t>& order) {
    // About eight blocks, 512 to 8192 vertices each: larger ones leave fewer seam vertices.
    const std::size_t nv = order.size();
    const int kBlockBits = std::clamp(static_cast<int>(std::bit_width(nv / 8)) - 1, 9, 13);
    std::vector<std::uint32_t> block(nv);
    for (std::size_t i = 0; i < nv; ++i) block[order[i]] = static_cast<std::uint32_t>(i >> kBlockBits);
    block_start_.assign((nv >> kBlockBits) + 2, 0);
    inner_.clear();
    seam_.clear();
    std::size_t free = 0;
    for (std::uint32_t v : order) {
      if (!free_[v]) continue;
      ++free;
      const std::uint32_t b = block[v];
      bool seam = false;
      for (Vertex u : mesh_.vertices(Vertex(v))) {
        const std::uint32_t c = block[u.idx()];
        seam = seam || (free_[u.idx()] && c + 1 != b && c != b && c != b + 1);
      }
      if (seam) {
        seam_.push_back(v);
      } else {
        inner_.push_back(v);
        ++block_start_[b + 1];
      }
    }
    for (std::size_t b = 0; b + 1 < block_start_.size(); ++b)
      block_start_[b + 1] += block_start_[b];
    return free;
  }

  // The vertices along a Morton (Z-order) curve through the bounding box, 10 bits an axis;
  // ties by index, so the order is the same on any machine.
  std::vector<std::uint32_t> morton_order() const {
    const std::size_t nv = mesh_.vertices_size();
    Eigen::AlignedBox3d box;
    for (std::size_t v = 0; v < nv; ++v) box.extend(mesh_.position(Vertex(v)));
    const Vector3 size = box.sizes().cwiseMax(1e-300);
    const auto spread = [](std::uint64_t x) {  // 10 bits to every third of 30
      x = (x | x << 16) & 0x030000FFull;
      x = (x | x << 8) & 0x0300F00Full;
      x = (x | x << 4) & 0x030C30C3ull;
      return (x | x << 2) & 0x09249249ull;
    };
    std::vector<std::uint64_t> key(nv);
    for (std::size_t v = 0; v < nv; ++v) {
      std::uint64_t code = 0;
      for (int i = 0; i < 3; ++i) {
        const double t = (mesh_.position(Vertex(v))[i] - box.min()[i]) / size[i];
        const auto q = static_cast<std::uint64_t>((t > 0 ? std::min(t, 1.0) : 0.0) * 1023.0);  // NaN: 0
        code |= spread(q) << i;
      }
      key[v] = code << 32 | v;
    }
    std::sort(key.begin(), key.end());
    std::vector<std::uint32_t> order(nv);
    for (std::size_t i = 0; i < nv; ++i) order[i] = static_cast<std::uint32_t>(key[i]);
    return order;
  }

  // Each sample pulls on the three corners of its closest simplified triangle (CSR by vertex).
  void assign(const std::vector<Sample>& samples) {
    const std::size_t nv = mesh_.vertices_size();
    // Normals at the current positions; a degenerate triangle's (zero) drops its samples.
    normal_.resize(tri_.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tri_.size(), 16384),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t t = range.begin(); t < range.end(); ++t) {
                          const auto [a, b, c] = corners(t);
                          const Vector3 n = (b - a).cross(c - a);
                          const double len = n.norm();
                          normal_[t] = len > 0 ? Vector3(n / len) : Vector3::Zero();
                        }
                      });
    sample_tri_.assign(samples.size(), kNoTriangle);
    sample_beta_.resize(samples.size());
    // Walks are independent of each other, and a sample's answer does not depend on which
    // came before (in_fan()): they go by start vertex, so that each fan is prepared about once.
    const std::vector<std::uint32_t> visit = by_start(samples);
    constexpr std::uint32_t kAskTree = kNoTriangle - 1;
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, samples.size(), 4096),
        [&](const tbb::blocked_range<std::size_t>& range) {
          PreparedFan fan;
          for (std::size_t k = range.begin(); k < range.end(); ++k) {
            const std::uint32_t i = visit[k];
            Hit hit;
            if (!in_fan(samples[i], fan, hit) && !walk(samples[i], hit)) {
              sample_tri_[i] = kAskTree;
            } else if (!normal_[hit.t].isZero()) {
              sample_tri_[i] = hit.t;
              sample_beta_[i] = hit.beta;
            }
          }
        });
    std::unique_ptr<TriangleBvh> bvh;  // only for samples the walk could not place
    start_.assign(nv + 1, 0);
    for (std::size_t i = 0; i < samples.size(); ++i) {
      if (sample_tri_[i] == kAskTree) {
        sample_tri_[i] = kNoTriangle;
        if (!bvh) {
          std::vector<Point> pos(nv);
          for (std::size_t v = 0; v < nv; ++v) pos[v] = mesh_.position(Vertex(v));
          bvh = std::make_unique<TriangleBvh>(std::move(pos), tri_);
        }
        const ClosestPoint cp = bvh->closest_point(samples[i].p);
        if (!cp.found() || normal_[cp.triangle].isZero()) continue;
        const auto [a, b, c] = corners(cp.triangle);
        sample_tri_[i] = cp.triangle;
        sample_beta_[i] = barycentric(cp.point, a, b, c);
      }
      if (sample_tri_[i] != kNoTriangle)
        for (std::uint32_t k : tri_[sample_tri_[i]]) ++start_[k + 1];
    }
    for (std::size_t v = 0; v < nv; ++v) start_[v + 1] += start_[v];
    pulls_.resize(start_[nv]);
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    // 4 bytes a pull (sample, corner): at 1.5M samples a fat record was 180 MB to write.
    for (std::uint32_t i = 0; i < samples.size(); ++i) {
      if (sample_tri_[i] == kNoTriangle) continue;
      for (std::uint32_t k = 0; k < 3; ++k) pulls_[fill[tri_[sample_tri_[i]][k]]++] = i << 2 | k;
    }
  }

  // The samples' indices grouped by the output vertex their walk starts from (a counting
  // sort, in index order within a group; those without one last). In the input's order,
  // consecutive samples of a scan in random vertex order rarely share a start: amo.ply at 10%
  // prepared 82.6k fans for 90k samples.
  std::vector<std::uint32_t> by_start(const std::vector<Sample>& samples) const {
    const std::size_t nv = fan_start_.size() - 1;
    const auto start = [&](const Sample& s) -> std::size_t {
      if (!s.seed.is_valid() || s.seed.idx() >= survivor_.size()) return nv;
      const Vertex v = survivor_[s.seed.idx()];
      return v.is_valid() && v.idx() < nv ? v.idx() : nv;
    };
    std::vector<std::uint32_t> first(nv + 2, 0), visit(samples.size());
    for (const Sample& s : samples) ++first[start(s) + 1];
    for (std::size_t v = 0; v <= nv; ++v) first[v + 1] += first[v];
    for (std::uint32_t i = 0; i < samples.size(); ++i) visit[first[start(samples[i])]++] = i;
    return visit;
  }

  Pull pull(std::uint32_t k) const {
    const std::uint32_t s = pulls_[k] >> 2;
    return {s, sample_beta_[s][pulls_[k] & 3], normal_[sample_tri_[s]]};
  }

  std::array<Point, 3> corners(std::size_t t) const {
    return {mesh_.position(Vertex(tri_[t][0])), mesh_.position(Vertex(tri_[t][1])),
            mesh_.position(Vertex(tri_[t][2]))};
  }

  // One vertex's triangles, ready for many closest-point queries: the projection onto a
  // triangle's plane, in barycentric coordinates, costs a few dot products once each
  // triangle's edges and their Gram matrix are at hand.
  struct FanTriangle {
    Point a;
    Vector3 e0, e1, n;
    Vector3 to_v, to_w;  // (p − a)·to_v, (p − a)·to_w: p's barycentric coordinates at b, c
    bool thin;  // too thin for the projection formulas: always measured in full
    std::array<double, 3> height2;  // squared height over the side opposite each corner
    std::uint32_t t;
  };
  struct PreparedFan {
    std::uint32_t vertex = kNoTriangle;
    std::uint32_t last = 0;  // the triangle of the latest sample placed in it
    std::vector<FanTriangle> triangles;
    std::vector<std::pair<double, std::uint32_t>> outside;  // scratch of in_fan()
  };

  void prepare(std::uint32_t v, PreparedFan& fan) const {
    fan.vertex = v;
    fan.last = 0;
    fan.triangles.clear();
    for (std::uint32_t k = fan_start_[v]; k < fan_start_[v + 1]; ++k) {
      const auto [a, b, c] = corners(fan_[k]);
      const Vector3 e0 = b - a, e1 = c - a;
      const double d00 = e0.dot(e0), d01 = e0.dot(e1), d11 = e1.dot(e1);
      const double den = d00 * d11 - d01 * d01;  // (twice the area)²
      // The Gram system of the projection, solved once for the triangle.
      const Vector3 to_v = (d11 * e0 - d01 * e1) / den, to_w = (d00 * e1 - d01 * e0) / den;
      const bool thin = !(den > 1e-12 * d00 * d11) || normal_[fan_[k]].isZero();
      fan.triangles.push_back({a, e0, e1, normal_[fan_[k]], to_v, to_w, thin,
                               {den / (c - b).squaredNorm(), den / d11, den / d00}, fan_[k]});
    }
  }

  // The walk's first step, for the common case: the sample's closest triangle is one of its
  // start vertex's, at a point with weight on that vertex. Consecutive samples often start
  // at the same vertex (the input's order is spatially coherent), so its fan is prepared
  // once for them. A triangle is measured in full only when a lower bound of its distance
  // does not rule it out: the distance to its plane, and beyond a side, the distance to
  // that side's line within the plane (a sample projects into one or two of its fan's
  // triangles, whose plane distance is then exact). False: the walk must go on from there
  // (or has nowhere to start).
  bool in_fan(const Sample& s, PreparedFan& fan, Hit& hit) const {
    if (!s.seed.is_valid() || s.seed.idx() >= survivor_.size()) return false;
    const Vertex start = survivor_[s.seed.idx()];
    if (!start.is_valid() || start.idx() + 1 >= fan_start_.size()) return false;
    if (fan.vertex != start.idx()) prepare(start.idx(), fan);
    const std::uint32_t m = static_cast<std::uint32_t>(fan.triangles.size());
    if (m == 0) return false;
    // The previous sample's triangle first, as a guess at the nearest: its distance then
    // rules most of the others out by their planes. It is only a guess (every triangle is
    // still measured or ruled out; stopping at it was wrong across creases, see walk()), and
    // ties go to the earlier triangle in the fan, as in walk(), so the answer does not depend
    // on which sample came before.
    double best = std::numeric_limits<double>::infinity();
    std::uint32_t best_i = m;
    const auto take = [&](double d2, std::uint32_t i, const Point& q) {
      if (d2 < best || (d2 == best && i < best_i)) best = d2, best_i = i, hit.q = q;
    };
    fan.outside.clear();
    for (std::uint32_t j = 0; j < m; ++j) {
      const std::uint32_t i = j == 0 ? fan.last : j <= fan.last ? j - 1 : j;
      const FanTriangle& f = fan.triangles[i];
      const Vector3 d = s.p - f.a;
      const double h = f.n.dot(d);
      // The plane's distance never exceeds the triangle's (margin: see walk()).
      if (h * h > best * (1 + 1e-6)) continue;
      const double v = d.dot(f.to_v), w = d.dot(f.to_w);
      const std::array<double, 3> lambda{1 - v - w, v, w};
      if (f.thin) {
        fan.outside.push_back({h * h, i});
      } else if (lambda[0] >= 0 && v >= 0 && w >= 0) {
        const Point q = s.p - h * f.n;  // projects inside: the plane's point is the closest
        take((q - s.p).squaredNorm(), i, q);
      } else {
        double off2 = 0;
        for (int k = 0; k < 3; ++k)
          if (lambda[k] < 0) off2 = std::max(off2, lambda[k] * lambda[k] * f.height2[k]);
        fan.outside.push_back({h * h + off2, i});
      }
    }
    for (const auto& [bound2, i] : fan.outside) {
      if (bound2 > best * (1 + 1e-6)) continue;
      const FanTriangle& f = fan.triangles[i];
      const Point q = closest_point_on_triangle(s.p, f.a, f.a + f.e0, f.a + f.e1);
      take((q - s.p).squaredNorm(), i, q);
    }
    if (best_i == m) return false;
    fan.last = best_i;
    hit.t = fan.triangles[best_i].t;
    const auto [a, b, c] = corners(hit.t);
    hit.beta = barycentric(hit.q, a, b, c);
    for (int k = 0; k < 3; ++k)
      if (tri_[hit.t][k] == start.idx()) return hit.beta[k] > 1e-9;
    return false;
  }

  // The sample's closest triangle, searched from the fan of the output vertex its seed was
  // collapsed into (it nearly always holds it, or a neighbour does) rather than in a tree over
  // the whole output: a query then costs a few triangles, not a descent. While the closest
  // point found lies where no visited vertex has weight (on the far side of the visited
  // fans), a closer triangle may lie beyond, so that triangle's other corners are visited
  // too. Like any local search it may settle on a near-closest triangle across a thin gap;
  // this is a fit, and the Hausdorff guard judges every move. False: no seed, or the walk
  // wandered too far (the caller asks the tree). (Taking the previous sample's triangle when
  // the closest point is inside it saves a quarter of the walks' time but is wrong across
  // concave creases: fandisk's error grew 2700-fold.)
  bool walk(const Sample& s, Hit& hit) const {
    if (!s.seed.is_valid() || s.seed.idx() >= survivor_.size()) return false;
    const Vertex start = survivor_[s.seed.idx()];
    if (!start.is_valid() || start.idx() + 1 >= fan_start_.size()) return false;
    constexpr int kMaxVisit = 16;
    std::array<std::uint32_t, kMaxVisit> visited;
    int n = 0, scanned = 0;
    visited[n++] = start.idx();
    const auto was_visited = [&](std::uint32_t v) {
      return std::find(visited.begin(), visited.begin() + n, v) != visited.begin() + n;
    };
    // A triangle with a corner whose fan was scanned already has been measured.
    const auto measured = [&](const std::array<std::uint32_t, 3>& t) {
      return std::find_first_of(visited.begin(), visited.begin() + scanned, t.begin(), t.end()) !=
             visited.begin() + scanned;
    };
    double best = std::numeric_limits<double>::infinity();
    for (;;) {
      for (; scanned < n; ++scanned)
        for (std::uint32_t k = fan_start_[visited[scanned]]; k < fan_start_[visited[scanned] + 1]; ++k) {
          if (measured(tri_[fan_[k]])) continue;
          const auto [a, b, c] = corners(fan_[k]);
          // The plane's distance never exceeds the triangle's: a far plane rules it out at
          // the cost of a dot product (the margin keeps rounding from deciding a near tie).
          const double h = normal_[fan_[k]].dot(s.p - a);
          if (h * h > best * (1 + 1e-6)) continue;
          const Point q = closest_point_on_triangle(s.p, a, b, c);
          const double d2 = (q - s.p).squaredNorm();
          if (d2 < best) best = d2, hit.t = fan_[k], hit.q = q;
        }
      if (!(best < std::numeric_limits<double>::infinity())) return false;
      const auto [a, b, c] = corners(hit.t);
      hit.beta = barycentric(hit.q, a, b, c);
      bool inside = false;
      for (int k = 0; k < 3; ++k) inside = inside || (hit.beta[k] > 1e-9 && was_visited(tri_[hit.t][k]));
      if (inside) return true;
      const int before = n;
      for (std::uint32_t v : tri_[hit.t])
        if (!was_visited(v)) {
          if (n == kMaxVisit) return false;
          visited[n++] = v;
        }
      // Nothing new to scan (barycentrics NaN from coordinates near the double range's end
      // made no corner count as inside): looping on would never end; the tree decides.
      if (n == before) return false;
    }
  }

  static constexpr std::size_t kPrefetch = 8;  // pulls

  // Gauss–Seidel step for v: minimise Σ w (n·(Σ β_j x_j − p))² + λ|x_v − x|² over x_v.
  void move(Vertex v, const std::vector<Sample>& samples, Scratch& w) {
    double a00 = 0, a10 = 0, a11 = 0, a20 = 0, a21 = 0, a22 = 0;
    Vector3 g = Vector3::Zero();
    w.residual.clear();
    w.vertex_points.clear();
    w.vertex_ids.clear();
    double weight = 0;
    for (std::uint32_t k = start_[v.idx()]; k < start_[v.idx() + 1]; ++k) {
      // A vertex's pulls name samples all over the arrays: fetching a few pulls ahead (into
      // the next vertex's, which comes next in a block) overlaps their cache misses.
      if (k + 2 * kPrefetch < pulls_.size()) {
        const std::uint32_t ahead = pulls_[k + 2 * kPrefetch] >> 2;
        __builtin_prefetch(&samples[ahead]);
        __builtin_prefetch(&sample_beta_[ahead]);
        __builtin_prefetch(&sample_tri_[ahead]);
        // Half way there, the sample's triangle is known: fetch its normal.
        const std::uint32_t t = sample_tri_[pulls_[k + kPrefetch] >> 2];
        if (t != kNoTriangle) __builtin_prefetch(&normal_[t]);
      }
      const Pull pull = this->pull(k);
      const Sample& s = samples[pull.sample];
      const auto& t = tri_[sample_tri_[pull.sample]];
      const auto& b = sample_beta_[pull.sample];
      Point on = Point::Zero();
      for (int j = 0; j < 3; ++j) on += b[j] * mesh_.position(Vertex(t[j]));
      const double r = pull.n.dot(on - s.p);
      w.residual.push_back({r, pull.beta, &pull.n});
      if (s.vertex.is_valid()) w.vertex_points.push_back(s.p), w.vertex_ids.push_back(s.vertex);
      const double wb = s.w * pull.beta;
      // Six sums in registers (the lower triangle, mirrored below: LDLT reads no more) rather
      // than a 3×3 on the stack, whose read-modify-write chain through memory held the loop
      // up; each term is the one Eigen's outer product formed, so A is the same.
      const Vector3 cn = (wb * pull.beta) * pull.n;
      a00 += cn[0] * pull.n[0], a10 += cn[1] * pull.n[0], a11 += cn[1] * pull.n[1];
      a20 += cn[2] * pull.n[0], a21 += cn[2] * pull.n[1], a22 += cn[2] * pull.n[2];
      g += wb * r * pull.n;
      weight += wb * pull.beta;
    }
    Eigen::Matrix3d A;
    A << a00, a10, a20, a10, a11, a21, a20, a21, a22;
    if (!(weight > 0)) return;
    A.diagonal().array() += options_.regularization * weight;
    Vector3 delta = free_[v.idx()] == kOnLine ? on_line(line_[v.idx()], A, g) : Vector3(-A.ldlt().solve(g));
    if (!delta.allFinite()) return;
    // Halve a move that would fold or crush a fan triangle or raise the local Hausdorff
    // distance; give up after a few tries.
    const Point old = mesh_.position(v);
    bool probed = false;
    for (int tries = 0; tries < 3; ++tries, delta *= 0.5) {
      if (!fan_ok(v, old, old + delta)) continue;
      if (!probed) probe(w, v), probed = true;
      if (hausdorff_ok(w, v, delta)) {
        mesh_.position(v) = old + delta;
        return;
      }
    }
  }

  // The minimiser of move()'s quadratic (A, g) on the line through the vertex along unit d.
  static Vector3 on_line(const Vector3& d, const Eigen::Matrix3d& A, const Vector3& g) {
    // > 0 with the regulariser; without it a zero gives a non-finite move, which move() drops.
    const double curvature = d.dot(A * d);
    return -(d.dot(g) / curvature) * d;
  }

  // Distance from x to the original fan of probe i's original vertex: an upper bound on x's
  // distance to the original surface, exact when the closest point lies in that fan. The
  // fan's corners are copied once per probe (a halved move measures it again); `closest`
  // receives the triangle (index of its b in w.fan_points; p.fan: the vertex) nearest to x.
  double fan_distance(Scratch& w, std::size_t i, const Point& x,
                      std::uint32_t* closest = nullptr) const {
    Scratch::Probe& p = w.probes[i];
    if (p.fan == p.fan_end) {
      p.fan = static_cast<std::uint32_t>(w.fan_points.size());
      w.fan_points.push_back(original_.position(p.near));
      for (Halfedge h : original_.outgoing(p.near)) {
        if (original_.is_boundary(h)) continue;
        w.fan_points.push_back(original_.position(original_.to_vertex(h)));
        w.fan_points.push_back(original_.position(original_.to_vertex(original_.next(h))));
      }
      p.fan_end = static_cast<std::uint32_t>(w.fan_points.size());
    }
    double d2 = (w.fan_points[p.fan] - x).squaredNorm();
    if (closest) *closest = p.fan;
    for (std::uint32_t k = p.fan + 1; k < p.fan_end; k += 2) {
      const double dk = triangle_distance2(w, p.fan, k, x);
      if (dk < d2) {
        d2 = dk;
        if (closest) *closest = k;
      }
    }
    return std::sqrt(d2);
  }

  // Squared distance from x to w.fan_points' triangle (a, k, k + 1), or to a alone (k == a).
  static double triangle_distance2(const Scratch& w, std::uint32_t a, std::uint32_t k,
                                   const Point& x) {
    if (k == a) return (w.fan_points[a] - x).squaredNorm();
    return (closest_point_on_triangle(x, w.fan_points[a], w.fan_points[k], w.fan_points[k + 1]) - x)
        .squaredNorm();
  }

  // Where the guard watches v's surroundings: v itself (probe 0) and the midpoint of each
  // edge of v (where the simplified→original distance peaks, unseen by the samples), each
  // measured on the original fan of the original vertex nearest to it among v's samples.
  // That vertex is chosen once, before the move, so before and after compare the same bound
  // and the tries of a halved move cost one fan each, not a search over the samples.
  void probe(Scratch& w, Vertex v) const {
    const Point& x = mesh_.position(v);
    w.probes.clear();
    constexpr double kInf = std::numeric_limits<double>::infinity();
    w.probed = v;
    w.fan_points.clear();
    w.probes.push_back({x, Vertex(), kInf, -1, 0, 0, 0});
    for (Vertex u : mesh_.vertices(v))
      w.probes.push_back({mesh_.position(u), Vertex(), kInf, -1, 0, 0, 0});
    for (std::size_t i = 0; i < w.probes.size(); ++i) {
      const Point m = midpoint(w, i, x);
      double best = kInf;
      std::size_t at = 0;
      for (std::size_t j = 0; j < w.vertex_points.size(); ++j) {
        const double d2 = (w.vertex_points[j] - m).squaredNorm();
        if (d2 < best) best = d2, at = j;
      }
      if (best < kInf) w.probes[i].near_d2 = best, w.probes[i].near = w.vertex_ids[at];
    }
  }

  // Probe i's distance before the move, measured on first need: a probe whose nearest original
  // vertex already clears the bound, or a move the samples refuse, needs no fan.
  double before(Scratch& w, std::size_t i) const {
    Scratch::Probe& p = w.probes[i];
    if (p.before < 0)
      p.before = fan_distance(w, i, midpoint(w, i, mesh_.position(w.probed)), &p.closest);
    return p.before;
  }

  // Probe i's point with v at x: v itself, or the midpoint of v's edge to a neighbour.
  static Point midpoint(const Scratch& w, std::size_t i, const Point& x) {
    return i == 0 ? x : Point(0.5 * (x + w.probes[i].other));
  }

  // Least squares trades the worst point for the typical one, and Hausdorff is the worst. The
  // largest residual of v's samples bounds the local error; after the move it may not exceed
  // that bound or v's own distance to the original, and v and its edges' midpoints may each
  // end no further from the original than they were or than that bound. Each point is held
  // to its own bound: one loose estimate must not license growth elsewhere. Without this
  // guard the fit lowered RMS but raised Hausdorff at 50%.
  bool hausdorff_ok(Scratch& w, Vertex v, const Vector3& delta) const {
    double bound = 0, after = 0;
    for (const Scratch::Residual& r : w.residual) {
      bound = std::max(bound, std::abs(r.r));
      after = std::max(after, std::abs(r.r + r.beta * r.n->dot(delta)));
    }
    // v's distance before the move is at most that to its nearest original vertex: beyond
    // that, its fan need not be measured to refuse the move.
    const bool has_v = w.probes[0].near.is_valid();
    if (after > bound &&
        (!has_v || after > std::sqrt(w.probes[0].near_d2) || after > before(w, 0)))
      return false;
    const Point moved = mesh_.position(v) + delta;
    for (std::size_t p = 0; p < w.probes.size(); ++p) {
      if (!w.probes[p].near.is_valid()) continue;
      // A distance moves no more than its point (v by delta, a midpoint by half of it), and
      // the distance to the nearest original vertex bounds it from above: when that clears
      // the bound, the point's fan need not be measured at all.
      const double step = (p == 0 ? 1.0 : 0.5) * delta.norm();
      if (std::sqrt(w.probes[p].near_d2) + step <= bound) continue;
      const double allowed = std::max(bound, before(w, p));
      if (before(w, p) + step <= allowed) continue;
      // The fan triangle closest before the move usually still clears the bound after it,
      // sparing the rest of the fan: any one triangle's distance bounds the fan's.
      const Point x = midpoint(w, p, moved);
      if (std::sqrt(triangle_distance2(w, w.probes[p].fan, w.probes[p].closest, x)) <= allowed)
        continue;
      if (fan_distance(w, p, x) > allowed) return false;
    }
    return true;
  }

  bool fan_ok(Vertex v, const Point& from, const Point& to) const {
    for (Halfedge h : mesh_.outgoing(v)) {
      if (mesh_.is_boundary(h)) continue;
      const Point& b = mesh_.position(mesh_.to_vertex(h));
      const Point& c = mesh_.position(mesh_.to_vertex(mesh_.next(h)));
      const Vector3 n0 = (b - from).cross(c - from), n1 = (b - to).cross(c - to);
      if (!(n0.dot(n1) > 0)) return false;
      const double q1 = quality(to, b, c);
      if (q1 < options_.min_triangle_quality && q1 < quality(from, b, c)) return false;
    }
    return true;
  }

  SurfaceMesh& mesh_;
  const SurfaceMesh& original_;
  const RefitOptions& options_;
  std::span<const Vertex> survivor_;
  // Per vertex: 0 (stays), kFree or kOnLine (moves along line_[v] only).
  static constexpr std::uint8_t kFree = 1, kOnLine = 2;
  std::vector<std::uint8_t> free_;
  std::vector<Vector3> line_;  // empty without lines
  std::vector<std::array<std::uint32_t, 3>> tri_;
  std::vector<std::uint32_t> fan_start_, fan_;  // triangles of each vertex (CSR)
  std::vector<std::uint32_t> start_;
  std::vector<std::uint32_t> pulls_;  // sample << 2 | corner
  std::vector<std::uint32_t> block_start_, inner_;  // free vertices inside each block (CSR)
  std::vector<std::uint32_t> seam_;  // free vertices with a free neighbour two blocks away or more
  std::vector<Vector3> normal_;             // of tri_, at the start of the round
  std::vector<std::uint32_t> sample_tri_;   // each sample's triangle (kNoTriangle: none)
  std::vector<std::array<double, 3>> sample_beta_;
};

}  // namespace

void refit_to_surface(SurfaceMesh& simplified, const SurfaceMesh& original,
                      const RefitOptions& options, std::span<const Vertex> fixed,
                      std::span<const Vertex> survivor) {
  detail::refit_to_surface(simplified, original, options, fixed, survivor, {}, {});
}

void detail::refit_to_surface(SurfaceMesh& simplified, const SurfaceMesh& original,
                              const RefitOptions& options, std::span<const Vertex> fixed,
                              std::span<const Vertex> survivor,
                              std::span<const double> vertex_area,
                              std::span<const RefitLine> lines) {
  if (options.iterations <= 0 || simplified.n_faces() == 0) return;
  // Interior samples pay only where the output is dense: with fewer than two original vertices
  // per simplified triangle the vertices alone leave the fit loose (fandisk at 50%: RMS 1.011×
  // the best peer's without them, 0.994× with); below that they triple the walks and turn no
  // row of the error matrix (10% and 1%) from a win into a loss.
  int per_triangle = options.samples_per_triangle;
  if (per_triangle < 0)
    per_triangle = refit_needs_surface_samples(original.n_vertices(), simplified.n_faces());
  if (vertex_area.size() != original.vertices_size()) vertex_area = {};
  // The samples and the output's triangle lists do not depend on each other: the lists'
  // serial build runs beside the samples' parallel one.
  std::vector<Sample> samples;
  std::optional<Refitter> refitter;
  tbb::parallel_invoke(
      [&] { samples = sample_original(original, per_triangle, vertex_area); },
      [&] { refitter.emplace(simplified, original, options, fixed, survivor, lines); });
  // A pull packs its sample's index with the corner in 32 bits.
  if (samples.size() >= (std::size_t{1} << 30))
    throw InvalidArgument("refit: " + std::to_string(samples.size()) +
                          " surface samples; at most 2^30 (use fewer samples_per_triangle)");
  for (int it = 0; it < options.iterations; ++it) refitter->iterate(samples);
}

}  // namespace geom
