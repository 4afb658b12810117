// Helpers shared by the NURBS kernel tests: seeded random numbers, polynomial curves and patches
// with known answers (exact B-spline form through blossoms), random knot vectors, finite
// differences that respect knot spans, and the closed-form parametrisation of the rational arcs
// the shape constructors use. Header-only.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <limits>
#include <random>
#include <vector>

#include "kernel/Nurbs_curve_3.h"
#include "kernel/Nurbs_surface_3.h"
#include "kernel/Types.h"

namespace extremal::test {

// ---------------------------------------------------------------------------------------------
// Seeds. The default is fixed so that ctest runs are deterministic; EXTREMAL_SEED=<n> (decimal or
// 0x-hex) overrides it. Every random test prints the seed it used and adds it to each failure.

inline std::uint64_t test_seed() {
  static const std::uint64_t seed = [] {
    std::uint64_t s = 20260917ULL;
    if (const char* env = std::getenv("EXTREMAL_SEED"); env && *env)
      s = std::strtoull(env, nullptr, 0);
    return s;
  }();
  return seed;
}

// Declares `std::mt19937_64 name` seeded with test_seed(), prints the seed and traces it.
#define EXTREMAL_SEEDED_RNG(name)                                                      \
  const std::uint64_t name##_seed = ::extremal::test::test_seed();                     \
  std::mt19937_64 name(name##_seed);                                                   \
  std::cout << "[   SEED   ] EXTREMAL_SEED=" << name##_seed << std::endl;              \
  ::testing::Test::RecordProperty("EXTREMAL_SEED", std::to_string(name##_seed));      \
  SCOPED_TRACE(::testing::Message() << "rerun with EXTREMAL_SEED=" << name##_seed)

inline double uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}
inline int uniform_int(std::mt19937_64& rng, int lo, int hi) {
  return std::uniform_int_distribution<int>(lo, hi)(rng);
}
inline Vec3 random_vec3(std::mt19937_64& rng, double lo = -1.0, double hi = 1.0) {
  return Vec3(uniform(rng, lo, hi), uniform(rng, lo, hi), uniform(rng, lo, hi));
}

constexpr double k_pi = 3.14159265358979323846;
constexpr double k_eps = std::numeric_limits<double>::epsilon();

// ---------------------------------------------------------------------------------------------
// Knot vectors.

// Clamped: p + 1 copies of lo and hi, `interior` random knots in between; with probability
// `repeat` a knot is repeated (multiplicity at most p).
inline std::vector<double> random_clamped_knots(std::mt19937_64& rng, int p, int n, double lo,
                                                double hi, double repeat = 0.25) {
  const int interior = n - p - 1;
  for (;;) {
    std::vector<double> inner;
    while (static_cast<int>(inner.size()) < interior) {
      const double t = lo + (hi - lo) * uniform(rng, 0.05, 0.95);
      int mult = 1;
      if (uniform(rng, 0.0, 1.0) < repeat) mult = uniform_int(rng, 1, p);
      mult = std::min(mult, interior - static_cast<int>(inner.size()));
      for (int m = 0; m < mult; ++m) inner.push_back(t);
    }
    std::sort(inner.begin(), inner.end());
    std::vector<double> k(p + 1, lo);
    k.insert(k.end(), inner.begin(), inner.end());
    k.insert(k.end(), p + 1, hi);
    // No tiny spans: finite differences need room inside each one.
    bool ok = true;
    for (std::size_t i = 0; i + 1 < k.size(); ++i)
      ok = ok && (k[i + 1] == k[i] || k[i + 1] - k[i] > 0.1 * (hi - lo) / (interior + 1));
    if (ok) return k;
  }
}

// Unclamped: n + p + 1 knots with random positive gaps (some repeated, multiplicity at most p)
// starting at `start`.
inline std::vector<double> random_unclamped_knots(std::mt19937_64& rng, int p, int n,
                                                  double start, double mean_gap,
                                                  double repeat = 0.15) {
  for (;;) {
    std::vector<double> k;
    double t = start;
    while (static_cast<int>(k.size()) < n + p + 1) {
      int mult = 1;
      if (uniform(rng, 0.0, 1.0) < repeat) mult = uniform_int(rng, 1, p);
      for (int m = 0; m < mult && static_cast<int>(k.size()) < n + p + 1; ++m) k.push_back(t);
      t += mean_gap * uniform(rng, 0.5, 1.5);
    }
    if (k[p] < k[n]) return k;  // else the domain is empty: draw again
  }
}

inline std::vector<double> uniform_unclamped_knots(int p, int n, double start, double gap) {
  std::vector<double> k;
  for (int i = 0; i < n + p + 1; ++i) k.push_back(start + gap * i);
  return k;
}

// Parameters worth testing on a knot vector's domain [knots[p], knots[n]]: a dense uniform grid,
// every distinct knot inside the domain (ends included) and points just beside each knot.
inline std::vector<double> sample_parameters(const std::vector<double>& knots, int n, int p,
                                             int grid) {
  const double lo = knots[p], hi = knots[n];
  std::vector<double> t;
  for (int i = 0; i <= grid; ++i) t.push_back(lo + (hi - lo) * i / grid);
  t.back() = hi;
  for (int i = p; i <= n; ++i) {
    t.push_back(knots[i]);
    const double nudge = 1e-9 * (hi - lo);
    if (knots[i] - nudge >= lo) t.push_back(knots[i] - nudge);
    if (knots[i] + nudge <= hi) t.push_back(knots[i] + nudge);
    t.push_back(std::nextafter(knots[i], lo));
    t.push_back(std::nextafter(knots[i], hi));
  }
  t.erase(std::remove_if(t.begin(), t.end(), [&](double x) { return x < lo || x > hi; }),
          t.end());
  std::sort(t.begin(), t.end());
  t.erase(std::unique(t.begin(), t.end()), t.end());
  return t;
}

// Smallest non-empty knot span inside the domain.
inline double min_span(const std::vector<double>& knots, int n, int p) {
  double m = std::numeric_limits<double>::infinity();
  for (int i = p; i < n; ++i)
    if (knots[i + 1] > knots[i]) m = std::min(m, knots[i + 1] - knots[i]);
  return m;
}

// The knot span [lo, hi] whose polynomial piece evaluation uses at x: the last non-empty span
// starting at or before x (so a knot belongs to the span on its right, the domain's right end to
// the last span). Written independently of the kernel's find_span.
inline std::pair<double, double> piece_interval(const std::vector<double>& knots, int n, int p,
                                                double x) {
  int k = p;
  for (int i = p; i < n; ++i)
    if (knots[i] <= x && knots[i] < knots[i + 1]) k = i;
  return {knots[k], knots[k + 1]};
}

// ---------------------------------------------------------------------------------------------
// Polynomials with known answers.

inline double binomial(int n, int k) {
  double b = 1.0;
  for (int i = 1; i <= k; ++i) b = b * (n - k + i) / i;
  return b;
}

// Elementary symmetric polynomials e_0..e_m of xs (m = xs.size()).
inline std::vector<double> elementary_symmetric(const double* xs, int m) {
  std::vector<double> e(m + 1, 0.0);
  e[0] = 1.0;
  for (int i = 0; i < m; ++i)
    for (int k = i + 1; k >= 1; --k) e[k] += xs[i] * e[k - 1];
  return e;
}

// Blossom factors: the control points of a degree p polynomial sum_k a_k t^k on `knots` are
// P_i = sum_k a_k B[i][k] with B[i][k] = e_k(t_{i+1}, ..., t_{i+p}) / C(p, k) (polar forms;
// exact for any knot vector, clamped or not).
inline std::vector<std::vector<double>> blossom_factors(const std::vector<double>& knots, int n,
                                                        int p) {
  std::vector<std::vector<double>> B(n, std::vector<double>(p + 1));
  for (int i = 0; i < n; ++i) {
    const auto e = elementary_symmetric(knots.data() + i + 1, p);
    for (int k = 0; k <= p; ++k) B[i][k] = e[k] / binomial(p, k);
  }
  return B;
}

// f(t) = sum_k a[k] t^k with vector coefficients.
struct Polynomial_curve {
  std::vector<Vec3> a;
  int degree() const { return static_cast<int>(a.size()) - 1; }

  // Value (r = 0) or r-th derivative at t.
  Vec3 derivative(double t, int r) const {
    Vec3 s = Vec3::Zero();
    for (int k = degree(); k >= r; --k) {
      double c = 1.0;
      for (int i = 0; i < r; ++i) c *= (k - i);
      s = s * t + c * a[k];
    }
    return s;
  }
  // Bound on |derivative| and on its rounding: sum_k |a_k| k!/(k-r)! |t|^(k-r).
  double magnitude(double t, int r) const {
    double s = 0.0;
    for (int k = degree(); k >= r; --k) {
      double c = 1.0;
      for (int i = 0; i < r; ++i) c *= (k - i);
      s = s * std::abs(t) + c * a[k].norm();
    }
    return s;
  }
  Nurbs_curve_3 to_nurbs(const std::vector<double>& knots) const {
    const int p = degree(), n = static_cast<int>(knots.size()) - p - 1;
    const auto B = blossom_factors(knots, n, p);
    std::vector<Point_3> poles;
    for (int i = 0; i < n; ++i) {
      Vec3 P = Vec3::Zero();
      for (int k = 0; k <= p; ++k) P += B[i][k] * a[k];
      poles.push_back(to_point(P));
    }
    return Nurbs_curve_3(p, poles, knots);
  }
};

inline Polynomial_curve random_polynomial_curve(std::mt19937_64& rng, int degree) {
  Polynomial_curve c;
  for (int k = 0; k <= degree; ++k) c.a.push_back(random_vec3(rng));
  return c;
}

// f(u, v) = sum_{k,l} a[k][l] u^k v^l.
struct Polynomial_patch {
  int p = 0, q = 0;
  std::vector<std::vector<Vec3>> a;  // (p + 1) x (q + 1)

  // d^(ru + rv) f / du^ru dv^rv at (u, v).
  Vec3 derivative(double u, double v, int ru, int rv) const {
    Vec3 s = Vec3::Zero();
    for (int k = p; k >= ru; --k) {
      Vec3 row = Vec3::Zero();
      for (int l = q; l >= rv; --l) {
        double c = 1.0;
        for (int i = 0; i < rv; ++i) c *= (l - i);
        row = row * v + c * a[k][l];
      }
      double c = 1.0;
      for (int i = 0; i < ru; ++i) c *= (k - i);
      s = s * u + c * row;
    }
    return s;
  }
  double magnitude(double u, double v, int ru, int rv) const {
    double s = 0.0;
    for (int k = p; k >= ru; --k) {
      double row = 0.0;
      for (int l = q; l >= rv; --l) {
        double c = 1.0;
        for (int i = 0; i < rv; ++i) c *= (l - i);
        row = row * std::abs(v) + c * a[k][l].norm();
      }
      double c = 1.0;
      for (int i = 0; i < ru; ++i) c *= (k - i);
      s = s * std::abs(u) + c * row;
    }
    return s;
  }
  Nurbs_surface_3 to_nurbs(const std::vector<double>& knots_u,
                           const std::vector<double>& knots_v) const {
    const int nu = static_cast<int>(knots_u.size()) - p - 1;
    const int nv = static_cast<int>(knots_v.size()) - q - 1;
    const auto Bu = blossom_factors(knots_u, nu, p);
    const auto Bv = blossom_factors(knots_v, nv, q);
    std::vector<Point_3> poles;
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j) {
        Vec3 P = Vec3::Zero();
        for (int k = 0; k <= p; ++k)
          for (int l = 0; l <= q; ++l) P += (Bu[i][k] * Bv[j][l]) * a[k][l];
        poles.push_back(to_point(P));
      }
    return Nurbs_surface_3(p, q, nu, nv, poles, knots_u, knots_v);
  }
};

inline Polynomial_patch random_polynomial_patch(std::mt19937_64& rng, int p, int q) {
  Polynomial_patch f;
  f.p = p;
  f.q = q;
  f.a.assign(p + 1, std::vector<Vec3>(q + 1));
  for (auto& row : f.a)
    for (auto& c : row) c = random_vec3(rng);
  return f;
}

// ---------------------------------------------------------------------------------------------
// Finite differences inside one polynomial piece.

// d/dx g at x by a fourth-order stencil with Richardson extrapolation (h, h/2), central when
// [x - 2h, x + 2h] stays in [lo, hi], one-sided otherwise; h is cut so the stencil fits.
inline Vec3 finite_difference(const std::function<Vec3(double)>& g, double x, double lo,
                              double hi, double h0) {
  const double h = std::min(h0, (hi - lo) / 8.0);
  auto stencil = [&](double s) -> Vec3 {
    if (x - 2 * s >= lo && x + 2 * s <= hi)
      return (g(x - 2 * s) - 8.0 * g(x - s) + 8.0 * g(x + s) - g(x + 2 * s)) / (12.0 * s);
    const double d = (x + 4 * s <= hi) ? s : -s;  // forward, or backward at the right end
    return (-25.0 * g(x) + 48.0 * g(x + d) - 36.0 * g(x + 2 * d) + 16.0 * g(x + 3 * d) -
            3.0 * g(x + 4 * d)) /
           (12.0 * d);
  };
  return (16.0 * stencil(h / 2) - stencil(h)) / 15.0;
}

// Largest over smallest weight. A rational piece's derivatives grow like (degree * ratio / width)^k,
// so finite-difference steps scale with width / (degree * ratio) to keep truncation negligible.
inline double weight_ratio(const std::vector<double>& w) {
  const auto [lo, hi] = std::minmax_element(w.begin(), w.end());
  return *hi / *lo;
}

// Checks du, dv (against differences of p) and duu, duv, dvv (against differences of du and dv)
// at (u, v), and that order 0 and 1 evaluations agree with order 2. `size` and the domain widths
// set the scale of each derivative; `rtol` is relative to max(|value|, scale).
inline void expect_derivatives_match_differences(const Nurbs_surface_3& s, double u, double v,
                                                 double rtol, double size) {
  SCOPED_TRACE(::testing::Message() << "u = " << u << ", v = " << v);
  const auto& ku = s.knots_u();
  const auto& kv = s.knots_v();
  const int nu = s.number_of_poles_u(), nv = s.number_of_poles_v();
  const auto [ulo, uhi] = piece_interval(ku, nu, s.degree_u(), u);
  const auto [vlo, vhi] = piece_interval(kv, nv, s.degree_v(), v);
  const double wu = s.u_max() - s.u_min(), wv = s.v_max() - s.v_min();
  Surface_point sp, o0, o1;
  s.evaluate(u, v, sp, 2);
  s.evaluate(u, v, o0, 0);
  s.evaluate(u, v, o1, 1);
  EXPECT_EQ(o0.p, sp.p);
  EXPECT_EQ(o1.p, sp.p);
  EXPECT_EQ(o1.du, sp.du);
  EXPECT_EQ(o1.dv, sp.dv);

  auto at = [&](double uu, double vv) {
    Surface_point r;
    s.evaluate(uu, vv, r, 2);
    return r;
  };
  auto check = [&](const char* what, const Vec3& value, const Vec3& fd, double scale) {
    const double tol = rtol * std::max({value.norm(), fd.norm(), scale});
    EXPECT_LE((value - fd).norm(), tol)
        << what << " = " << value.transpose() << ", differences give " << fd.transpose();
  };
  const double ratio = weight_ratio(s.weights());
  const double hu = 1e-3 * wu / (s.degree_u() * ratio), hv = 1e-3 * wv / (s.degree_v() * ratio);
  const Vec3 du = finite_difference([&](double x) { return at(x, v).p; }, u, ulo, uhi, hu);
  const Vec3 dv = finite_difference([&](double y) { return at(u, y).p; }, v, vlo, vhi, hv);
  const Vec3 duu = finite_difference([&](double x) { return at(x, v).du; }, u, ulo, uhi, hu);
  const Vec3 duv1 = finite_difference([&](double y) { return at(u, y).du; }, v, vlo, vhi, hv);
  const Vec3 duv2 = finite_difference([&](double x) { return at(x, v).dv; }, u, ulo, uhi, hu);
  const Vec3 dvv = finite_difference([&](double y) { return at(u, y).dv; }, v, vlo, vhi, hv);
  check("du", sp.du, du, size / wu);
  check("dv", sp.dv, dv, size / wv);
  check("duu", sp.duu, duu, size / (wu * wu));
  check("duv (d/dv of du)", sp.duv, duv1, size / (wu * wv));
  check("duv (d/du of dv)", sp.duv, duv2, size / (wu * wv));
  check("dvv", sp.dvv, dvv, size / (wv * wv));
}

// The curve version: d1 against differences of p, d2 against differences of d1.
inline void expect_curve_derivatives_match_differences(const Nurbs_curve_3& c, double t,
                                                       double rtol, double size) {
  SCOPED_TRACE(::testing::Message() << "t = " << t);
  const auto [lo, hi] = piece_interval(c.knots(), c.number_of_poles(), c.degree(), t);
  const double w = c.domain_max() - c.domain_min();
  Curve_point cp, o0, o1;
  c.evaluate(t, cp, 2);
  c.evaluate(t, o0, 0);
  c.evaluate(t, o1, 1);
  EXPECT_EQ(o0.p, cp.p);
  EXPECT_EQ(o1.p, cp.p);
  EXPECT_EQ(o1.d1, cp.d1);
  auto at = [&](double x) {
    Curve_point r;
    c.evaluate(x, r, 2);
    return r;
  };
  const double h = 1e-3 * w / (c.degree() * weight_ratio(c.weights()));
  const Vec3 d1 = finite_difference([&](double x) { return at(x).p; }, t, lo, hi, h);
  const Vec3 d2 = finite_difference([&](double x) { return at(x).d1; }, t, lo, hi, h);
  EXPECT_LE((cp.d1 - d1).norm(), rtol * std::max({cp.d1.norm(), d1.norm(), size / w}))
      << "d1 = " << cp.d1.transpose() << ", differences give " << d1.transpose();
  EXPECT_LE((cp.d2 - d2).norm(), rtol * std::max({cp.d2.norm(), d2.norm(), size / (w * w)}))
      << "d2 = " << cp.d2.transpose() << ", differences give " << d2.transpose();
}

inline double bbox_size(const Bbox_3& b) {
  return std::max({b.xmax() - b.xmin(), b.ymax() - b.ymin(), b.zmax() - b.zmin()});
}

// Point within `slack` of the box.
inline bool box_contains(const Bbox_3& b, const Vec3& p, double slack) {
  return p.x() >= b.xmin() - slack && p.x() <= b.xmax() + slack && p.y() >= b.ymin() - slack &&
         p.y() <= b.ymax() + slack && p.z() >= b.zmin() - slack && p.z() <= b.zmax() + slack;
}

// ---------------------------------------------------------------------------------------------
// The rational quadratic quarter arcs of the shape constructors (middle weight cos(pi/4)) are
// not parametrised by angle: on a knot span [t0, t0 + pi/2] with local s = (t - t0) / (pi/2),
// the angle is theta = theta0 + pi/4 + 2 atan(tan(pi/8) (2 s - 1)). Returns theta and its first
// two derivatives in t.
struct Arc_angle {
  double theta, d1, d2;
};
inline Arc_angle arc_angle(double t, double t0, double theta0) {
  const double h = k_pi / 2, T = std::tan(k_pi / 8);
  const double s = (t - t0) / h, x = T * (2 * s - 1), den = 1 + x * x;
  Arc_angle a;
  a.theta = theta0 + k_pi / 4 + 2 * std::atan(x);
  a.d1 = 4 * T / den / h;
  a.d2 = -16 * T * T * x / (den * den) / (h * h);
  return a;
}

// Angle of a shape's circle parameter t in [0, 2 pi] (knots at multiples of pi/2), using the
// span the kernel evaluates in (a knot belongs to the span on its right, 2 pi to the last).
inline Arc_angle circle_angle(double t) {
  const double h = k_pi / 2;  // knots k * h, computed as the constructors do
  int k = 3;
  while (k > 0 && t < k * h) --k;
  return arc_angle(t, k * h, k * h);
}
// Latitude of a meridian parameter t in [-pi/2, pi/2] (knot at 0).
inline Arc_angle latitude_angle(double t) {
  const double t0 = t < 0.0 ? -k_pi / 2 : 0.0;
  return arc_angle(t, t0, t0);
}

}  // namespace extremal::test
