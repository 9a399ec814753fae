// Exact fallbacks of the predicates. Every determinant is expanded over exact coordinate
// differences (two-component expansions), so the expansion lengths are bounded at compile
// time; zero components are dropped as they appear, which keeps the common degenerate
// inputs (integer grids, where every difference is exact) short.

#include <geom/predicates/expansion.h>
#include <geom/predicates/predicates.h>

#include <algorithm>
#include <utility>

namespace geom {
namespace detail {

int expansion_sum(int elen, const double* e, int flen, const double* f, double* h) {
  if (elen == 0) {
    std::copy(f, f + flen, h);
    return flen;
  }
  if (flen == 0) {
    std::copy(e, e + elen, h);
    return elen;
  }
  // Merge by increasing magnitude, then carry a running sum upward; each rounding error
  // that falls out is a component of the result (Shewchuk's Fast-Expansion-Sum).
  int ei = 0, fi = 0, hi = 0;
  const int total = elen + flen;
  auto take = [&]() {
    if (ei < elen && (fi >= flen || std::fabs(e[ei]) < std::fabs(f[fi]))) return e[ei++];
    return f[fi++];
  };
  double q = take();
  double qnew, err;
  if (ei + fi < total) {
    double g = take();
    fast_two_sum(g, q, qnew, err);
    q = qnew;
    if (err != 0) h[hi++] = err;
    while (ei + fi < total) {
      g = take();
      two_sum(q, g, qnew, err);
      q = qnew;
      if (err != 0) h[hi++] = err;
    }
  }
  if (q != 0) h[hi++] = q;
  return hi;
}

int expansion_scale(int elen, const double* e, double b, double* h) {
  if (elen == 0 || b == 0) return 0;
  int hi = 0;
  double q, err, p1, p0, s;
  two_product(e[0], b, q, err);
  if (err != 0) h[hi++] = err;
  for (int i = 1; i < elen; ++i) {
    two_product(e[i], b, p1, p0);
    two_sum(q, p0, s, err);
    if (err != 0) h[hi++] = err;
    fast_two_sum(p1, s, q, err);
    if (err != 0) h[hi++] = err;
  }
  if (q != 0) h[hi++] = q;
  return hi;
}

namespace {

using E2 = Expansion<2>;

// x1 * y2 - x2 * y1 over two-component expansions.
Expansion<16> cross(const E2& x1, const E2& y2, const E2& x2, const E2& y1) {
  Expansion<8> l, r;
  mul(x1, y2, l);
  mul(x2, y1, r);
  Expansion<16> out;
  sub(l, r, out);
  return out;
}

// Second stage: evaluate the determinant in doubles while checking that no operation
// rounds (every difference, product and sum has a zero error term). On integer grids and
// other low-precision input this settles the sign - typically zero - without expansions.
struct ExactDouble {
  bool ok = true;
  double sub(double a, double b) {
    double x, y;
    two_diff(a, b, x, y);
    ok &= y == 0;
    return x;
  }
  double add(double a, double b) {
    double x, y;
    two_sum(a, b, x, y);
    ok &= y == 0;
    return x;
  }
  double mul(double a, double b) {
    double x = a * b;
    ok &= std::fma(a, b, -x) == 0;
    return x;
  }
};

}  // namespace

int orient2d_exact(const double* a, const double* b, const double* c) {
  {
    ExactDouble q;
    double l = q.mul(q.sub(a[0], c[0]), q.sub(b[1], c[1]));
    double r = q.mul(q.sub(a[1], c[1]), q.sub(b[0], c[0]));
    double det = q.sub(l, r);
    if (q.ok) return sign_of(det);
  }
  E2 acx = diff(a[0], c[0]), bcy = diff(b[1], c[1]);
  E2 acy = diff(a[1], c[1]), bcx = diff(b[0], c[0]);
  return cross(acx, bcy, bcx, acy).sign();
}

int orient3d_exact(const double* a, const double* b, const double* c, const double* d) {
  {
    ExactDouble q;
    double adx = q.sub(a[0], d[0]), bdx = q.sub(b[0], d[0]), cdx = q.sub(c[0], d[0]);
    double ady = q.sub(a[1], d[1]), bdy = q.sub(b[1], d[1]), cdy = q.sub(c[1], d[1]);
    double adz = q.sub(a[2], d[2]), bdz = q.sub(b[2], d[2]), cdz = q.sub(c[2], d[2]);
    double m1 = q.sub(q.mul(bdx, cdy), q.mul(cdx, bdy));
    double m2 = q.sub(q.mul(cdx, ady), q.mul(adx, cdy));
    double m3 = q.sub(q.mul(adx, bdy), q.mul(bdx, ady));
    double det = q.add(q.add(q.mul(adz, m1), q.mul(bdz, m2)), q.mul(cdz, m3));
    if (q.ok) return sign_of(det);
  }
  E2 adx = diff(a[0], d[0]), bdx = diff(b[0], d[0]), cdx = diff(c[0], d[0]);
  E2 ady = diff(a[1], d[1]), bdy = diff(b[1], d[1]), cdy = diff(c[1], d[1]);
  E2 adz = diff(a[2], d[2]), bdz = diff(b[2], d[2]), cdz = diff(c[2], d[2]);
  Expansion<16> bc = cross(bdx, cdy, cdx, bdy);
  Expansion<16> ca = cross(cdx, ady, adx, cdy);
  Expansion<16> ab = cross(adx, bdy, bdx, ady);
  Expansion<64> t1, t2, t3;
  mul(bc, adz, t1);
  mul(ca, bdz, t2);
  mul(ab, cdz, t3);
  Expansion<128> s12;
  add(t1, t2, s12);
  Expansion<192> det;
  add(s12, t3, det);
  return det.sign();
}

int incircle_exact(const double* a, const double* b, const double* c, const double* d) {
  {
    ExactDouble q;
    double adx = q.sub(a[0], d[0]), bdx = q.sub(b[0], d[0]), cdx = q.sub(c[0], d[0]);
    double ady = q.sub(a[1], d[1]), bdy = q.sub(b[1], d[1]), cdy = q.sub(c[1], d[1]);
    double al = q.add(q.mul(adx, adx), q.mul(ady, ady));
    double bl = q.add(q.mul(bdx, bdx), q.mul(bdy, bdy));
    double cl = q.add(q.mul(cdx, cdx), q.mul(cdy, cdy));
    double m1 = q.sub(q.mul(bdx, cdy), q.mul(cdx, bdy));
    double m2 = q.sub(q.mul(cdx, ady), q.mul(adx, cdy));
    double m3 = q.sub(q.mul(adx, bdy), q.mul(bdx, ady));
    double det = q.add(q.add(q.mul(al, m1), q.mul(bl, m2)), q.mul(cl, m3));
    if (q.ok) return sign_of(det);
  }
  E2 adx = diff(a[0], d[0]), bdx = diff(b[0], d[0]), cdx = diff(c[0], d[0]);
  E2 ady = diff(a[1], d[1]), bdy = diff(b[1], d[1]), cdy = diff(c[1], d[1]);
  auto lift = [](const E2& x, const E2& y, Expansion<16>& out) {
    Expansion<8> xx, yy;
    mul(x, x, xx);
    mul(y, y, yy);
    add(xx, yy, out);
  };
  Expansion<16> al, bl, cl;
  lift(adx, ady, al);
  lift(bdx, bdy, bl);
  lift(cdx, cdy, cl);
  Expansion<16> bc = cross(bdx, cdy, cdx, bdy);
  Expansion<16> ca = cross(cdx, ady, adx, cdy);
  Expansion<16> ab = cross(adx, bdy, bdx, ady);
  Expansion<512> t1, t2, t3;
  mul(al, bc, t1);
  mul(bl, ca, t2);
  mul(cl, ab, t3);
  Expansion<1024> s12;
  add(t1, t2, s12);
  Expansion<1536> det;
  add(s12, t3, det);
  return det.sign();
}

double insphere_filter(const double* a, const double* b, const double* c, const double* d,
                       const double* e, bool& sure) {
  double aex = a[0] - e[0], bex = b[0] - e[0], cex = c[0] - e[0], dex = d[0] - e[0];
  double aey = a[1] - e[1], bey = b[1] - e[1], cey = c[1] - e[1], dey = d[1] - e[1];
  double aez = a[2] - e[2], bez = b[2] - e[2], cez = c[2] - e[2], dez = d[2] - e[2];
  double aexbey = aex * bey, bexaey = bex * aey;
  double bexcey = bex * cey, cexbey = cex * bey;
  double cexdey = cex * dey, dexcey = dex * cey;
  double dexaey = dex * aey, aexdey = aex * dey;
  double aexcey = aex * cey, cexaey = cex * aey;
  double bexdey = bex * dey, dexbey = dex * bey;
  double ab = aexbey - bexaey, bc = bexcey - cexbey, cd = cexdey - dexcey;
  double da = dexaey - aexdey, ac = aexcey - cexaey, bd = bexdey - dexbey;
  double abc = aez * bc - bez * ac + cez * ab;
  double bcd = bez * cd - cez * bd + dez * bc;
  double cda = cez * da + dez * ac + aez * cd;
  double dab = dez * ab + aez * bd + bez * da;
  double alift = aex * aex + aey * aey + aez * aez;
  double blift = bex * bex + bey * bey + bez * bez;
  double clift = cex * cex + cey * cey + cez * cez;
  double dlift = dex * dex + dey * dey + dez * dez;
  double det = (dlift * abc - clift * dab) + (blift * cda - alift * bcd);
  double pab = std::fabs(aexbey) + std::fabs(bexaey), pbc = std::fabs(bexcey) + std::fabs(cexbey);
  double pcd = std::fabs(cexdey) + std::fabs(dexcey), pda = std::fabs(dexaey) + std::fabs(aexdey);
  double pac = std::fabs(aexcey) + std::fabs(cexaey), pbd = std::fabs(bexdey) + std::fabs(dexbey);
  double aezp = std::fabs(aez), bezp = std::fabs(bez), cezp = std::fabs(cez), dezp = std::fabs(dez);
  double perm = (cezp * pab + bezp * pac + aezp * pbc) * dlift +
                (dezp * pab + aezp * pbd + bezp * pda) * clift +
                (dezp * pac + cezp * pda + aezp * pcd) * blift +
                (dezp * pbc + cezp * pbd + bezp * pcd) * alift;
  sure = std::fabs(det) > kInsphereBound * perm;
  return det;
}

int insphere_exact(const double* a, const double* b, const double* c, const double* d,
                   const double* e) {
  E2 aex = diff(a[0], e[0]), bex = diff(b[0], e[0]), cex = diff(c[0], e[0]), dex = diff(d[0], e[0]);
  E2 aey = diff(a[1], e[1]), bey = diff(b[1], e[1]), cey = diff(c[1], e[1]), dey = diff(d[1], e[1]);
  E2 aez = diff(a[2], e[2]), bez = diff(b[2], e[2]), cez = diff(c[2], e[2]), dez = diff(d[2], e[2]);
  Expansion<16> ab = cross(aex, bey, bex, aey), bc = cross(bex, cey, cex, bey);
  Expansion<16> cd = cross(cex, dey, dex, cey), da = cross(dex, aey, aex, dey);
  Expansion<16> ac = cross(aex, cey, cex, aey), bd = cross(bex, dey, dex, bey);
  // s1 * x - s2 * y + s3 * z over 2x2 minors x, y, z and heights s1, s2, s3.
  auto minor3 = [](const Expansion<16>& x, const E2& s1, const Expansion<16>& y, const E2& s2,
                   const Expansion<16>& z, const E2& s3, Expansion<192>& out) {
    Expansion<64> t1, t2, t3;
    mul(x, s1, t1);
    mul(y, s2, t2);
    mul(z, s3, t3);
    t2.negate();
    Expansion<128> s12;
    add(t1, t2, s12);
    add(s12, t3, out);
  };
  Expansion<16> nac = ac, nbd = bd;
  nac.negate();
  nbd.negate();
  Expansion<192> abc, bcd, cda, dab;
  minor3(bc, aez, ac, bez, ab, cez, abc);   // aez*bc - bez*ac + cez*ab
  minor3(cd, bez, bd, cez, bc, dez, bcd);   // bez*cd - cez*bd + dez*bc
  minor3(da, cez, nac, dez, cd, aez, cda);  // cez*da + dez*ac + aez*cd
  minor3(ab, dez, nbd, aez, da, bez, dab);  // dez*ab + aez*bd + bez*da
  auto lift = [](const E2& x, const E2& y, const E2& z, Expansion<24>& out) {
    Expansion<8> xx, yy, zz;
    mul(x, x, xx);
    mul(y, y, yy);
    mul(z, z, zz);
    Expansion<16> s;
    add(xx, yy, s);
    add(s, zz, out);
  };
  Expansion<24> al, bl, cl, dl;
  lift(aex, aey, aez, al);
  lift(bex, bey, bez, bl);
  lift(cex, cey, cez, cl);
  lift(dex, dey, dez, dl);
  auto& t1 = scratch<9216, 1>();
  auto& t2 = scratch<9216, 2>();
  auto& t3 = scratch<9216, 3>();
  auto& t4 = scratch<9216, 4>();
  mul(abc, dl, t1);
  mul(dab, cl, t2);
  mul(cda, bl, t3);
  mul(bcd, al, t4);
  t2.negate();
  t4.negate();
  auto& s12 = scratch<18432, 1>();
  auto& s34 = scratch<18432, 2>();
  add(t1, t2, s12);
  add(t3, t4, s34);
  auto& det = scratch<36864, 1>();
  add(s12, s34, det);
  return det.sign();
}

}  // namespace detail

namespace {

// Sorts the entries by decreasing index and reports the parity of the permutation used.
template <int N>
bool sort_by_index_desc(const double* (&p)[N], std::int64_t (&idx)[N]) {
  bool odd = false;
  for (int i = 1; i < N; ++i)
    for (int j = i; j > 0 && idx[j] > idx[j - 1]; --j) {
      std::swap(idx[j], idx[j - 1]);
      std::swap(p[j], p[j - 1]);
      odd = !odd;
    }
  return odd;
}

}  // namespace

int orient2d_sos(const double* a, const double* b, const double* c, std::int64_t ia,
                 std::int64_t ib, std::int64_t ic) {
  int s = orient2d(a, b, c);
  if (s != 0) return s;
  const double* p[3] = {a, b, c};
  std::int64_t idx[3] = {ia, ib, ic};
  bool odd = sort_by_index_desc(p, idx);
  if (idx[0] == idx[1] || idx[1] == idx[2]) return 0;
  // Point with rank k moves by (d_k, d'_k), d_0 >> d_1 >> d_2 >> d'_0 >> d'_1 >> d'_2 (powers
  // eps^1, eps^2, eps^4, eps^8, ...). The leading non-vanishing terms of the determinant
  // det[x y 1] are, in order: d_0 (qy - ry), d_1 (ry - py), d_2 (py - qy), d'_0 (rx - qx),
  // and d'_0 d_1 with coefficient -1; differences of doubles compare exactly.
  const double *P = p[0], *Q = p[1], *R = p[2];
  int r = 0;
  if (Q[1] != R[1])
    r = Q[1] > R[1] ? 1 : -1;
  else if (R[1] != P[1])
    r = R[1] > P[1] ? 1 : -1;
  else if (P[1] != Q[1])
    r = P[1] > Q[1] ? 1 : -1;
  else if (R[0] != Q[0])
    r = R[0] > Q[0] ? 1 : -1;
  else
    r = -1;
  return odd ? -r : r;
}

int incircle_sos(const double* a, const double* b, const double* c, const double* d,
                 std::int64_t ia, std::int64_t ib, std::int64_t ic, std::int64_t id) {
  int s = incircle(a, b, c, d);
  if (s != 0) return s;
  return detail::incircle_perturbed(a, b, c, d, ia, ib, ic, id);
}

int detail::incircle_perturbed(const double* a, const double* b, const double* c, const double* d,
                               std::int64_t ia, std::int64_t ib, std::int64_t ic, std::int64_t id) {
  // Raising point k's lift by e_k changes the determinant by e_k times its cofactor; the
  // point with the largest index moves most, so the first non-zero cofactor in decreasing
  // index order decides.
  struct Term {
    std::int64_t idx;
    int which;
  } t[4] = {{ia, 0}, {ib, 1}, {ic, 2}, {id, 3}};
  std::sort(t, t + 4, [](const Term& x, const Term& y) { return x.idx > y.idx; });
  for (const Term& term : t) {
    int v = 0;
    switch (term.which) {
      case 3:
        v = -orient2d(a, b, c);
        break;
      case 2:
        v = orient2d(a, b, d);
        break;
      case 1:
        v = -orient2d(a, c, d);
        break;
      default:
        v = orient2d(b, c, d);
        break;
    }
    if (v != 0) return v;
  }
  return 0;
}

int insphere_sos(const double* a, const double* b, const double* c, const double* d,
                 const double* e, std::int64_t ia, std::int64_t ib, std::int64_t ic,
                 std::int64_t id, std::int64_t ie) {
  int s = insphere(a, b, c, d, e);
  if (s != 0) return s;
  struct Term {
    std::int64_t idx;
    int which;
  } t[5] = {{ia, 0}, {ib, 1}, {ic, 2}, {id, 3}, {ie, 4}};
  std::sort(t, t + 5, [](const Term& x, const Term& y) { return x.idx > y.idx; });
  for (const Term& term : t) {
    int v = 0;
    switch (term.which) {
      case 4:
        v = -orient3d(a, b, c, d);
        break;
      case 3:
        v = orient3d(a, b, c, e);
        break;
      case 2:
        v = -orient3d(a, b, d, e);
        break;
      case 1:
        v = orient3d(a, c, d, e);
        break;
      default:
        v = -orient3d(b, c, d, e);
        break;
    }
    if (v != 0) return v;
  }
  return 0;
}

}  // namespace geom
