// Simulation of Simplicity: deterministic, consistent signs for exactly degenerate input.
#include <geom/predicates/predicates.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>

namespace {

TEST(Sos, AgreesWithExactPredicateWhenNonDegenerate) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> u(-3, 3);
  for (int it = 0; it < 20000; ++it) {
    double p[5][3];
    for (auto& q : p)
      for (double& x : q) x = u(rng);
    int o = geom::orient2d(p[0], p[1], p[2]);
    if (o != 0) {
      EXPECT_EQ(geom::orient2d_sos(p[0], p[1], p[2], 0, 1, 2), o);
    }
    int ic = geom::incircle(p[0], p[1], p[2], p[3]);
    if (ic != 0) {
      EXPECT_EQ(geom::incircle_sos(p[0], p[1], p[2], p[3], 3, 1, 0, 2), ic);
    }
    int is = geom::insphere(p[0], p[1], p[2], p[3], p[4]);
    if (is != 0) {
      EXPECT_EQ(geom::insphere_sos(p[0], p[1], p[2], p[3], p[4], 0, 1, 2, 3, 4), is);
    }
  }
}

// Permuting the arguments (with their indices) changes the sign by the permutation's parity;
// this is what makes the perturbed answers consistent across calls.
TEST(Sos, AlternatingUnderPermutationOnDegenerateInput) {
  std::mt19937 rng(8);
  std::uniform_int_distribution<int> u(-2, 2);
  int nonzero2 = 0, nonzero_ic = 0, nonzero_is = 0;
  for (int it = 0; it < 5000; ++it) {
    double p[5][3];
    for (auto& q : p)
      for (double& x : q) x = u(rng);
    std::array<int, 5> id = {0, 1, 2, 3, 4};
    std::shuffle(id.begin(), id.end(), rng);
    int o = geom::orient2d_sos(p[0], p[1], p[2], id[0], id[1], id[2]);
    EXPECT_EQ(geom::orient2d_sos(p[1], p[0], p[2], id[1], id[0], id[2]), -o);
    EXPECT_EQ(geom::orient2d_sos(p[1], p[2], p[0], id[1], id[2], id[0]), o);
    nonzero2 += o != 0;
    int c = geom::incircle_sos(p[0], p[1], p[2], p[3], id[0], id[1], id[2], id[3]);
    EXPECT_EQ(geom::incircle_sos(p[1], p[0], p[2], p[3], id[1], id[0], id[2], id[3]), -c);
    EXPECT_EQ(geom::incircle_sos(p[0], p[1], p[3], p[2], id[0], id[1], id[3], id[2]), -c);
    nonzero_ic += c != 0;
    int s = geom::insphere_sos(p[0], p[1], p[2], p[3], p[4], id[0], id[1], id[2], id[3], id[4]);
    EXPECT_EQ(geom::insphere_sos(p[0], p[1], p[2], p[4], p[3], id[0], id[1], id[2], id[4], id[3]),
              -s);
    EXPECT_EQ(geom::insphere_sos(p[2], p[1], p[0], p[3], p[4], id[2], id[1], id[0], id[3], id[4]),
              -s);
    nonzero_is += s != 0;
  }
  EXPECT_EQ(nonzero2, 5000);  // distinct indices: never zero
  EXPECT_GT(nonzero_ic, 4000);
  EXPECT_GT(nonzero_is, 4000);
}

TEST(Sos, CocircularPointWithLargestIndexCountsAsOutside) {
  double a[2] = {5, 0}, b[2] = {3, 4}, c[2] = {-4, 3}, d[2] = {0, -5};
  ASSERT_EQ(geom::incircle(a, b, c, d), 0);
  EXPECT_EQ(geom::incircle_sos(a, b, c, d, 0, 1, 2, 3), -1);
  // d carries the smallest index: a (largest) decides; in the perturbed world the circle
  // through b, c, d does not contain... a is moved outward, so d is inside circle(a, b, c)
  // exactly when a is outside circle(b, c, d) — the determinant flips accordingly.
  int s = geom::incircle_sos(a, b, c, d, 3, 1, 2, 0);
  EXPECT_EQ(s, geom::orient2d(b, c, d));
  double p[5][3] = {{1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, 0, -1}, {0, -1, 0}};
  ASSERT_GT(geom::orient3d(p[0], p[1], p[2], p[3]), 0);
  ASSERT_EQ(geom::insphere(p[0], p[1], p[2], p[3], p[4]), 0);
  EXPECT_EQ(geom::insphere_sos(p[0], p[1], p[2], p[3], p[4], 0, 1, 2, 3, 4), -1);
}

TEST(Sos, CollinearAndCoincidentOrient2d) {
  double a[2] = {0, 0}, b[2] = {1, 1}, c[2] = {2, 2};
  int s = geom::orient2d_sos(a, b, c, 0, 1, 2);
  EXPECT_NE(s, 0);
  EXPECT_EQ(geom::orient2d_sos(c, b, a, 2, 1, 0), -s);
  // Three copies of one point with distinct indices are still decided.
  EXPECT_NE(geom::orient2d_sos(a, a, a, 0, 1, 2), 0);
  EXPECT_EQ(geom::orient2d_sos(a, a, a, 0, 1, 2), -geom::orient2d_sos(a, a, a, 1, 0, 2));
  // The same point passed twice (same index) is genuinely degenerate.
  EXPECT_EQ(geom::orient2d_sos(a, a, b, 0, 0, 1), 0);
}

}  // namespace
