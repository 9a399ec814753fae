#pragma once
/// \file
/// Floating-point expansion arithmetic: a real number held exactly as a sum of doubles
/// whose components do not overlap, stored in increasing order of magnitude. Sums and
/// products of expansions are exact; the sign of an expansion is the sign of its largest
/// component. Used only by the exact fallback of the predicates (geom::detail).
///
/// Pre: no intermediate overflow or underflow (the predicates document the coordinate range).
/// Ref: J. R. Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast Robust
///      Geometric Predicates", Discrete & Computational Geometry 18(3), 1997 (sections 2-3).

#include <array>
#include <cmath>
#include <type_traits>
#include <vector>

namespace geom::detail {

/// a + b = x + y exactly, with x = fl(a + b). No precondition on magnitudes.
inline void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  double bv = x - a;
  double av = x - bv;
  y = (a - av) + (b - bv);
}

/// a + b = x + y exactly. Pre: |a| >= |b| (or a == 0).
inline void fast_two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  y = b - (x - a);
}

/// a - b = x + y exactly.
inline void two_diff(double a, double b, double& x, double& y) {
  x = a - b;
  double bv = a - x;
  double av = x + bv;
  y = (a - av) + (bv - b);
}

/// a * b = x + y exactly (the fused multiply-add yields the rounding error of the product).
inline void two_product(double a, double b, double& x, double& y) {
  x = a * b;
  y = std::fma(a, b, -x);
}

/// Fixed-capacity expansion. Large capacities live on the heap so that the insphere
/// fallback does not need megabytes of stack.
template <int N>
struct Expansion {
  static constexpr int kCapacity = N;
  static constexpr bool kHeap = N > 2048;
  using Storage = std::conditional_t<kHeap, std::vector<double>, std::array<double, N>>;

  Expansion() {
    if constexpr (kHeap) v.resize(N);
  }
  int n = 0;
  Storage v;

  double* data() { return v.data(); }
  const double* data() const { return v.data(); }
  int sign() const { return n == 0 ? 0 : (v[n - 1] > 0 ? 1 : (v[n - 1] < 0 ? -1 : 0)); }
  void negate() {
    for (int i = 0; i < n; ++i) v[i] = -v[i];
  }
};

/// A per-thread expansion, allocated once: the large insphere intermediates would otherwise
/// cost a heap allocation (and page faults) per call. `Tag` separates simultaneous uses.
/// Only heap-backed sizes: the thread-local object is then a few bytes of static TLS.
template <int N, int Tag>
requires Expansion<N>::kHeap Expansion<N>
&scratch() {
  thread_local Expansion<N> s;
  return s;
}

/// h = e + f, zero components dropped. Returns the length of h. h may not alias e or f.
/// Pre: e and f are strongly nonoverlapping, ordered by increasing magnitude.
int expansion_sum(int elen, const double* e, int flen, const double* f, double* h);

/// h = b * e, zero components dropped. Returns the length of h. h may not alias e.
int expansion_scale(int elen, const double* e, double b, double* h);

/// The exact difference a - b as an expansion of at most two components.
inline Expansion<2> diff(double a, double b) {
  Expansion<2> r;
  double x, y;
  two_diff(a, b, x, y);
  if (y != 0) r.v[r.n++] = y;
  if (x != 0) r.v[r.n++] = x;
  return r;
}

template <int A, int B>
void add(const Expansion<A>& e, const Expansion<B>& f, Expansion<A + B>& out) {
  out.n = expansion_sum(e.n, e.data(), f.n, f.data(), out.data());
}

template <int A, int B>
void sub(const Expansion<A>& e, Expansion<B> f, Expansion<A + B>& out) {
  f.negate();
  out.n = expansion_sum(e.n, e.data(), f.n, f.data(), out.data());
}

/// out = e * f, using tmp as the second buffer.
template <int A, int B>
void mul_into(const Expansion<A>& e, const Expansion<B>& f, Expansion<2 * A * B>& out,
              Expansion<2 * A * B>& tmp) {
  out.n = 0;
  if (e.n == 0 || f.n == 0) return;
  Expansion<2 * A> scaled;
  double* cur = out.data();
  double* other = tmp.data();
  int n = 0;
  for (int j = 0; j < f.n; ++j) {
    scaled.n = expansion_scale(e.n, e.data(), f.v[j], scaled.data());
    n = expansion_sum(n, cur, scaled.n, scaled.data(), other);
    std::swap(cur, other);
  }
  if (cur != out.data())
    for (int i = 0; i < n; ++i) out.v[i] = cur[i];
  out.n = n;
}

/// out = e * f: the sum of e scaled by each component of f.
template <int A, int B>
void mul(const Expansion<A>& e, const Expansion<B>& f, Expansion<2 * A * B>& out) {
  if constexpr (Expansion<2 * A * B>::kHeap) {
    mul_into(e, f, out, scratch<2 * A * B, 0>());
  } else {
    Expansion<2 * A * B> tmp;
    mul_into(e, f, out, tmp);
  }
}

}  // namespace geom::detail
