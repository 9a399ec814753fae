// Signs of the exact predicates against GMP rational arithmetic on near-degenerate and
// exactly degenerate inputs.
#include <geom/predicates/predicates.h>

#include <gmpxx.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>

namespace {

using geom::PredicateStats;

int qsign(const mpq_class& q) { return mpq_sgn(q.get_mpq_t()); }

int ref_orient2d(const double* a, const double* b, const double* c) {
  mpq_class acx = mpq_class(a[0]) - c[0], acy = mpq_class(a[1]) - c[1];
  mpq_class bcx = mpq_class(b[0]) - c[0], bcy = mpq_class(b[1]) - c[1];
  return qsign(acx * bcy - acy * bcx);
}

int ref_orient3d(const double* a, const double* b, const double* c, const double* d) {
  mpq_class m[3][3];
  const double* r[3] = {a, b, c};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m[i][j] = mpq_class(r[i][j]) - d[j];
  mpq_class det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                  m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                  m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  return qsign(det);
}

int ref_incircle(const double* a, const double* b, const double* c, const double* d) {
  mpq_class m[3][3];
  const double* r[3] = {a, b, c};
  for (int i = 0; i < 3; ++i) {
    m[i][0] = mpq_class(r[i][0]) - d[0];
    m[i][1] = mpq_class(r[i][1]) - d[1];
    m[i][2] = m[i][0] * m[i][0] + m[i][1] * m[i][1];
  }
  mpq_class det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                  m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                  m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  return qsign(det);
}

mpq_class det3(const mpq_class m[4][4], int r0, int r1, int r2, int c0, int c1, int c2) {
  return m[r0][c0] * (m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1]) -
         m[r0][c1] * (m[r1][c0] * m[r2][c2] - m[r1][c2] * m[r2][c0]) +
         m[r0][c2] * (m[r1][c0] * m[r2][c1] - m[r1][c1] * m[r2][c0]);
}

// Shewchuk's convention: positive when e is inside the sphere of positively oriented abcd;
// equals det of the 4x4 matrix of rows (p - e, |p - e|^2).
int ref_insphere(const double* a, const double* b, const double* c, const double* d,
                 const double* e) {
  mpq_class m[4][4];
  const double* r[4] = {a, b, c, d};
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 3; ++j) m[i][j] = mpq_class(r[i][j]) - e[j];
    m[i][3] = m[i][0] * m[i][0] + m[i][1] * m[i][1] + m[i][2] * m[i][2];
  }
  mpq_class det = -m[0][3] * det3(m, 1, 2, 3, 0, 1, 2) + m[1][3] * det3(m, 0, 2, 3, 0, 1, 2) -
                  m[2][3] * det3(m, 0, 1, 3, 0, 1, 2) + m[3][3] * det3(m, 0, 1, 2, 0, 1, 2);
  return qsign(det);
}

// Moves x by k ulps (k may be negative).
double nudge(double x, int k) {
  for (; k > 0; --k) x = std::nextafter(x, INFINITY);
  for (; k < 0; ++k) x = std::nextafter(x, -INFINITY);
  return x;
}

struct Gen {
  std::mt19937_64 rng;
  explicit Gen(std::uint64_t seed) : rng(seed) {}
  double uni(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
  int ulps() { return std::uniform_int_distribution<int>(-3, 3)(rng); }
  // A scale and offset: unit, huge offset, tiny scale.
  void frame(int kind, double& scale, double& offset) {
    switch (kind % 3) {
      case 0:
        scale = 1, offset = 0;
        break;
      case 1:
        scale = 1, offset = 1e9;
        break;
      default:
        scale = 1e-12, offset = 0;
        break;
    }
  }
};

// 400k + 250k + 200k + 150k = 1e6 random near-degenerate cases in all.
constexpr int kCases = 250000;

TEST(Predicates, Orient2dMatchesGmpOnNearCollinearPoints) {
  Gen g(1);
  int wrong = 0, zeros = 0;
  PredicateStats st;
  for (int i = 0; i < 400000; ++i) {
    double s, o;
    g.frame(i, s, o);
    double a[2] = {o + s * g.uni(-1, 1), o + s * g.uni(-1, 1)};
    double b[2] = {o + s * g.uni(-1, 1), o + s * g.uni(-1, 1)};
    double t = g.uni(-2, 3);
    double c[2] = {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])};
    c[0] = nudge(c[0], g.ulps());
    c[1] = nudge(c[1], g.ulps());
    int r = ref_orient2d(a, b, c);
    zeros += r == 0;
    wrong += geom::orient2d(a, b, c, st) != r;
    wrong += geom::orient2d(b, c, a) != r;
    wrong += geom::orient2d(b, a, c) != -r;
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(st.exact, 0u);  // the battery does exercise the exact path
  RecordProperty("zeros", zeros);
}

TEST(Predicates, IncircleMatchesGmpOnNearCocircularPoints) {
  Gen g(2);
  int wrong = 0;
  PredicateStats st;
  for (int i = 0; i < kCases; ++i) {
    double s, o;
    g.frame(i, s, o);
    double cx = o + s * g.uni(-1, 1), cy = o + s * g.uni(-1, 1), r = s * g.uni(0.01, 2);
    double p[4][2];
    for (auto& q : p) {
      double th = g.uni(0, 2 * std::numbers::pi);
      q[0] = nudge(cx + r * std::cos(th), g.ulps());
      q[1] = nudge(cy + r * std::sin(th), g.ulps());
    }
    int ref = ref_incircle(p[0], p[1], p[2], p[3]);
    wrong += geom::incircle(p[0], p[1], p[2], p[3], st) != ref;
    wrong += geom::incircle(p[1], p[0], p[2], p[3]) != -ref;
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(st.exact, 0u);
}

TEST(Predicates, Orient3dMatchesGmpOnNearCoplanarPoints) {
  Gen g(3);
  int wrong = 0;
  PredicateStats st;
  for (int i = 0; i < 200000; ++i) {
    double s, o;
    g.frame(i, s, o);
    double a[3], b[3], c[3], d[3];
    for (int k = 0; k < 3; ++k) {
      a[k] = o + s * g.uni(-1, 1);
      b[k] = o + s * g.uni(-1, 1);
      c[k] = o + s * g.uni(-1, 1);
    }
    double u = g.uni(-1, 2), v = g.uni(-1, 2);
    for (int k = 0; k < 3; ++k)
      d[k] = nudge(a[k] + u * (b[k] - a[k]) + v * (c[k] - a[k]), g.ulps());
    int ref = ref_orient3d(a, b, c, d);
    wrong += geom::orient3d(a, b, c, d, st) != ref;
    wrong += geom::orient3d(b, a, c, d) != -ref;
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(st.exact, 0u);
}

TEST(Predicates, InsphereMatchesGmpOnNearCosphericalPoints) {
  Gen g(4);
  int wrong = 0;
  PredicateStats st;
  for (int i = 0; i < 150000; ++i) {
    double s, o;
    g.frame(i, s, o);
    double c[3] = {o + s * g.uni(-1, 1), o + s * g.uni(-1, 1), o + s * g.uni(-1, 1)};
    double r = s * g.uni(0.01, 2);
    double p[5][3];
    for (auto& q : p) {
      double z = g.uni(-1, 1), th = g.uni(0, 2 * std::numbers::pi);
      double w = std::sqrt(1 - z * z);
      q[0] = nudge(c[0] + r * w * std::cos(th), g.ulps());
      q[1] = nudge(c[1] + r * w * std::sin(th), g.ulps());
      q[2] = nudge(c[2] + r * z, g.ulps());
    }
    int ref = ref_insphere(p[0], p[1], p[2], p[3], p[4]);
    wrong += geom::insphere(p[0], p[1], p[2], p[3], p[4], st) != ref;
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(st.exact, 0u);
}

TEST(Predicates, ExactlyDegenerateConfigurationsGiveZero) {
  // Collinear on a lattice, with huge offsets and tiny scales (all exactly representable).
  for (double s : {1.0, 0x1p-40, 0x1p30})
    for (double o : {0.0, 1e9, -0x1p40}) {
      double a[2] = {o + 0 * s, o + 0 * s}, b[2] = {o + 3 * s, o + 1 * s},
             c[2] = {o + 9 * s, o + 3 * s};
      EXPECT_EQ(geom::orient2d(a, b, c), 0);
      EXPECT_EQ(ref_orient2d(a, b, c), 0);
      // 3-4-5 cocircular points (x^2 + y^2 = 25).
      double p[4][2] = {
          {o + 5 * s, o}, {o + 3 * s, o + 4 * s}, {o - 4 * s, o + 3 * s}, {o, o - 5 * s}};
      EXPECT_EQ(geom::incircle(p[0], p[1], p[2], p[3]), 0);
      double q[5][3] = {{o + s, o, o}, {o, o + s, o}, {o - s, o, o}, {o, o, o + s}, {o, o - s, o}};
      EXPECT_EQ(geom::orient3d(q[0], q[1], q[2], q[4]), 0);
      EXPECT_EQ(geom::insphere(q[0], q[1], q[2], q[3], q[4]), 0);
    }
  // Repeated points.
  double a[3] = {0.1, 0.2, 0.3};
  EXPECT_EQ(geom::orient2d(a, a, a), 0);
  EXPECT_EQ(geom::orient3d(a, a, a, a), 0);
}

TEST(Predicates, KnownSigns) {
  double a[2] = {0, 0}, b[2] = {1, 0}, c[2] = {0, 1}, in[2] = {0.25, 0.25}, out[2] = {2, 2};
  EXPECT_EQ(geom::orient2d(a, b, c), 1);
  EXPECT_EQ(geom::orient2d(a, c, b), -1);
  EXPECT_EQ(geom::incircle(a, b, c, in), 1);
  EXPECT_EQ(geom::incircle(a, b, c, out), -1);
  double p[3] = {0, 0, 0}, q[3] = {1, 0, 0}, r[3] = {0, 1, 0}, below[3] = {0.1, 0.1, -1};
  EXPECT_EQ(geom::orient3d(p, q, r, below), 1);
  double top[3] = {0, 0, 1}, inside[3] = {0.1, 0.1, 0.1}, far[3] = {5, 5, 5};
  // p, q, r, below: positively oriented; the sphere through them contains `inside`.
  EXPECT_EQ(geom::insphere(p, q, r, below, inside), 1);
  EXPECT_EQ(geom::insphere(p, q, r, below, far), -1);
  EXPECT_EQ(ref_insphere(p, q, r, below, inside), 1);
  (void)top;
}

TEST(Predicates, StatsCountFallbacks) {
  PredicateStats st;
  double a[2] = {0, 0}, b[2] = {1, 1}, c[2] = {2, 2}, d[2] = {0, 1};
  geom::orient2d(a, b, d, st);
  EXPECT_EQ(st.calls, 1u);
  EXPECT_EQ(st.exact, 0u);
  geom::orient2d(a, b, c, st);
  EXPECT_EQ(st.calls, 2u);
  EXPECT_EQ(st.exact, 1u);
  EXPECT_DOUBLE_EQ(st.exact_rate(), 0.5);
}

}  // namespace
