#include <geom/lod/collapse.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>
#include <unordered_set>

namespace geom::detail {

namespace {

std::uint64_t pair_key(Vertex a, Vertex b) {
  const std::uint64_t lo = std::min(a.idx(), b.idx()), hi = std::max(a.idx(), b.idx());
  return lo << 32 | hi;
}

double quality(const Point& a, const Point& b, const Point& c, double area2) {
  const double s = (b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm();
  // 4√3·A / Σl² with A = area2 / 2.
  return s > 0 ? 2.0 * std::sqrt(3.0) * area2 / s : 0.0;
}

// The first corner of a polygon whose fan diagonals are neither edges of the mesh nor
// diagonals of an earlier polygon: such a diagonal (two quads around a valence-2 vertex, say)
// would give that edge a third and fourth triangle. The first corner when none qualifies.
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
  return 0;
}

}  // namespace

CollapseEngine::CollapseEngine(const SurfaceMesh& mesh, const SimplifyOptions& options,
                               bool record)
    : options_(options), record_(record) {
  if (!(options.ratio >= 0.0 && options.ratio <= 1.0))
    throw InvalidArgument("simplify: ratio must be in [0, 1], got " + std::to_string(options.ratio));
  if (std::isnan(options.max_error) || options.max_error < 0)
    throw InvalidArgument("simplify: max_error must be >= 0, got " +
                          std::to_string(options.max_error));
  if (!(options.boundary_weight >= 0) || !std::isfinite(options.boundary_weight))
    throw InvalidArgument("simplify: boundary_weight must be finite and >= 0");

  // Dense numbering of the vertices that faces use.
  std::vector<std::uint32_t> dense(mesh.vertices_size(), kNone);
  for (Vertex v : mesh.vertices()) {
    if (mesh.is_isolated(v)) continue;
    dense[v.idx()] = static_cast<std::uint32_t>(vertex_of_.size());
    vertex_of_.push_back(v);
    original_positions_.push_back(mesh.position(v));
  }
  const std::size_t n = vertex_of_.size();
  triangles_.reserve(mesh.n_faces() * 2);
  std::vector<Vertex> corners;
  std::unordered_set<std::uint64_t> diagonals;
  for (Face f : mesh.faces()) {
    corners.clear();
    for (Vertex v : mesh.vertices(f)) corners.push_back(v);
    const std::size_t apex = fan_apex(mesh, corners, diagonals);
    const std::size_t k = corners.size();
    for (std::size_t i = 2; i + 1 < k; ++i)
      diagonals.insert(pair_key(corners[apex], corners[(apex + i) % k]));
    for (std::size_t i = 1; i + 1 < k; ++i)
      triangles_.push_back({dense[corners[apex].idx()], dense[corners[(apex + i) % k].idx()],
                            dense[corners[(apex + i + 1) % k].idx()]});
  }
  if (record_) original_triangles_ = triangles_;
  tri_alive_.assign(triangles_.size(), 1);
  alive_triangles_ = triangles_.size();

  // Work in a box of unit diagonal centred at the origin, so that quadric coefficients and
  // tolerances mean the same at 1e-9 and at 1e9.
  Eigen::AlignedBox3d box;
  box.setEmpty();
  for (const Point& p : original_positions_) box.extend(p);
  if (n > 0) {
    center_ = box.center();
    const double diag = box.diagonal().norm();
    scale_ = diag > 0 && std::isfinite(diag) ? diag : 1.0;
  }
  model_ = original_positions_;
  pos_.resize(n);
  for (std::size_t i = 0; i < n; ++i) pos_[i] = (model_[i] - center_) / scale_;

  quadric_.assign(n, Quadric{});
  weight_.assign(n, 0.0);
  stamp_.assign(n, 0);
  tri_count_.assign(n, 0);
  boundary_.assign(n, 0);
  locked_.assign(n, 0);
  retry_.assign(n, 0);
  mark_.assign(n, 0);
  for (Vertex v : options.locked)
    if (mesh.is_valid(v) && dense[v.idx()] != kNone) locked_[dense[v.idx()]] = 1;

  ref_begin_.assign(n, 0);
  ref_size_.assign(n, 0);
  for (const auto& t : triangles_)
    for (std::uint32_t v : t) ++tri_count_[v];
  std::uint32_t offset = 0;
  for (std::size_t v = 0; v < n; ++v) ref_begin_[v] = offset, offset += tri_count_[v];
  refs_.reserve(3 * static_cast<std::size_t>(offset) + 64);
  refs_.resize(offset);
  for (std::uint32_t t = 0; t < triangles_.size(); ++t)
    for (std::uint32_t v : triangles_[t]) refs_[ref_begin_[v] + ref_size_[v]++] = t;

  for (const auto& t : triangles_) {
    const Point &a = pos_[t[0]], &b = pos_[t[1]], &c = pos_[t[2]];
    const Eigen::Vector3d nrm = (b - a).cross(c - a);
    const double len = nrm.norm();
    if (!(len > 0) || !std::isfinite(len)) continue;
    const Eigen::Vector3d unit = nrm / len;
    const double area = 0.5 * len;
    const Quadric q = Quadric::plane_through(a, unit, area);
    for (std::uint32_t v : t) quadric_[v] += q, weight_[v] += area;
  }

  // Boundary edges: a→b with no triangle b→a around a. Each gets a constraint plane
  // through the edge, perpendicular to its face, weighted like an area (length²).
  for (std::uint32_t a = 0; a < n; ++a) {
    for (std::uint32_t i = ref_begin_[a]; i < ref_begin_[a] + ref_size_[a]; ++i) {
      const auto& t = triangles_[refs_[i]];
      const int k = t[0] == a ? 0 : t[1] == a ? 1 : 2;
      const std::uint32_t b = t[(k + 1) % 3];
      bool twin = false;
      for (std::uint32_t j = ref_begin_[a]; j < ref_begin_[a] + ref_size_[a] && !twin; ++j) {
        const auto& s = triangles_[refs_[j]];
        const int m = s[0] == a ? 0 : s[1] == a ? 1 : 2;
        twin = s[(m + 2) % 3] == b;
      }
      if (twin) continue;
      boundary_[a] = boundary_[b] = 1;
      const Eigen::Vector3d e = pos_[b] - pos_[a];
      const Eigen::Vector3d fn = e.cross(pos_[t[(k + 2) % 3]] - pos_[a]);
      Eigen::Vector3d cn = e.cross(fn);
      const double len = cn.norm();
      if (options.boundary_weight > 0 && len > 0 && std::isfinite(len)) {
        cn /= len;
        const Quadric q = Quadric::plane_through(pos_[a], cn, options.boundary_weight * e.squaredNorm());
        quadric_[a] += q;
        quadric_[b] += q;
      }
    }
  }
  if (options.lock_boundary)
    for (std::size_t v = 0; v < n; ++v) locked_[v] |= boundary_[v];

  for (std::uint32_t a = 0; a < n; ++a) {
    ++mark_token_;
    for (std::uint32_t i = ref_begin_[a]; i < ref_begin_[a] + ref_size_[a]; ++i)
      for (std::uint32_t b : triangles_[refs_[i]])
        if (b > a && mark_[b] != mark_token_ && !(locked_[a] && locked_[b])) {
          mark_[b] = mark_token_;
          queue_.push({static_cast<float>(place(a, b).cost), a, b, 0});
        }
  }
}

std::uint32_t CollapseEngine::RadixQueue::key(float cost) {
  // Non-negative floats order like their bit patterns; NaN goes last.
  if (!(cost >= 0.0f)) return std::isnan(cost) ? 0x7f800000u : 0u;
  return std::bit_cast<std::uint32_t>(cost);
}

int CollapseEngine::RadixQueue::bucket(std::uint32_t k) const {
  return k == last_ ? 0 : 32 - std::countl_zero(k ^ last_);
}

void CollapseEngine::RadixQueue::push(Candidate c) {
  std::uint32_t k = key(c.cost);
  if (k < last_) {
    k = last_;
    c.cost = std::bit_cast<float>(k);
  }
  buckets_[bucket(k)].push_back(c);
  ++size_;
}

void CollapseEngine::RadixQueue::settle() {
  if (buckets_[0].empty()) {
    int i = 1;
    while (buckets_[i].empty()) ++i;
    // Every entry of bucket i shares the bits above i with last_; the new minimum splits
    // them into lower buckets, each entry moving at least one bucket down.
    std::vector<Candidate>& from = buckets_[i];
    std::uint32_t lowest = key(from.front().cost);
    for (const Candidate& c : from) lowest = std::min(lowest, key(c.cost));
    last_ = lowest;
    for (const Candidate& c : from) buckets_[bucket(key(c.cost))].push_back(c);
    from.clear();
  }
}

CollapseEngine::Candidate CollapseEngine::RadixQueue::pop() {
  settle();
  const Candidate c = buckets_[0].back();
  buckets_[0].pop_back();
  --size_;
  return c;
}

CollapseEngine::Placement CollapseEngine::place(std::uint32_t a, std::uint32_t b) const {
  Quadric q = quadric_[a];
  q += quadric_[b];
  if (locked_[a]) return {q.evaluate(pos_[a]), pos_[a], 1};
  if (locked_[b]) return {q.evaluate(pos_[b]), pos_[b], 2};
  const Point mid = 0.5 * (pos_[a] + pos_[b]);
  // Differences below the evaluation's round-off (coordinates are within the unit box)
  // are ties.
  const double noise = 1e-12 * (q.a00 + q.a11 + q.a22 + std::abs(q.b0) + std::abs(q.b1) +
                                std::abs(q.b2) + std::abs(q.c));
  Placement best{q.evaluate(pos_[a]), pos_[a], 1};
  const double cb = q.evaluate(pos_[b]);
  if (cb < best.cost - noise) best = {cb, pos_[b], 2};
  const double cm = q.evaluate(mid);
  if (cm < best.cost - noise) best = {cm, mid, 3};
  const Point opt = q.minimizer(mid);
  // The optimum must stay near the edge: a far-away minimiser of a nearly singular quadric
  // is numerically meaningless even when finite.
  const double reach = 4.0 * (pos_[a] - pos_[b]).squaredNorm();
  if ((opt - mid).squaredNorm() <= reach) {
    // Ties (within round-off) go to the endpoint: its position is then kept bit-exact,
    // which matters on flat regions and at corners where every choice costs ~0.
    const double co = q.evaluate(opt);
    if (co < best.cost - noise) best = {co, opt, 0};
  }
  return best;
}

void CollapseEngine::push_edge(std::uint32_t a, std::uint32_t b) {
  if (locked_[a] && locked_[b]) return;
  queue_.push({static_cast<float>(place(a, b).cost), a, b, stamp_[a] + stamp_[b]});
}

void CollapseEngine::push_vertex_edges(std::uint32_t v) {
  ++mark_token_;
  mark_[v] = mark_token_;
  // Gather first and prefetch the neighbours' quadrics: their cache misses then overlap
  // instead of stalling one placement after another.
  neighbours_.clear();
  for (std::uint32_t i = ref_begin_[v]; i < ref_begin_[v] + ref_size_[v]; ++i) {
    const std::uint32_t t = refs_[i];
    if (!tri_alive_[t]) continue;
    for (std::uint32_t w : triangles_[t])
      if (mark_[w] != mark_token_) {
        mark_[w] = mark_token_;
        neighbours_.push_back(w);
        __builtin_prefetch(&quadric_[w]);
        __builtin_prefetch(&quadric_[w].b1);
        __builtin_prefetch(&pos_[w]);
      }
  }
  for (std::uint32_t w : neighbours_) push_edge(v, w);
}

bool CollapseEngine::has_tri_with(std::uint32_t t, std::uint32_t x) const {
  const auto& tri = triangles_[t];
  return tri[0] == x || tri[1] == x || tri[2] == x;
}

// Whether triangle t stays acceptable when its corner `moved` goes to p: no flip against its
// current normal, and no drop below the quality bound unless it was already that poor.
bool CollapseEngine::face_ok(std::uint32_t t, std::uint32_t moved, const Point& p) const {
  const auto& tri = triangles_[t];
  const int k = tri[0] == moved ? 0 : tri[1] == moved ? 1 : 2;
  const Point& a = pos_[tri[0]];
  const Point& b = pos_[tri[1]];
  const Point& c = pos_[tri[2]];
  const Eigen::Vector3d n0 = (b - a).cross(c - a);
  const Point& a1 = k == 0 ? p : a;
  const Point& b1 = k == 1 ? p : b;
  const Point& c1 = k == 2 ? p : c;
  const Eigen::Vector3d n1 = (b1 - a1).cross(c1 - a1);
  const double l0 = n0.norm(), l1 = n1.norm();
  if (l0 > 0 && !(n0.dot(n1) > 0)) return false;
  const double q1 = quality(a1, b1, c1, l1);
  if (q1 < options_.min_triangle_quality && q1 < quality(a, b, c, l0)) return false;
  return true;
}

void CollapseEngine::ensure_refs(std::size_t extra) {
  if (refs_.size() + extra <= refs_.capacity()) return;
  // Out of room: rewrite every live list without its dead triangles into a fresh array with
  // slack, so this (rare) reallocation is amortised over many collapses.
  std::size_t live = 0;
  for (std::size_t v = 0; v < ref_size_.size(); ++v) live += tri_count_[v];
  std::vector<std::uint32_t> fresh;
  fresh.reserve(std::max(refs_.capacity(), 2 * live + extra + 64));
  for (std::size_t v = 0; v < ref_begin_.size(); ++v) {
    const std::uint32_t begin = ref_begin_[v], size = ref_size_[v];
    ref_begin_[v] = static_cast<std::uint32_t>(fresh.size());
    for (std::uint32_t i = begin; i < begin + size; ++i)
      if (tri_alive_[refs_[i]]) fresh.push_back(refs_[i]);
    ref_size_[v] = static_cast<std::uint32_t>(fresh.size()) - ref_begin_[v];
  }
  refs_.swap(fresh);
}

int CollapseEngine::try_collapse(std::uint32_t u, std::uint32_t v, const Placement& pl) {
  // 1 = ok, 0 = topologically or geometrically invalid, 2 = over max_error.
  std::uint32_t opposite[2] = {kNone, kNone};
  int n_shared = 0;
  for (std::uint32_t i = ref_begin_[u]; i < ref_begin_[u] + ref_size_[u]; ++i) {
    const std::uint32_t t = refs_[i];
    if (!tri_alive_[t] || !has_tri_with(t, v)) continue;
    if (n_shared == 2) return 0;
    const auto& tri = triangles_[t];
    opposite[n_shared++] = tri[0] != u && tri[0] != v ? tri[0] : tri[1] != u && tri[1] != v ? tri[1] : tri[2];
  }
  if (n_shared == 0) return 0;
  const bool boundary_edge = n_shared == 1;
  // An interior edge between two boundary vertices would pinch or merge boundaries.
  if (!boundary_edge && boundary_[u] && boundary_[v]) return 0;

  // Link condition: the common neighbours of u and v are exactly the opposite corners.
  ++mark_token_;
  for (std::uint32_t i = ref_begin_[u]; i < ref_begin_[u] + ref_size_[u]; ++i) {
    const std::uint32_t t = refs_[i];
    if (!tri_alive_[t]) continue;
    for (std::uint32_t w : triangles_[t]) mark_[w] = mark_token_;
  }
  const std::uint32_t token_u = mark_token_;
  ++mark_token_;
  int common = 0;
  for (std::uint32_t i = ref_begin_[v]; i < ref_begin_[v] + ref_size_[v]; ++i) {
    const std::uint32_t t = refs_[i];
    if (!tri_alive_[t]) continue;
    for (std::uint32_t w : triangles_[t])
      if (w != u && w != v && mark_[w] == token_u) {
        mark_[w] = mark_token_;
        ++common;
      }
  }
  if (common != n_shared) return 0;

  // Valences stay sane: interior vertices keep ≥ 3 triangles, boundary ones ≥ 1. This is
  // what stops a tetrahedron from folding into a two-triangle pillow.
  for (int s = 0; s < n_shared; ++s) {
    const std::uint32_t w = opposite[s];
    if (tri_count_[w] - 1 < (boundary_[w] ? 1u : 3u)) return 0;
  }
  const std::uint32_t merged = tri_count_[u] + tri_count_[v] - 2u * static_cast<std::uint32_t>(n_shared);
  if (merged < ((boundary_[u] || boundary_[v]) ? 1u : 3u)) return 0;

  for (std::uint32_t i = ref_begin_[u]; i < ref_begin_[u] + ref_size_[u]; ++i) {
    const std::uint32_t t = refs_[i];
    if (tri_alive_[t] && !has_tri_with(t, v) && !face_ok(t, u, pl.p)) return 0;
  }
  for (std::uint32_t i = ref_begin_[v]; i < ref_begin_[v] + ref_size_[v]; ++i) {
    const std::uint32_t t = refs_[i];
    if (tri_alive_[t] && !has_tri_with(t, u) && !face_ok(t, v, pl.p)) return 0;
  }

  if (std::isfinite(options_.max_error)) {
    const double w = weight_[u] + weight_[v];
    const double err = w > 0 ? std::sqrt(pl.cost / w) * scale_ : 0.0;
    if (err > options_.max_error) return 2;
  }
  return 1;
}

void CollapseEngine::collapse(std::uint32_t u, std::uint32_t v, const Placement& pl) {
  ensure_refs(ref_size_[u] + ref_size_[v]);
  CollapseRecord rec;
  if (record_) {
    rec.u = u;
    rec.v = v;
    rec.pos_u = model_[u];
    rec.pos_v_before = model_[v];
    rec.changed_begin = static_cast<std::uint32_t>(changed_.size());
  }
  const auto new_begin = static_cast<std::uint32_t>(refs_.size());
  for (std::uint32_t i = ref_begin_[v]; i < ref_begin_[v] + ref_size_[v]; ++i) {
    const std::uint32_t t = refs_[i];
    if (tri_alive_[t] && !has_tri_with(t, u)) refs_.push_back(t);
  }
  int n_dead = 0;
  for (std::uint32_t i = ref_begin_[u]; i < ref_begin_[u] + ref_size_[u]; ++i) {
    const std::uint32_t t = refs_[i];
    if (!tri_alive_[t]) continue;
    auto& tri = triangles_[t];
    if (has_tri_with(t, v)) {
      tri_alive_[t] = 0;
      --alive_triangles_;
      for (std::uint32_t w : tri)
        if (w != u && w != v) --tri_count_[w];
      if (record_) rec.dead[n_dead] = t;
      ++n_dead;
      continue;
    }
    for (std::uint32_t k = 0; k < 3; ++k)
      if (tri[k] == u) {
        tri[k] = v;
        if (record_) changed_.push_back(3 * t + k);
      }
    refs_.push_back(t);
  }
  const double w = weight_[u] + weight_[v];
  if (w > 0) max_error_ = std::max(max_error_, std::sqrt(pl.cost / w) * scale_);

  ref_begin_[v] = new_begin;
  ref_size_[v] = static_cast<std::uint32_t>(refs_.size()) - new_begin;
  tri_count_[v] = ref_size_[v];
  tri_count_[u] = 0;
  ref_size_[u] = 0;
  quadric_[v] += quadric_[u];
  weight_[v] = w;
  pos_[v] = pl.p;
  // Sources 1 and 2 keep the survivor's own position (run() orders u, v so): copying the
  // model-unit value keeps kept and locked vertices bit-exact.
  if (pl.source == 0 || pl.source == 3) model_[v] = center_ + scale_ * pl.p;
  boundary_[v] |= boundary_[u];
  ++stamp_[v];
  ++stamp_[u];
  ++collapses_;
  if (record_) {
    rec.pos_v_after = model_[v];
    rec.changed_end = static_cast<std::uint32_t>(changed_.size());
    records_.push_back(rec);
  }
}

SimplifyStop CollapseEngine::run(std::size_t target) {
  const std::size_t start = alive_triangles_;
  std::size_t next_report = 4096;
  while (alive_triangles_ > target) {
    if (queue_.empty()) return error_rejected_ ? SimplifyStop::kMaxError : SimplifyStop::kNoValidCollapse;
    const Candidate c = queue_.pop();
    // The next entry's stamps are a cache miss away; start fetching them now.
    if (const Candidate* next = queue_.peek()) {
      __builtin_prefetch(&stamp_[next->a]);
      __builtin_prefetch(&stamp_[next->b]);
    }
    // Every collapse queues all edges of its survivor afresh, so an entry whose endpoints
    // changed since (including one that was removed) has a newer twin: drop it unevaluated.
    if (c.stamps != stamp_[c.a] + stamp_[c.b]) continue;
    const Placement pl = place(c.a, c.b);
    // Remove the vertex whose position is not kept; a locked vertex is always the survivor.
    std::uint32_t u = c.a, v = c.b;
    if (pl.source == 1 || locked_[c.a]) std::swap(u, v);
    const int verdict = try_collapse(u, v, pl);
    if (verdict != 1) {
      // Remember both ends: when a neighbour changes, their edges get another chance.
      retry_[c.a] = retry_[c.b] = 1;
      if (verdict == 2) error_rejected_ = true;
      continue;
    }
    collapse(u, v, pl);
    // Re-evaluated now, while the neighbourhood is in cache, rather than when the old
    // entries reach the top.
    retry_[v] = 0;
    push_vertex_edges(v);
    // Neighbours with rejected edges: their surroundings changed, so queue their edges
    // again (duplicates of still-valid entries are harmless).
    for (std::uint32_t i = ref_begin_[v]; i < ref_begin_[v] + ref_size_[v]; ++i)
      for (std::uint32_t w : triangles_[refs_[i]])
        if (w != v && retry_[w]) {
          retry_[w] = 0;
          push_vertex_edges(w);
        }
    if (options_.progress && collapses_ >= next_report) {
      next_report = collapses_ + 4096;
      const double total = static_cast<double>(start - std::min(start, target));
      if (!options_.progress(total > 0 ? static_cast<double>(start - alive_triangles_) / total : 1.0))
        return SimplifyStop::kCancelled;
    }
  }
  return SimplifyStop::kTargetReached;
}

SurfaceMesh CollapseEngine::extract(std::vector<Vertex>* out_origin) const {
  SurfaceMesh out;
  std::vector<std::uint32_t> index(pos_.size(), kNone);
  std::size_t nv = 0;
  for (std::size_t v = 0; v < pos_.size(); ++v) nv += tri_count_[v] > 0;
  out.reserve(nv, alive_triangles_ * 3 / 2 + 3, alive_triangles_);
  if (out_origin) out_origin->clear();
  for (std::size_t v = 0; v < pos_.size(); ++v) {
    if (tri_count_[v] == 0) continue;
    index[v] = out.add_vertex(model_[v]).idx();
    if (out_origin) out_origin->push_back(vertex_of_[v]);
  }
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    if (!tri_alive_[t]) continue;
    const auto& tri = triangles_[t];
    out.add_triangle(Vertex(index[tri[0]]), Vertex(index[tri[1]]), Vertex(index[tri[2]]));
  }
  return out;
}

}  // namespace geom::detail
