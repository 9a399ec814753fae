// Incremental Delaunay triangulation: Hilbert order, visibility walk, Bowyer-Watson cavity.
// Every decision is an exact predicate; a zero in-circle test is broken by Simulation of
// Simplicity on the insertion rank, which makes the triangulation the unique Delaunay
// triangulation of infinitesimally lifted points (the ranks come from the Hilbert order,
// a deterministic function of the input).

#include <geom/compgeom/hull2.h>
#include <geom/compgeom/spatial_sort.h>
#include <geom/compgeom/triangulation2.h>
#include <geom/core/errors.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace geom {
namespace detail {

std::vector<std::array<std::uint32_t, 3>> Triangulation2::finite_triangles() const {
  std::vector<std::array<std::uint32_t, 3>> out;
  out.reserve(v.size() / 2 + 1);
  for (std::uint32_t t = 0; t < v.size(); ++t)
    if (!dead[t] && !infinite(t)) out.push_back(v[t]);
  return out;
}

void flip(Triangulation2& tr, std::uint32_t t, int i) {
  const std::uint32_t a = tr.v[t][i], b = tr.v[t][(i + 1) % 3], c = tr.v[t][(i + 2) % 3];
  const std::uint32_t u = tr.nb[t][i];
  const int j = tr.back_index(u, t);
  const std::uint32_t d = tr.v[u][j];
  const std::uint32_t na = tr.nb[t][(i + 1) % 3], nbb = tr.nb[t][(i + 2) % 3];
  const std::uint32_t nc = tr.nb[u][(j + 1) % 3], nd = tr.nb[u][(j + 2) % 3];
  const int back_nc = tr.back_index(nc, u), back_na = tr.back_index(na, t);
  tr.v[t] = {a, b, d};
  tr.nb[t] = {nc, u, nbb};
  tr.v[u] = {a, d, c};
  tr.nb[u] = {nd, na, t};
  tr.nb[nc][back_nc] = t;
  tr.nb[na][back_na] = u;
}

namespace {

template <bool Exact>
class Inserter {
 public:
  explicit Inserter(Triangulation2& tr)
      : tr_(tr), start_of_(tr.n_points + 1), seen_(tr.n_points + 1, 0) {}

  int orient(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    if constexpr (Exact) {
      if (small_integers_) {
        bool sure;
        ++tr_.stats.calls;
        return sign_of(orient2d_filter(tr_.p(a), tr_.p(b), tr_.p(c), sure));
      }
      return orient2d(tr_.p(a), tr_.p(b), tr_.p(c), tr_.stats);
    } else {
      bool sure;
      ++tr_.stats.calls;
      return sign_of(orient2d_filter(tr_.p(a), tr_.p(b), tr_.p(c), sure));
    }
  }

  bool same(std::uint32_t a, std::uint32_t b) const {
    return tr_.p(a)[0] == tr_.p(b)[0] && tr_.p(a)[1] == tr_.p(b)[1];
  }

  // Collinear c strictly inside segment ab (exact: the points are known collinear).
  bool strictly_between(std::uint32_t a, std::uint32_t b, std::uint32_t c) const {
    int k = tr_.p(a)[0] != tr_.p(b)[0] ? 0 : 1;
    double pa = tr_.p(a)[k], pb = tr_.p(b)[k], pc = tr_.p(c)[k];
    return (pa < pc && pc < pb) || (pb < pc && pc < pa);
  }

  bool conflict(std::uint32_t t, std::uint32_t q) {
    const auto& v = tr_.v[t];
    int k = v[0] == kInfinite ? 0 : v[1] == kInfinite ? 1 : v[2] == kInfinite ? 2 : 3;
    if (k == 3) {
      const double *a = tr_.p(v[0]), *b = tr_.p(v[1]), *c = tr_.p(v[2]), *d = tr_.p(q);
      int s;
      if constexpr (Exact) {
        if (small_integers_) {
          bool sure;
          ++tr_.stats.calls;
          s = sign_of(incircle_filter(a, b, c, d, sure));
        } else {
          s = incircle(a, b, c, d, tr_.stats);
        }
      } else {
        bool sure;
        ++tr_.stats.calls;
        s = sign_of(incircle_filter(a, b, c, d, sure));
      }
      if (s != 0) return s > 0;
      // Cocircular: q has the highest rank, so its lift is perturbed most and the
      // perturbed test reads -orient2d(a, b, c) < 0 (incircle_perturbed's leading term).
      ++tr_.cocircular;
      return false;
    }
    std::uint32_t a = v[(k + 1) % 3], b = v[(k + 2) % 3];
    int o = orient(a, b, q);
    if (o != 0) return o > 0;
    return strictly_between(a, b, q);
  }

  std::uint32_t locate(std::uint32_t q) {
    std::uint32_t t = hint_;
    if (tr_.dead[t]) t = first_live();
    if (tr_.infinite(t)) t = tr_.nb[t][tr_.index_of(t, kInfinite)];
    std::uint32_t prev = kNoTriangle;
    const std::size_t limit = 4 * tr_.v.size() + 64;
    for (std::size_t steps = 0;; ++steps) {
      if (tr_.infinite(t)) return t;
      if (steps > limit)
        throw Error(
            "delaunay_2d: point location did not terminate (inexact predicates "
            "gave inconsistent answers at point " +
            std::to_string(q) + ")");
      rng_ = rng_ * 6364136223846793005ULL + 1442695040888963407ULL;
      const int e0 = static_cast<int>((rng_ >> 33) % 3);
      bool moved = false;
      for (int k = 0; k < 3; ++k) {
        int i = (e0 + k) % 3;
        std::uint32_t n = tr_.nb[t][i];
        if (n == prev) continue;
        if (orient(tr_.v[t][(i + 1) % 3], tr_.v[t][(i + 2) % 3], q) < 0) {
          prev = t;
          t = n;
          moved = true;
          break;
        }
      }
      if (!moved) return t;
    }
  }

  std::uint32_t first_live() const {
    for (std::uint32_t t = 0; t < tr_.v.size(); ++t)
      if (!tr_.dead[t]) return t;
    return 0;
  }

  // Inserts point q; returns false when q repeats an existing vertex (vertex_of set).
  bool insert(std::uint32_t q) {
    std::uint32_t t = locate(q);
    for (std::uint32_t x : tr_.v[t])
      if (x != kInfinite && same(x, q)) {
        tr_.vertex_of[q] = x;
        return false;
      }
    if (!conflict(t, q))
      throw Error("delaunay_2d: the triangle located for point " + std::to_string(q) +
                  " does not conflict with it (inexact predicates)");
    stamp_ += 2;
    const std::uint32_t in = stamp_, out = stamp_ + 1;
    mark_.resize(tr_.v.size(), 0);
    cavity_.clear();
    boundary_.clear();
    stack_.clear();
    mark_[t] = in;
    stack_.push_back(t);
    cavity_.push_back(t);
    while (!stack_.empty()) {
      std::uint32_t c = stack_.back();
      stack_.pop_back();
      for (int i = 0; i < 3; ++i) {
        std::uint32_t n = tr_.nb[c][i];
        if (mark_[n] == in) continue;
        if (mark_[n] != out && conflict(n, q)) {
          mark_[n] = in;
          stack_.push_back(n);
          cavity_.push_back(n);
        } else {
          mark_[n] = out;
          boundary_.push_back(
              {tr_.v[c][(i + 1) % 3], tr_.v[c][(i + 2) % 3], n, tr_.back_index(n, c)});
        }
      }
    }
    // Re-use the cavity's slots for the new fan around q.
    std::size_t reuse = 0;
    std::uint32_t last_finite = kNoTriangle;
    for (const Border& e : boundary_) {
      std::uint32_t T;
      if (reuse < cavity_.size()) {
        T = cavity_[reuse++];
      } else {
        T = static_cast<std::uint32_t>(tr_.v.size());
        tr_.tri.push_back({});
        tr_.dead.push_back(0);
        mark_.push_back(0);
      }
      tr_.v[T] = {q, e.a, e.b};
      tr_.nb[T] = {e.n, kNoTriangle, kNoTriangle};
      tr_.nb[e.n][e.back] = T;
      std::uint32_t key = e.a == kInfinite ? static_cast<std::uint32_t>(tr_.n_points) : e.a;
      if (seen_[key] == stamp_)
        throw Error("delaunay_2d: the cavity of point " + std::to_string(q) +
                    " is not star-shaped (inexact predicates)");
      seen_[key] = stamp_;
      start_of_[key] = T;
      if (e.a != kInfinite && e.b != kInfinite) last_finite = T;
    }
    // A cavity has two triangles fewer than its border edges; with inexact predicates the
    // counts can disagree, and the left-over slots are retired.
    for (; reuse < cavity_.size(); ++reuse) tr_.dead[cavity_[reuse]] = 1;
    for (std::size_t k = 0; k < boundary_.size(); ++k) {
      const Border& e = boundary_[k];
      std::uint32_t T = tr_.nb[e.n][e.back];
      std::uint32_t key = e.b == kInfinite ? static_cast<std::uint32_t>(tr_.n_points) : e.b;
      if (seen_[key] != stamp_)
        throw Error("delaunay_2d: the cavity of point " + std::to_string(q) +
                    " is not closed (inexact predicates)");
      std::uint32_t U = start_of_[key];
      tr_.nb[T][1] = U;
      tr_.nb[U][2] = T;
    }
    if (last_finite != kNoTriangle) hint_ = last_finite;
    return true;
  }

  void set_hint(std::uint32_t t) { hint_ = t; }

  /// Declares that every coordinate is an integer multiple of one power of two and the
  /// coordinate ranges span at most 2^12 such units: then every intermediate of the
  /// orient2d and incircle determinants is an integer below 2^53 (in those units), the
  /// plain double evaluation is exact, and the filters' fallbacks are unnecessary.
  void set_small_integers(bool on) { small_integers_ = on; }

 private:
  struct Border {
    std::uint32_t a, b, n;
    int back;
  };
  Triangulation2& tr_;
  std::vector<std::uint32_t> start_of_, seen_, mark_, stack_, cavity_;
  std::vector<Border> boundary_;
  std::uint32_t stamp_ = 0;
  std::uint32_t hint_ = 0;
  bool small_integers_ = false;
  std::uint64_t rng_ = 0x853c49e6748fea9bULL;
};

// True when all coordinates are integer multiples of one power of two 2^e and each axis
// spans at most 2^12 units: differences are then integers below 2^13 units, lifted terms
// below 2^27, products below 2^52 - all exact in double (see set_small_integers).
bool small_integer_grid(const double* xy, std::size_t n) {
  if (n == 0) return false;
  double lo[2] = {xy[0], xy[1]}, hi[2] = {xy[0], xy[1]};
  int e = std::numeric_limits<int>::max();  // the smallest exponent of a set bit
  for (std::size_t i = 0; i < 2 * n; ++i) {
    double x = xy[i];
    lo[i & 1] = std::min(lo[i & 1], x);
    hi[i & 1] = std::max(hi[i & 1], x);
    if (x == 0) continue;
    int ex;
    double m = std::frexp(x, &ex);  // x = m * 2^ex, 0.5 <= |m| < 1
    // Lowest set bit of the 53-bit mantissa.
    std::int64_t mant = static_cast<std::int64_t>(std::ldexp(std::fabs(m), 53));
    int tz = 0;
    while (tz < 53 && !(mant & (std::int64_t(1) << tz))) ++tz;
    e = std::min(e, ex - 53 + tz);
  }
  if (e == std::numeric_limits<int>::max()) return true;  // all zero
  if (e < -900) return false;                             // keep clear of underflow
  const double unit = std::ldexp(1.0, e);
  for (int k = 0; k < 2; ++k)
    if ((hi[k] - lo[k]) / unit > 4096.0) return false;
  return true;
}

// The distinct points are collinear: sort them along the line (lexicographically) and merge
// repeats into their first copy.
void build_chain(Triangulation2& tr) {
  const std::size_t n = tr.n_points;
  tr.collinear = true;
  auto same = [&](std::uint32_t a, std::uint32_t b) {
    return tr.p(a)[0] == tr.p(b)[0] && tr.p(a)[1] == tr.p(b)[1];
  };
  std::vector<std::uint32_t> s(n);
  for (std::uint32_t i = 0; i < n; ++i) s[i] = i;
  auto less = [&](std::uint32_t a, std::uint32_t b) {
    const double *p = tr.p(a), *q = tr.p(b);
    return p[0] < q[0] || (p[0] == q[0] && (p[1] < q[1] || (p[1] == q[1] && a < b)));
  };
  std::sort(s.begin(), s.end(), less);
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0 && same(s[i], tr.vertex_of[s[i - 1]])) {
      tr.vertex_of[s[i]] = tr.vertex_of[s[i - 1]];
    } else {
      tr.vertex_of[s[i]] = s[i];
      tr.chain.push_back(s[i]);
    }
  }
  tr.order = tr.chain;
}

template <bool Exact>
void build(Triangulation2& tr) {
  const std::size_t n = tr.n_points;
  const double* input = tr.xy;
  std::vector<std::uint32_t> order = hilbert_order_2d(input, n, 2);
  // Work on a copy in insertion order: consecutive insertions then touch neighbouring
  // memory. Vertex ids are insertion ranks until the final remap. SoS perturbs by rank: a
  // new point is the most perturbed (lifted highest), so a cocircular neighbour triangle
  // is never in conflict and cavities stay as small as with a strict in-circle test.
  std::vector<double> local(2 * n);
  for (std::size_t k = 0; k < n; ++k) {
    local[2 * k] = input[2 * std::size_t(order[k])];
    local[2 * k + 1] = input[2 * std::size_t(order[k]) + 1];
  }
  tr.xy = local.data();
  tr.sos = nullptr;
  Inserter<Exact> ins(tr);
  ins.set_small_integers(small_integer_grid(input, n));
  auto same = [&](std::uint32_t a, std::uint32_t b) { return ins.same(a, b); };
  // The first triangle: the first point, the next distinct one, the next not collinear.
  std::uint32_t j = 1;
  while (j < n && same(j, 0)) ++j;
  std::uint32_t k = j + 1;
  while (k < n && ins.orient(0, j, k) == 0) ++k;
  if (k >= n) {
    tr.xy = input;
    tr.sos = nullptr;
    build_chain(tr);
    return;
  }
  std::uint32_t a = 0, b = j, c = k;
  if (ins.orient(a, b, c) < 0) std::swap(b, c);
  // One finite triangle and the three infinite ones across its edges.
  tr.tri = {{{a, b, c}, {1, 2, 3}},
            {{c, b, kInfinite}, {3, 2, 0}},
            {{a, c, kInfinite}, {1, 3, 0}},
            {{b, a, kInfinite}, {2, 1, 0}}};
  tr.dead.assign(4, 0);
  tr.order = {a, b, c};
  ins.set_hint(0);
  for (std::uint32_t i = 1; i < k; ++i)
    if (i != j && ins.insert(i)) tr.order.push_back(i);
  for (std::uint32_t i = k + 1; i < n; ++i)
    if (ins.insert(i)) tr.order.push_back(i);
  // Back to input indices.
  for (auto& t : tr.tri)
    for (auto& x : t.v)
      if (x != kInfinite) x = order[x];
  std::vector<std::uint32_t> vo(n);
  for (std::size_t r = 0; r < n; ++r) vo[order[r]] = order[tr.vertex_of[r]];
  tr.vertex_of.swap(vo);
  for (auto& x : tr.order) x = order[x];
  tr.xy = input;
  tr.rank.resize(n);
  for (std::uint32_t r = 0; r < n; ++r) tr.rank[order[r]] = r;
  tr.sos = tr.rank.data();
}

}  // namespace

void build_delaunay(Triangulation2& tr, const double* xy, std::size_t n, bool exact) {
  if (n >= std::numeric_limits<std::uint32_t>::max() / 2)
    throw InvalidArgument("delaunay_2d: too many points (" + std::to_string(n) + ")");
  tr.xy = xy;
  tr.n_points = n;
  tr.vertex_of.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) tr.vertex_of[i] = i;
  if (exact)
    build<true>(tr);
  else
    build<false>(tr);
}

}  // namespace detail

namespace {
void fill_result(const detail::Triangulation2& tr, DelaunayResult& r) {
  r.triangles = tr.finite_triangles();
  r.vertex_of = tr.vertex_of;
  r.collinear = tr.collinear;
  r.chain = tr.chain;
  r.cocircular = tr.cocircular;
  r.predicates = tr.stats;
  for (std::uint32_t i = 0; i < r.vertex_of.size(); ++i) r.duplicates += r.vertex_of[i] != i;
  r.vertices = r.vertex_of.size() - r.duplicates;
}
}  // namespace

DelaunayResult delaunay_2d(std::span<const Eigen::Vector2d> given,
                           const DelaunayOptions& options) {
  check_finite(given);
  std::vector<Eigen::Vector2d> scaled;
  const std::span<const Eigen::Vector2d> points = in_predicate_range(given, scaled);
  DelaunayResult r;
  if (points.empty()) {
    r.collinear = true;
    return r;
  }
  detail::Triangulation2 tr;
  detail::build_delaunay(tr, points.data()->data(), points.size(), options.exact);
  fill_result(tr, r);
  return r;
}

}  // namespace geom
