// B-spline basis functions and their derivatives (Piegl and Tiller, The NURBS Book, A2.1 and
// A2.3), on fixed-size stack arrays so that evaluation never touches the heap.
#pragma once

#include <algorithm>
#include <vector>

namespace extremal {

// Highest degree the kernel evaluates. Real IGES files carry degree 12; 25 leaves room.
constexpr int k_max_degree = 25;

namespace internal {

// Index k of the knot span [t_k, t_{k+1}) holding t, with p <= k <= n - 1 where n is the number
// of control points. The domain's right end maps to the last non-empty span.
inline int find_span(const double* knots, int n, int p, double t) {
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

// The algorithm, for a degree known at compile time (Fixed > 0: arrays sized to it, loops the
// compiler can unroll) or at run time (Fixed == 0). Both do the same operations in the same
// order, so their results are identical.
template <int Fixed>
inline void basis_derivatives_impl(const double* knots, int k, int p_run, double t, int nd,
                                   Basis_derivatives& out) {
  const int p = Fixed > 0 ? Fixed : p_run;
  constexpr int cap = Fixed > 0 ? Fixed : k_max_degree;
  double left[cap + 1];
  double right[cap + 1];
  // ndu[j][r]: upper triangle holds basis functions, lower triangle knot differences.
  double ndu[cap + 1][cap + 1];
  ndu[0][0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = t - knots[k + 1 - j];
    right[j] = knots[k + j] - t;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      ndu[j][r] = right[r + 1] + left[j - r];
      const double temp = ndu[r][j - 1] / ndu[j][r];
      ndu[r][j] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    ndu[j][j] = saved;
  }
  for (int j = 0; j <= p; ++j) out.ders[0][j] = ndu[j][p];
  for (int kk = p + 1; kk <= nd; ++kk)  // derivatives above the degree vanish
    for (int j = 0; j <= p; ++j) out.ders[kk][j] = 0.0;
  nd = std::min(nd, p);
  if (nd == 0) return;

  // Every entry read was written first; the initialiser only quiets -Wmaybe-uninitialized.
  double a[2][cap + 1] = {};
  for (int r = 0; r <= p; ++r) {
    int s1 = 0, s2 = 1;
    a[0][0] = 1.0;
    for (int kk = 1; kk <= nd; ++kk) {
      double d = 0.0;
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
      out.ders[kk][r] = d;
      std::swap(s1, s2);
    }
  }
  double factor = p;
  for (int kk = 1; kk <= nd; ++kk) {
    for (int j = 0; j <= p; ++j) out.ders[kk][j] *= factor;
    factor *= (p - kk);
  }
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
