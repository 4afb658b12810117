// B-spline basis functions and their derivatives (Piegl and Tiller, The NURBS Book, A2.1 and
// A2.3), on fixed-size stack arrays so that evaluation never touches the heap.
#pragma once

#include <algorithm>
#include <type_traits>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace extremal {

// Highest degree the kernel evaluates. Real IGES files carry degree 12; 25 leaves room.
constexpr int k_max_degree = 25;

namespace internal {

// Index k of the knot span [t_k, t_{k+1}) holding t, with p <= k <= n - 1 where n is the number
// of control points. The domain's right end maps to the last non-empty span.
inline int find_span(const double* knots, int n, int p, double t) {
  if (n == p + 1) return p;  // one span (a Bezier piece): the common case in the hot loops
  if (t >= knots[n]) {
    int k = n - 1;
    while (k > p && knots[k] >= knots[k + 1]) --k;
    return k;
  }
  if (t <= knots[p]) {
    int k = p;
    while (k < n - 1 && knots[k + 1] <= t) ++k;
    return k;
  }
  // Largest k in [p, n-1] with knots[k] <= t.
  const double* it = std::upper_bound(knots + p, knots + n, t);
  return static_cast<int>(it - knots) - 1;
}

// Basis values and derivatives up to order nd (nd <= 2) at t in span k:
// ders[r][j] = d^r/dt^r N_{k-p+j,p}(t), j = 0..p.
struct Basis_derivatives {
  double ders[3][k_max_degree + 1];
};

#if defined(__SSE2__)
// Two doubles in one SSE2 register, one per lane; every operation rounds each lane exactly as
// the scalar operation would.
struct Double_pair {
  __m128d x;
  static Double_pair Constant(double c) { return {_mm_set1_pd(c)}; }
  double first() const { return _mm_cvtsd_f64(x); }
  double second() const { return _mm_cvtsd_f64(_mm_unpackhi_pd(x, x)); }
};
inline Double_pair operator+(Double_pair a, Double_pair b) { return {_mm_add_pd(a.x, b.x)}; }
inline Double_pair operator-(Double_pair a, Double_pair b) { return {_mm_sub_pd(a.x, b.x)}; }
inline Double_pair operator*(Double_pair a, Double_pair b) { return {_mm_mul_pd(a.x, b.x)}; }
inline Double_pair operator/(Double_pair a, Double_pair b) { return {_mm_div_pd(a.x, b.x)}; }
inline Double_pair operator-(Double_pair a) { return {_mm_xor_pd(a.x, _mm_set1_pd(-0.0))}; }
inline Double_pair& operator+=(Double_pair& a, Double_pair b) { return a = a + b; }
inline Double_pair& operator*=(Double_pair& a, double b) {
  return a = a * Double_pair::Constant(b);
}
#endif

template <class Real>
inline Real real_constant(double c) {
  if constexpr (std::is_same_v<Real, double>)
    return c;
  else
    return Real::Constant(c);
}

// The algorithm (A2.3) for a degree known at compile time (Fixed > 0: arrays sized to it, loops
// the compiler unrolls) or at run time (Fixed == 0), on Real = double or on Real = Double_pair,
// which runs two bases of the same degree side by side, one per SIMD lane.
// knot(i) is knot k + i of the span k (per lane). Every variant does the same operations in the
// same order, and SIMD lanes round exactly like scalars, so all give identical results.
// ders[r * stride + j] receives d^r/dt^r N_{k-p+j,p}(t).
template <int Fixed, class Real, class Knot>
inline void basis_recurrence(const Knot& knot, int p_run, const Real& t, int nd, Real* ders,
                             int stride) {
  const int p = Fixed > 0 ? Fixed : p_run;
  constexpr int cap = Fixed > 0 ? Fixed : k_max_degree;
  Real left[cap + 1];
  Real right[cap + 1];
  // ndu[j][r]: upper triangle holds basis functions, lower triangle knot differences.
  Real ndu[cap + 1][cap + 1];
  ndu[0][0] = real_constant<Real>(1.0);
  for (int j = 1; j <= p; ++j) {
    left[j] = t - knot(1 - j);
    right[j] = knot(j) - t;
    Real saved = real_constant<Real>(0.0);
    for (int r = 0; r < j; ++r) {
      ndu[j][r] = right[r + 1] + left[j - r];
      const Real temp = ndu[r][j - 1] / ndu[j][r];
      ndu[r][j] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    ndu[j][j] = saved;
  }
  for (int j = 0; j <= p; ++j) ders[j] = ndu[j][p];
  for (int kk = p + 1; kk <= nd; ++kk)  // derivatives above the degree vanish
    for (int j = 0; j <= p; ++j) ders[kk * stride + j] = real_constant<Real>(0.0);
  nd = std::min(nd, p);
  if (nd == 0) return;

  // Every entry read was written first; the initialiser only quiets -Wmaybe-uninitialized.
  Real a[2][cap + 1] = {};
  for (int r = 0; r <= p; ++r) {
    int s1 = 0, s2 = 1;
    a[0][0] = real_constant<Real>(1.0);
    for (int kk = 1; kk <= nd; ++kk) {
      Real d = real_constant<Real>(0.0);
      const int rk = r - kk, pk = p - kk;
      if (r >= kk) {
        a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
        d = a[s2][0] * ndu[rk][pk];
      }
      const int j1 = (rk >= -1) ? 1 : -rk;
      const int j2 = (r - 1 <= pk) ? kk - 1 : p - r;
      for (int j = j1; j <= j2; ++j) {
        a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][rk + j];
        d += a[s2][j] * ndu[rk + j][pk];
      }
      if (r <= pk) {
        a[s2][kk] = -a[s1][kk - 1] / ndu[pk + 1][r];
        d += a[s2][kk] * ndu[r][pk];
      }
      ders[kk * stride + r] = d;
      std::swap(s1, s2);
    }
  }
  double factor = p;
  for (int kk = 1; kk <= nd; ++kk) {
    for (int j = 0; j <= p; ++j) ders[kk * stride + j] *= factor;
    factor *= (p - kk);
  }
}

// Whether span k of a degree-p knot vector is a Bezier segment: both its ends have multiplicity
// p (clamped ends, the double knots of conics, single-span patches). The B-spline basis on it
// is then the Bernstein basis of [knots[k], knots[k + 1]].
inline bool is_bezier_span(const double* knots, int k, int p) {
  return knots[k - p + 1] == knots[k] && knots[k + 1] == knots[k + p];
}

// The Bernstein basis of degree p at s in [0, 1] and its derivatives up to order nd (nd <= 2)
// with respect to t = a + s h, where inv_h = 1 / h: the triangle of de Casteljau's algorithm,
// whose last three rows give the values and, by differences, the derivatives. No division;
// far fewer operations than the general recurrence. Same Fixed / Real scheme as
// basis_recurrence; ders[r * stride + j] receives the r-th derivative of basis function j.
template <int Fixed, class Real>
inline void bernstein_derivatives(int p_run, const Real& s, const Real& inv_h, int nd, Real* ders,
                                  int stride) {
  const int p = Fixed > 0 ? Fixed : p_run;
  constexpr int cap = Fixed > 0 ? Fixed : k_max_degree;
  const Real zero = real_constant<Real>(0.0);
  const Real r = real_constant<Real>(1.0) - s;
  Real row[cap + 1];
  Real row_p1[cap + 1];  // degree p - 1
  Real row_p2[cap + 1];  // degree p - 2
  row[0] = real_constant<Real>(1.0);
  for (int d = 1; d <= p; ++d) {
    if (d == p - 1)
      for (int j = 0; j < d; ++j) row_p2[j] = row[j];
    if (d == p)
      for (int j = 0; j < d; ++j) row_p1[j] = row[j];
    Real before = zero;  // entry j - 1 of the previous row
    for (int j = 0; j < d; ++j) {
      const Real here = row[j];
      row[j] = r * here + s * before;
      before = here;
    }
    row[d] = s * before;
  }
  for (int j = 0; j <= p; ++j) ders[j] = row[j];
  for (int kk = 1; kk <= nd; ++kk)
    for (int j = 0; j <= p; ++j) ders[kk * stride + j] = zero;
  if (nd >= 1 && p >= 1) {
    // d/dt B_j^p = p / h (B_{j-1}^{p-1} - B_j^{p-1}).
    const Real f = real_constant<Real>(p) * inv_h;
    for (int j = 0; j <= p; ++j) {
      const Real left = j >= 1 ? row_p1[j - 1] : zero;
      const Real right = j <= p - 1 ? row_p1[j] : zero;
      ders[stride + j] = f * (left - right);
    }
  }
  if (nd >= 2 && p >= 2) {
    // d2/dt2 B_j^p = p (p - 1) / h^2 (B_{j-2}^{p-2} - 2 B_{j-1}^{p-2} + B_j^{p-2}).
    const Real f = real_constant<Real>(p * (p - 1)) * inv_h * inv_h;
    for (int j = 0; j <= p; ++j) {
      const Real a = j >= 2 ? row_p2[j - 2] : zero;
      const Real b = j >= 1 && j - 1 <= p - 2 ? row_p2[j - 1] : zero;
      const Real c = j <= p - 2 ? row_p2[j] : zero;
      ders[2 * stride + j] = f * ((a - (b + b)) + c);
    }
  }
}

// Basis values and derivatives up to order nd (nd <= 2) at t in span k, degree p (Fixed > 0:
// known at compile time).
template <int Fixed>
inline void basis_derivatives_impl(const double* knots, int k, int p, double t, int nd,
                                   Basis_derivatives& out) {
  if (Fixed > 0 && is_bezier_span(knots, k, p)) {
    // s by division, not by 1 / h: exactly 1 at the span's right end (0 at its left).
    const double h = knots[k + 1] - knots[k];
    bernstein_derivatives<Fixed>(p, (t - knots[k]) / h, 1.0 / h, nd, &out.ders[0][0],
                                 k_max_degree + 1);
    return;
  }
  basis_recurrence<Fixed>([=](int i) { return knots[k + i]; }, p, t, nd, &out.ders[0][0],
                          k_max_degree + 1);
}

// Two bases of the same degree P at once, u in span ku and v in span kv: with SSE2 one per
// lane, the same results as two basis_derivatives_impl<P> calls in fewer instructions (and half
// the divisions, which dominate).
#if defined(__SSE2__)
// The two bases side by side, as they come out of the lanes: ders[r * (P + 1) + j] holds the
// r-th derivative of basis function j along u (first lane) and along v (second lane).
template <int P>
inline void basis_derivative_pairs(const double* knots_u, int ku, double u,
                                   const double* knots_v, int kv, double v, int nd,
                                   Double_pair* ders) {
  static_assert(P > 0, "the pair runs compile-time degrees only");
  if (is_bezier_span(knots_u, ku, P) && is_bezier_span(knots_v, kv, P)) {
    const Double_pair a{_mm_set_pd(knots_v[kv], knots_u[ku])};
    const Double_pair h = Double_pair{_mm_set_pd(knots_v[kv + 1], knots_u[ku + 1])} - a;
    // s by division, not by 1 / h: exactly 1 at the span's right end (0 at its left).
    bernstein_derivatives<P>(P, (Double_pair{_mm_set_pd(v, u)} - a) / h,
                             Double_pair::Constant(1.0) / h, nd, ders, P + 1);
  } else {
    basis_recurrence<P>(
        [=](int i) { return Double_pair{_mm_set_pd(knots_v[kv + i], knots_u[ku + i])}; }, P,
        Double_pair{_mm_set_pd(v, u)}, nd, ders, P + 1);
  }
}
#endif

template <int P>
inline void basis_derivatives_pair(const double* knots_u, int ku, double u, const double* knots_v,
                                   int kv, double v, int nd, Basis_derivatives& out_u,
                                   Basis_derivatives& out_v) {
  static_assert(P > 0, "the pair runs compile-time degrees only");
#if defined(__SSE2__)
  Double_pair ders[3 * (P + 1)];
  basis_derivative_pairs<P>(knots_u, ku, u, knots_v, kv, v, nd, ders);
  for (int r = 0; r <= std::min(nd, 2); ++r)
    for (int j = 0; j <= P; ++j) {
      out_u.ders[r][j] = ders[r * (P + 1) + j].first();
      out_v.ders[r][j] = ders[r * (P + 1) + j].second();
    }
#else
  basis_derivatives_impl<P>(knots_u, ku, P, u, nd, out_u);
  basis_derivatives_impl<P>(knots_v, kv, P, v, nd, out_v);
#endif
}

// Degrees 1 to 3 (planes, conics, bicubics) take the compile-time version.
inline void basis_derivatives(const double* knots, int k, int p, double t, int nd,
                              Basis_derivatives& out) {
  switch (p) {
    case 1: return basis_derivatives_impl<1>(knots, k, p, t, nd, out);
    case 2: return basis_derivatives_impl<2>(knots, k, p, t, nd, out);
    case 3: return basis_derivatives_impl<3>(knots, k, p, t, nd, out);
    default: return basis_derivatives_impl<0>(knots, k, p, t, nd, out);
  }
}

}  // namespace internal
}  // namespace extremal
