// Evaluation of NURBS curves and surfaces: points of the analytic shapes on their surfaces,
// derivatives to order 2 against closed forms (shapes, polynomial patches and curves in exact
// B-spline form) and against finite differences (rational, high-degree, unclamped), at knots and
// domain ends included.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "kernel/Error.h"
#include "kernel/Nurbs_curve_3.h"
#include "kernel/Nurbs_surface_3.h"
#include "kernel/Rigid_pose_3.h"
#include "kernel/Shapes.h"
#include "kernel/internal/Tensor_product.h"
#include "tests/support/Nurbs_test_support.h"

namespace extremal {
namespace {

using namespace extremal::test;

// Longitude and latitude samples: a dense grid, every knot, and points just beside the poles and
// the seam.
std::vector<double> angle_samples(double lo, double hi, int grid) {
  std::vector<double> t;
  for (int i = 0; i <= grid; ++i) t.push_back(lo + (hi - lo) * i / grid);
  t.back() = hi;
  for (double d : {1e-15, 1e-12, 1e-9, 1e-6, 1e-3}) {
    t.push_back(lo + d);
    t.push_back(hi - d);
  }
  t.push_back(std::nextafter(lo, hi));
  t.push_back(std::nextafter(hi, lo));
  return t;
}

std::vector<double> knots_and_grid(const std::vector<double>& knots, int n, int p, int grid) {
  return sample_parameters(knots, n, p, grid);
}

// A parametrised analytic surface F(a, b) with its partials; a(u), b(v) map the NURBS parameters
// to the analytic ones.
struct Analytic_point {
  Vec3 F, Fa, Fb, Faa, Fab, Fbb;
};

Surface_point chain_rule(const Analytic_point& A, const Arc_angle& a, const Arc_angle& b) {
  Surface_point s;
  s.p = A.F;
  s.du = A.Fa * a.d1;
  s.dv = A.Fb * b.d1;
  s.duu = A.Faa * a.d1 * a.d1 + A.Fa * a.d2;
  s.duv = A.Fab * a.d1 * b.d1;
  s.dvv = A.Fbb * b.d1 * b.d1 + A.Fb * b.d2;
  return s;
}

void expect_surface_point_near(const Surface_point& got, const Surface_point& want, double tol_p,
                               double tol_d) {
  EXPECT_LE((got.p - want.p).norm(), tol_p) << got.p.transpose() << " vs " << want.p.transpose();
  EXPECT_LE((got.du - want.du).norm(), tol_d) << "du " << got.du.transpose() << " vs "
                                              << want.du.transpose();
  EXPECT_LE((got.dv - want.dv).norm(), tol_d) << "dv " << got.dv.transpose() << " vs "
                                              << want.dv.transpose();
  EXPECT_LE((got.duu - want.duu).norm(), tol_d) << "duu " << got.duu.transpose() << " vs "
                                                << want.duu.transpose();
  EXPECT_LE((got.duv - want.duv).norm(), tol_d) << "duv " << got.duv.transpose() << " vs "
                                                << want.duv.transpose();
  EXPECT_LE((got.dvv - want.dvv).norm(), tol_d) << "dvv " << got.dvv.transpose() << " vs "
                                                << want.dvv.transpose();
}

Analytic_point ellipsoid_point(double a, double b, double c, double th, double ph) {
  const double ct = std::cos(th), st = std::sin(th), cp = std::cos(ph), sp = std::sin(ph);
  Analytic_point A;
  A.F = Vec3(a * cp * ct, b * cp * st, c * sp);
  A.Fa = Vec3(-a * cp * st, b * cp * ct, 0);
  A.Faa = Vec3(-a * cp * ct, -b * cp * st, 0);
  A.Fb = Vec3(-a * sp * ct, -b * sp * st, c * cp);
  A.Fbb = Vec3(-a * cp * ct, -b * cp * st, -c * sp);
  A.Fab = Vec3(a * sp * st, -b * sp * ct, 0);
  return A;
}

Analytic_point torus_point(double R, double r, double th, double ps) {
  const double ct = std::cos(th), st = std::sin(th), cp = std::cos(ps), sp = std::sin(ps);
  const double rho = R + r * cp;
  Analytic_point A;
  A.F = Vec3(rho * ct, rho * st, r * sp);
  A.Fa = Vec3(-rho * st, rho * ct, 0);
  A.Faa = Vec3(-rho * ct, -rho * st, 0);
  A.Fb = Vec3(-r * sp * ct, -r * sp * st, r * cp);
  A.Fbb = Vec3(-r * cp * ct, -r * cp * st, -r * sp);
  A.Fab = Vec3(r * sp * st, -r * sp * ct, 0);
  return A;
}

// ---------------------------------------------------------------------------------------------
// Points of the analytic shapes lie on their surfaces.

struct Ellipsoid_case {
  double a, b, c;
};

class Ellipsoid_shapes : public ::testing::TestWithParam<Ellipsoid_case> {};

TEST_P(Ellipsoid_shapes, PointsLieOnTheImplicitSurface) {
  const auto [a, b, c] = GetParam();
  const Nurbs_surface_3 s = make_ellipsoid(a, b, c);
  EXPECT_DOUBLE_EQ(s.u_min(), 0.0);
  EXPECT_DOUBLE_EQ(s.u_max(), 2 * k_pi);
  EXPECT_DOUBLE_EQ(s.v_min(), -k_pi / 2);
  EXPECT_DOUBLE_EQ(s.v_max(), k_pi / 2);
  EXPECT_TRUE(s.is_rational());
  EXPECT_TRUE(s.is_closed_u());
  EXPECT_FALSE(s.is_closed_v());
  const double size = std::max({a, b, c});
  double worst = 0.0;
  Surface_point sp;
  for (double u : angle_samples(s.u_min(), s.u_max(), 360))
    for (double v : angle_samples(s.v_min(), s.v_max(), 180)) {
      s.evaluate(u, v, sp, 0);
      const Vec3& x = sp.p;
      // F - 1 is twice the relative radial error; 2e-14 allows 1e-14 relative.
      const double F = x.x() * x.x() / (a * a) + x.y() * x.y() / (b * b) + x.z() * x.z() / (c * c);
      worst = std::max(worst, std::abs(F - 1.0));
      ASSERT_LE(std::abs(F - 1.0), 2e-14) << "u = " << u << ", v = " << v;
      // The documented parametrisation: longitude and latitude through the arc angle map.
      const Vec3 want =
          ellipsoid_point(a, b, c, circle_angle(u).theta, latitude_angle(v).theta).F;
      ASSERT_LE((x - want).norm(), 1e-14 * size) << "u = " << u << ", v = " << v;
    }
  RecordProperty("worst_implicit_residual", std::to_string(worst));
  // Poles at the v ends, whatever u: exactly on the axis, and at height -c or c up to the
  // rounding of the weighted mean sum(N_i w_i z) / sum(N_i w_i) of equal heights (an ulp).
  for (double u : {0.0, 1.0, k_pi, 2 * k_pi}) {
    for (double sign : {-1.0, 1.0}) {
      s.evaluate(u, sign * k_pi / 2, sp, 0);
      EXPECT_EQ(sp.p.x(), 0.0) << "u = " << u;
      EXPECT_EQ(sp.p.y(), 0.0) << "u = " << u;
      EXPECT_NEAR(sp.p.z(), sign * c, 2 * std::numeric_limits<double>::epsilon() * c)
          << "u = " << u;
    }
  }
}

TEST_P(Ellipsoid_shapes, DerivativesMatchTheAngleParametrisation) {
  const auto [a, b, c] = GetParam();
  const Nurbs_surface_3 s = make_ellipsoid(a, b, c);
  const double size = std::max({a, b, c});
  Surface_point sp;
  for (double u : angle_samples(s.u_min(), s.u_max(), 72))
    for (double v : angle_samples(s.v_min(), s.v_max(), 36)) {
      SCOPED_TRACE(::testing::Message() << "u = " << u << ", v = " << v);
      s.evaluate(u, v, sp, 2);
      const Arc_angle th = circle_angle(u), ph = latitude_angle(v);
      expect_surface_point_near(sp, chain_rule(ellipsoid_point(a, b, c, th.theta, ph.theta), th, ph),
                                1e-14 * size, 1e-13 * size);
      if (HasFailure()) return;
    }
}

TEST_P(Ellipsoid_shapes, OutwardNormalPointsOut) {
  const auto [a, b, c] = GetParam();
  const Nurbs_surface_3 s = make_ellipsoid(a, b, c);
  Surface_point sp;
  for (double u : angle_samples(s.u_min(), s.u_max(), 24))
    for (double v : angle_samples(s.v_min() + 1e-3, s.v_max() - 1e-3, 12)) {
      s.evaluate(u, v, sp, 1);
      const Vec3 n = s.outward_normal(sp);
      // Gradient of the implicit function: the exact outward normal direction.
      const Vec3 g = Vec3(sp.p.x() / (a * a), sp.p.y() / (b * b), sp.p.z() / (c * c)).normalized();
      EXPECT_NEAR(n.norm(), 1.0, 1e-14);
      EXPECT_GT(n.dot(g), 1.0 - 1e-12) << "u = " << u << ", v = " << v;
    }
  // f_u vanishes at the poles (up to rounding): no normal, and no NaN.
  const double size = std::max({a, b, c});
  for (double u : angle_samples(s.u_min(), s.u_max(), 36))
    for (double v : {s.v_min(), s.v_max()}) {
      s.evaluate(u, v, sp, 1);
      EXPECT_LE(sp.du.norm(), 1e-14 * size);
      EXPECT_EQ(s.outward_normal(sp), Vec3::Zero()) << "u = " << u << ", v = " << v;
    }
}

TEST_P(Ellipsoid_shapes, DerivativesMatchFiniteDifferences) {
  const auto [a, b, c] = GetParam();
  const Nurbs_surface_3 s = make_ellipsoid(a, b, c);
  for (double u : knots_and_grid(s.knots_u(), s.number_of_poles_u(), 2, 16))
    for (double v : knots_and_grid(s.knots_v(), s.number_of_poles_v(), 2, 8)) {
      expect_derivatives_match_differences(s, u, v, 1e-8, std::max({a, b, c}));
      if (HasFailure()) return;
    }
}

INSTANTIATE_TEST_SUITE_P(Kernel, Ellipsoid_shapes,
                         ::testing::Values(Ellipsoid_case{1, 1, 1}, Ellipsoid_case{2.5, 2.5, 2.5},
                                           Ellipsoid_case{3, 2, 1.5}, Ellipsoid_case{2, 1.2, 1},
                                           Ellipsoid_case{1e-3, 5e-3, 2e-3},
                                           Ellipsoid_case{1e3, 10, 0.1}));

TEST(Shapes, SphereIsTheEllipsoidWithEqualAxes) {
  const Nurbs_surface_3 s = make_sphere(2.0), e = make_ellipsoid(2, 2, 2);
  ASSERT_EQ(s.poles().size(), e.poles().size());
  for (std::size_t k = 0; k < s.poles().size(); ++k) EXPECT_EQ(s.poles()[k], e.poles()[k]);
  EXPECT_EQ(s.weights(), e.weights());
  Surface_point sp;
  for (double u : angle_samples(0, 2 * k_pi, 200))
    for (double v : angle_samples(-k_pi / 2, k_pi / 2, 100)) {
      s.evaluate(u, v, sp, 0);
      ASSERT_NEAR(sp.p.norm(), 2.0, 2e-14) << "u = " << u << ", v = " << v;
    }
}

struct Torus_case {
  double R, r;
};

class Torus_shapes : public ::testing::TestWithParam<Torus_case> {};

TEST_P(Torus_shapes, PointsLieOnTheImplicitSurface) {
  const auto [R, r] = GetParam();
  const Nurbs_surface_3 s = make_torus(R, r);
  EXPECT_TRUE(s.is_closed_u());
  EXPECT_TRUE(s.is_closed_v());
  EXPECT_DOUBLE_EQ(s.v_max(), 2 * k_pi);
  Surface_point sp;
  for (double u : angle_samples(s.u_min(), s.u_max(), 360))
    for (double v : angle_samples(s.v_min(), s.v_max(), 180)) {
      s.evaluate(u, v, sp, 0);
      const Vec3& x = sp.p;
      const double rho = std::hypot(x.x(), x.y());
      ASSERT_NEAR(std::hypot(rho - R, x.z()), r, 1e-14 * (R + r)) << "u = " << u << ", v = " << v;
      const Vec3 want = torus_point(R, r, circle_angle(u).theta, circle_angle(v).theta).F;
      ASSERT_LE((x - want).norm(), 1e-14 * (R + r)) << "u = " << u << ", v = " << v;
    }
}

TEST_P(Torus_shapes, DerivativesMatchTheAngleParametrisation) {
  const auto [R, r] = GetParam();
  const Nurbs_surface_3 s = make_torus(R, r);
  Surface_point sp;
  for (double u : angle_samples(s.u_min(), s.u_max(), 72))
    for (double v : angle_samples(s.v_min(), s.v_max(), 72)) {
      SCOPED_TRACE(::testing::Message() << "u = " << u << ", v = " << v);
      s.evaluate(u, v, sp, 2);
      const Arc_angle th = circle_angle(u), ps = circle_angle(v);
      expect_surface_point_near(sp, chain_rule(torus_point(R, r, th.theta, ps.theta), th, ps),
                                1e-14 * (R + r), 1e-13 * (R + r));
      if (HasFailure()) return;
    }
}

TEST_P(Torus_shapes, DerivativesMatchFiniteDifferences) {
  const auto [R, r] = GetParam();
  const Nurbs_surface_3 s = make_torus(R, r);
  for (double u : knots_and_grid(s.knots_u(), s.number_of_poles_u(), 2, 16))
    for (double v : knots_and_grid(s.knots_v(), s.number_of_poles_v(), 2, 16)) {
      expect_derivatives_match_differences(s, u, v, 1e-8, R + r);
      if (HasFailure()) return;
    }
}

TEST_P(Torus_shapes, OutwardNormalPointsAwayFromTheTubeCentre) {
  const auto [R, r] = GetParam();
  const Nurbs_surface_3 s = make_torus(R, r);
  Surface_point sp;
  for (double u : angle_samples(0, 2 * k_pi, 24))
    for (double v : angle_samples(0, 2 * k_pi, 24)) {
      s.evaluate(u, v, sp, 1);
      const Vec3 centre = R * Vec3(sp.p.x(), sp.p.y(), 0).normalized();
      EXPECT_GT(s.outward_normal(sp).dot((sp.p - centre).normalized()), 1.0 - 1e-12);
    }
}

INSTANTIATE_TEST_SUITE_P(Kernel, Torus_shapes,
                         ::testing::Values(Torus_case{3, 1}, Torus_case{1, 0.25},
                                           Torus_case{1, 0.999}, Torus_case{1e3, 1}));

TEST(Shapes, CylinderSide) {
  const double r = 1.5, h = 4.0;
  const Nurbs_surface_3 s = make_cylinder_side(r, h);
  EXPECT_TRUE(s.is_closed_u());
  EXPECT_FALSE(s.is_closed_v());
  EXPECT_EQ(s.v_min(), 0.0);
  EXPECT_EQ(s.v_max(), 1.0);
  Surface_point sp;
  for (double u : angle_samples(0, 2 * k_pi, 120))
    for (double v : angle_samples(0, 1, 40)) {
      SCOPED_TRACE(::testing::Message() << "u = " << u << ", v = " << v);
      s.evaluate(u, v, sp, 2);
      ASSERT_NEAR(std::hypot(sp.p.x(), sp.p.y()), r, 1e-14 * r);
      const Arc_angle th = circle_angle(u);
      const double ct = std::cos(th.theta), st = std::sin(th.theta);
      Surface_point want;
      want.p = Vec3(r * ct, r * st, v * h);
      want.du = Vec3(-r * st, r * ct, 0) * th.d1;
      want.dv = Vec3(0, 0, h);
      want.duu = Vec3(-r * ct, -r * st, 0) * th.d1 * th.d1 + Vec3(-r * st, r * ct, 0) * th.d2;
      expect_surface_point_near(sp, want, 1e-14 * h, 1e-13 * h);
      const Vec3 radial(ct, st, 0);
      EXPECT_GT(s.outward_normal(sp).dot(radial), 1.0 - 1e-12);
      if (HasFailure()) return;
    }
  for (double u : knots_and_grid(s.knots_u(), s.number_of_poles_u(), 2, 16))
    for (double v : {0.0, 0.5, 1.0}) expect_derivatives_match_differences(s, u, v, 1e-8, h);
}

TEST(Shapes, Disks) {
  const double r = 2.0;
  for (double z0 : {-1.0, 0.0, 3.5})
    for (bool up : {true, false}) {
      SCOPED_TRACE(::testing::Message() << "z0 = " << z0 << ", outward_up = " << up);
      const Nurbs_surface_3 s = make_disk(r, z0, up);
      Surface_point sp;
      for (double u : angle_samples(0, 2 * k_pi, 90))
        for (double v : angle_samples(0, 1, 30)) {
          SCOPED_TRACE(::testing::Message() << "u = " << u << ", v = " << v);
          s.evaluate(u, v, sp, 2);
          EXPECT_NEAR(sp.p.z(), z0, 2 * k_eps * std::abs(z0));
          const Arc_angle th = circle_angle(u);
          const Vec3 radial(std::cos(th.theta), std::sin(th.theta), 0);
          const Vec3 tangent(-radial.y(), radial.x(), 0);
          Surface_point want;
          want.p = Vec3(0, 0, z0) + v * r * radial;
          want.du = v * r * th.d1 * tangent;
          want.dv = r * radial;
          want.duu = v * r * (-th.d1 * th.d1 * radial + th.d2 * tangent);
          want.duv = r * th.d1 * tangent;
          expect_surface_point_near(sp, want, 1e-14 * (r + std::abs(z0)), 1e-13 * r);
          const Vec3 n = s.outward_normal(sp);
          // Near the collapsed centre f_u is small and carries rounding noise of about
          // eps |z0|, which tilts the normal by noise / |f_u|; right at it there is no normal.
          const double tol = 1e-15 * std::max(1.0, 1.0 / v);
          if (n != Vec3::Zero() || v >= 1e-9) {
            EXPECT_LE((n - Vec3(0, 0, up ? 1 : -1)).norm(), tol);
          }
          if (HasFailure()) return;
        }
      // The centre is a collapsed edge: f_u = 0 there (up to rounding), and no normal.
      s.evaluate(1.0, 0.0, sp, 1);
      EXPECT_LE(sp.du.norm(), 1e-14 * (r + std::abs(z0)));
      EXPECT_EQ(s.outward_normal(sp), Vec3::Zero());
    }
}

TEST(Shapes, PlaneIsBilinear) {
  const double w = 3.0, h = 0.5;
  const Nurbs_surface_3 s = make_plane(w, h);
  EXPECT_FALSE(s.is_rational());
  EXPECT_FALSE(s.is_closed_u());
  EXPECT_FALSE(s.is_closed_v());
  Surface_point sp;
  for (double u : angle_samples(0, 1, 50))
    for (double v : angle_samples(0, 1, 50)) {
      s.evaluate(u, v, sp, 2);
      Surface_point want;
      want.p = Vec3(-w / 2 + w * u, -h / 2 + h * v, 0);
      want.du = Vec3(w, 0, 0);
      want.dv = Vec3(0, h, 0);
      expect_surface_point_near(sp, want, 1e-15 * w, 4 * k_eps * w);
      EXPECT_LE((s.outward_normal(sp) - Vec3(0, 0, 1)).norm(), 1e-15);
      if (HasFailure()) return;
    }
}

TEST(Shapes, CircleCurve) {
  const double r = 0.75;
  const Nurbs_curve_3 c = make_circle(r);
  EXPECT_TRUE(c.is_closed());
  EXPECT_TRUE(c.is_rational());
  Curve_point cp;
  for (double t : angle_samples(c.domain_min(), c.domain_max(), 2000)) {
    SCOPED_TRACE(::testing::Message() << "t = " << t);
    c.evaluate(t, cp, 2);
    const Arc_angle th = circle_angle(t);
    const Vec3 radial(std::cos(th.theta), std::sin(th.theta), 0), tangent(-radial.y(), radial.x(), 0);
    ASSERT_NEAR(cp.p.norm(), r, 1e-14 * r);
    ASSERT_EQ(cp.p.z(), 0.0);
    EXPECT_LE((cp.p - r * radial).norm(), 1e-14 * r);
    EXPECT_LE((cp.d1 - r * th.d1 * tangent).norm(), 1e-13 * r);
    EXPECT_LE((cp.d2 - r * (th.d2 * tangent - th.d1 * th.d1 * radial)).norm(), 1e-13 * r);
    if (HasFailure()) return;
  }
  for (double t : knots_and_grid(c.knots(), c.number_of_poles(), 2, 64))
    expect_curve_derivatives_match_differences(c, t, 1e-8, r);
}

// ---------------------------------------------------------------------------------------------
// Polynomial patches and curves: exact B-spline forms of known polynomial maps.

// Bernstein form of a monomial patch by the exact conversion
// P_ij = sum_{k <= i, l <= j} C(i,k)/C(p,k) C(j,l)/C(q,l) a_kl.
Nurbs_surface_3 bezier_from_monomials(const Polynomial_patch& f) {
  std::vector<Point_3> poles;
  for (int i = 0; i <= f.p; ++i)
    for (int j = 0; j <= f.q; ++j) {
      Vec3 P = Vec3::Zero();
      for (int k = 0; k <= i; ++k)
        for (int l = 0; l <= j; ++l)
          P += (binomial(i, k) / binomial(f.p, k) * binomial(j, l) / binomial(f.q, l)) * f.a[k][l];
      poles.push_back(to_point(P));
    }
  std::vector<double> ku(f.p + 1, 0.0), kv(f.q + 1, 0.0);
  ku.insert(ku.end(), f.p + 1, 1.0);
  kv.insert(kv.end(), f.q + 1, 1.0);
  return Nurbs_surface_3(f.p, f.q, f.p + 1, f.q + 1, poles, ku, kv);
}

double max_pole_norm(const std::vector<Point_3>& poles) {
  double m = 0.0;
  for (const auto& P : poles) m = std::max(m, to_vec3(P).norm());
  return m;
}

// Compares every derivative of s with the polynomial f at the parameters us x vs. The tolerance
// is a rounding-error bound: c eps (|poles| (p/h_u)^ru (q/h_v)^rv + |f^(ru,rv)| magnitude) with
// h the smallest knot span; a wrong formula misses it by orders of magnitude.
void expect_matches_polynomial(const Nurbs_surface_3& s, const Polynomial_patch& f,
                               const std::vector<double>& us, const std::vector<double>& vs) {
  const double P = max_pole_norm(s.poles());
  const double gu = f.p / min_span(s.knots_u(), s.number_of_poles_u(), f.p);
  const double gv = f.q / min_span(s.knots_v(), s.number_of_poles_v(), f.q);
  constexpr double c = 64 * k_eps;
  Surface_point sp;
  for (double u : us)
    for (double v : vs) {
      s.evaluate(u, v, sp, 2);
      const Vec3* got[6] = {&sp.p, &sp.du, &sp.dv, &sp.duu, &sp.duv, &sp.dvv};
      const int ru[6] = {0, 1, 0, 2, 1, 0}, rv[6] = {0, 0, 1, 0, 1, 2};
      const char* name[6] = {"p", "du", "dv", "duu", "duv", "dvv"};
      for (int d = 0; d < 6; ++d) {
        const Vec3 want = f.derivative(u, v, ru[d], rv[d]);
        const double tol = c * (P * std::pow(gu, ru[d]) * std::pow(gv, rv[d]) +
                                f.magnitude(u, v, ru[d], rv[d]));
        ASSERT_LE((*got[d] - want).norm(), tol)
            << name[d] << " at u = " << u << ", v = " << v << ": " << got[d]->transpose()
            << " vs " << want.transpose();
      }
    }
}

TEST(PolynomialPatch, BezierFromMonomialsMatchesClosedForm) {
  EXTREMAL_SEEDED_RNG(rng);
  for (auto [p, q] : {std::pair{1, 1}, {2, 2}, {3, 3}, {1, 4}, {5, 2}, {7, 7}, {12, 12}, {12, 1}}) {
    SCOPED_TRACE(::testing::Message() << "degrees " << p << " x " << q);
    const Polynomial_patch f = random_polynomial_patch(rng, p, q);
    const Nurbs_surface_3 s = bezier_from_monomials(f);
    EXPECT_FALSE(s.is_rational());
    // The blossom construction used below agrees with the Bernstein conversion on Bezier knots.
    const Nurbs_surface_3 b = f.to_nurbs(s.knots_u(), s.knots_v());
    for (std::size_t k = 0; k < s.poles().size(); ++k)
      EXPECT_LE((to_vec3(s.poles()[k]) - to_vec3(b.poles()[k])).norm(), 1e-14 * (p + 1) * (q + 1));
    const auto us = sample_parameters(s.knots_u(), p + 1, p, 40);
    const auto vs = sample_parameters(s.knots_v(), q + 1, q, 40);
    expect_matches_polynomial(s, f, us, vs);
  }
}

TEST(PolynomialPatch, BilinearPlane) {
  // f(u, v) = o + u e1 + v e2: a flat bilinear patch; second derivatives are exactly zero.
  Polynomial_patch f;
  f.p = f.q = 1;
  f.a = {{Vec3(1, 2, 3), Vec3(0, 0.5, 0)}, {Vec3(2, 0, 1), Vec3(0, 0, 0)}};
  const Nurbs_surface_3 s = bezier_from_monomials(f);
  Surface_point sp;
  for (double u : angle_samples(0, 1, 20))
    for (double v : angle_samples(0, 1, 20)) {
      s.evaluate(u, v, sp, 2);
      EXPECT_LE((sp.p - f.derivative(u, v, 0, 0)).norm(), 1e-15 * 8);
      EXPECT_LE((sp.du - Vec3(2, 0, 1)).norm(), 1e-15 * 8);
      EXPECT_LE((sp.dv - Vec3(0, 0.5, 0)).norm(), 1e-15 * 8);
      EXPECT_EQ(sp.duu, Vec3::Zero());  // degree 1: no second derivative, exactly
      EXPECT_LE(sp.duv.norm(), 1e-15 * 8);
      EXPECT_EQ(sp.dvv, Vec3::Zero());
    }
}

enum class Knot_kind { Clamped, Unclamped_random, Unclamped_uniform };

std::vector<double> make_knots(std::mt19937_64& rng, Knot_kind kind, int p, int n) {
  switch (kind) {
    case Knot_kind::Clamped:
      return random_clamped_knots(rng, p, n, uniform(rng, -1.0, 0.0), uniform(rng, 0.5, 1.5));
    case Knot_kind::Unclamped_random:
      return random_unclamped_knots(rng, p, n, uniform(rng, -1.5, -1.0), 2.5 / (n + p));
    case Knot_kind::Unclamped_uniform:
      break;
  }
  return uniform_unclamped_knots(p, n, -1.0, 2.0 / (n + p));
}

const char* kind_name(Knot_kind k) {
  return k == Knot_kind::Clamped ? "clamped"
                                 : k == Knot_kind::Unclamped_random ? "unclamped random"
                                                                    : "unclamped uniform";
}

TEST(PolynomialPatch, BsplineFormsOnAnyKnotVector) {
  EXTREMAL_SEEDED_RNG(rng);
  for (Knot_kind kind : {Knot_kind::Clamped, Knot_kind::Unclamped_random,
                         Knot_kind::Unclamped_uniform})
    for (auto [p, q] : {std::pair{1, 1}, {2, 3}, {3, 3}, {4, 2}, {12, 3}, {5, 12}}) {
      SCOPED_TRACE(::testing::Message() << kind_name(kind) << " knots, degrees " << p << " x " << q);
      const int nu = p + 1 + uniform_int(rng, 0, 6), nv = q + 1 + uniform_int(rng, 0, 6);
      const auto ku = make_knots(rng, kind, p, nu), kv = make_knots(rng, kind, q, nv);
      const Polynomial_patch f = random_polynomial_patch(rng, p, q);
      const Nurbs_surface_3 s = f.to_nurbs(ku, kv);
      ASSERT_EQ(s.u_min(), ku[p]);
      ASSERT_EQ(s.u_max(), ku[nu]);
      expect_matches_polynomial(s, f, sample_parameters(ku, nu, p, 12),
                                sample_parameters(kv, nv, q, 12));
      if (HasFailure()) return;
    }
}

TEST(PolynomialCurve, DegreesOneToTwelveOnAnyKnotVector) {
  EXTREMAL_SEEDED_RNG(rng);
  for (Knot_kind kind : {Knot_kind::Clamped, Knot_kind::Unclamped_random,
                         Knot_kind::Unclamped_uniform})
    for (int p = 1; p <= 12; ++p)
      for (int extra : {0, 1, 5, 13}) {
        SCOPED_TRACE(::testing::Message() << kind_name(kind) << " knots, degree " << p << ", "
                                          << p + 1 + extra << " poles");
        const int n = p + 1 + extra;
        const auto knots = make_knots(rng, kind, p, n);
        const Polynomial_curve f = random_polynomial_curve(rng, p);
        const Nurbs_curve_3 c = f.to_nurbs(knots);
        EXPECT_FALSE(c.is_rational());
        const double P = max_pole_norm(c.poles());
        const double g = p / min_span(knots, n, p);
        Curve_point cp;
        for (double t : sample_parameters(knots, n, p, 100)) {
          c.evaluate(t, cp, 2);
          const Vec3* got[3] = {&cp.p, &cp.d1, &cp.d2};
          for (int r = 0; r <= 2; ++r) {
            const double tol = 64 * k_eps * (P * std::pow(g, r) + f.magnitude(t, r));
            ASSERT_LE((*got[r] - f.derivative(t, r)).norm(), tol)
                << "derivative " << r << " at t = " << t;
          }
        }
      }
}

// ---------------------------------------------------------------------------------------------
// Finite differences everywhere: rational, high degree, unclamped.

std::vector<Point_3> random_poles(std::mt19937_64& rng, int count) {
  std::vector<Point_3> poles;
  for (int k = 0; k < count; ++k) poles.push_back(to_point(random_vec3(rng)));
  return poles;
}
std::vector<double> random_weights(std::mt19937_64& rng, int count, double lo, double hi) {
  std::vector<double> w;
  // Log-uniform, so that both ends of [lo, hi] are well represented.
  for (int k = 0; k < count; ++k) w.push_back(std::exp(uniform(rng, std::log(lo), std::log(hi))));
  return w;
}

void expect_surface_matches_differences(const Nurbs_surface_3& s, int grid) {
  const double size = bbox_size(s.hull_bbox());
  for (double u : sample_parameters(s.knots_u(), s.number_of_poles_u(), s.degree_u(), grid))
    for (double v : sample_parameters(s.knots_v(), s.number_of_poles_v(), s.degree_v(), grid)) {
      expect_derivatives_match_differences(s, u, v, 1e-7, size);
      if (::testing::Test::HasFailure()) return;
    }
}

TEST(RationalFreeform, DerivativesMatchFiniteDifferences) {
  EXTREMAL_SEEDED_RNG(rng);
  for (auto [p, q] : {std::pair{1, 1}, {2, 2}, {3, 3}, {2, 5}, {4, 1}, {5, 5}}) {
    SCOPED_TRACE(::testing::Message() << "degrees " << p << " x " << q);
    const int nu = p + 1 + uniform_int(rng, 0, 4), nv = q + 1 + uniform_int(rng, 0, 4);
    const Nurbs_surface_3 s = make_freeform(p, q, nu, nv, random_poles(rng, nu * nv),
                                            random_weights(rng, nu * nv, 0.2, 5.0));
    EXPECT_TRUE(s.is_rational());
    expect_surface_matches_differences(s, 6);
    if (HasFailure()) return;
  }
}

TEST(RationalFreeform, UnclampedKnotsWithMultiplicities) {
  EXTREMAL_SEEDED_RNG(rng);
  for (auto [p, q] : {std::pair{1, 2}, {2, 2}, {3, 3}, {4, 2}}) {
    SCOPED_TRACE(::testing::Message() << "degrees " << p << " x " << q);
    const int nu = p + 2 + uniform_int(rng, 0, 4), nv = q + 2 + uniform_int(rng, 0, 4);
    const Nurbs_surface_3 s(p, q, nu, nv, random_poles(rng, nu * nv),
                            random_unclamped_knots(rng, p, nu, -0.5, 0.3, 0.3),
                            random_unclamped_knots(rng, q, nv, 2.0, 0.7, 0.3),
                            random_weights(rng, nu * nv, 0.2, 5.0));
    expect_surface_matches_differences(s, 6);
    if (HasFailure()) return;
  }
}

TEST(RationalFreeform, DegreeTwelve) {
  EXTREMAL_SEEDED_RNG(rng);
  // A 13 x 13 Bezier patch, and a 12 x 3 one with interior knots in v.
  const Nurbs_surface_3 a = make_freeform(12, 12, 13, 13, random_poles(rng, 169),
                                          random_weights(rng, 169, 0.2, 5.0));
  expect_surface_matches_differences(a, 8);
  const Nurbs_surface_3 b = make_freeform(12, 3, 13, 7, random_poles(rng, 91),
                                          random_weights(rng, 91, 0.2, 5.0));
  expect_surface_matches_differences(b, 8);
}

TEST(PolynomialPatch, DerivativesMatchFiniteDifferencesOnUnclampedKnots) {
  EXTREMAL_SEEDED_RNG(rng);
  for (auto [p, q] : {std::pair{2, 3}, {3, 3}, {12, 2}}) {
    const int nu = p + 3, nv = q + 4;
    const Nurbs_surface_3 s(p, q, nu, nv, random_poles(rng, nu * nv),
                            uniform_unclamped_knots(p, nu, -1, 0.25),
                            random_unclamped_knots(rng, q, nv, 0, 1.0, 0.3));
    EXPECT_FALSE(s.is_rational());
    expect_surface_matches_differences(s, 6);
  }
}

TEST(RationalCurve, DerivativesMatchFiniteDifferences) {
  EXTREMAL_SEEDED_RNG(rng);
  for (int p = 1; p <= 12; ++p) {
    SCOPED_TRACE(::testing::Message() << "degree " << p);
    const int n = p + 1 + uniform_int(rng, 0, 6);
    const bool clamped = p % 2 == 0;
    const auto knots = clamped ? random_clamped_knots(rng, p, n, 0.0, 1.0)
                               : random_unclamped_knots(rng, p, n, 1.0, 0.2);
    const Nurbs_curve_3 c(p, random_poles(rng, n), knots, random_weights(rng, n, 0.2, 5.0));
    const double size = bbox_size(c.hull_bbox());
    for (double t : sample_parameters(knots, n, p, 40)) {
      expect_curve_derivatives_match_differences(c, t, 1e-7, size);
      if (HasFailure()) return;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// The AVX2 + FMA kernels (chosen at run time) against the portable path: the same values to
// rounding, in the patch frame and placed, for every order, degree mix and rational or not.

class Portable_evaluation {  // switches the SIMD kernels off for its lifetime
 public:
  Portable_evaluation() { internal::set_fast_tensor_product(false); }
  ~Portable_evaluation() { internal::set_fast_tensor_product(true); }
};

TEST(SimdEvaluation, AgreesWithThePortablePath) {
  if (internal::avx2_kernels().sum == nullptr)
    GTEST_SKIP() << "this CPU or build has no AVX2 + FMA kernel";
  EXTREMAL_SEEDED_RNG(rng);
  const Rigid_pose_3 X = Rigid_pose_3::from_quaternion(Vec3(3.0, -2.0, 7.5), 0.8, 0.1, -0.5, 0.3);
  for (auto [p, q] : {std::pair{1, 1}, {2, 2}, {3, 3}, {2, 1}, {1, 2}, {4, 3}, {5, 2}, {7, 7}}) {
    for (bool rational : {false, true}) {
      SCOPED_TRACE(::testing::Message() << "degrees " << p << " x " << q
                                        << (rational ? ", rational" : ""));
      const int nu = p + 1 + uniform_int(rng, 0, 3), nv = q + 1 + uniform_int(rng, 0, 3);
      const Nurbs_surface_3 s =
          rational ? make_freeform(p, q, nu, nv, random_poles(rng, nu * nv),
                                   random_weights(rng, nu * nv, 0.2, 5.0))
                   : make_freeform(p, q, nu, nv, random_poles(rng, nu * nv), {});
      ASSERT_EQ(s.is_rational(), rational);
      for (int k = 0; k < 20; ++k) {
        const double u = uniform(rng, s.u_min(), s.u_max()), v = uniform(rng, s.v_min(), s.v_max());
        for (int order = 0; order <= 2; ++order) {
          Surface_point fast, fast_placed, slow, slow_placed;
          s.evaluate(u, v, fast, order);
          s.evaluate_placed(u, v, X.rotation(), X.translation(), fast_placed, order);
          {
            Portable_evaluation portable;
            s.evaluate(u, v, slow, order);
            s.evaluate_placed(u, v, X.rotation(), X.translation(), slow_placed, order);
          }
          const Vec3 Surface_point::*members[] = {&Surface_point::p,   &Surface_point::du,
                                                  &Surface_point::dv,  &Surface_point::duu,
                                                  &Surface_point::duv, &Surface_point::dvv};
          const int count = order == 0 ? 1 : order == 1 ? 3 : 6;
          for (int m = 0; m < count; ++m) {
            const Vec3& a = fast.*members[m];
            const Vec3& b = slow.*members[m];
            const Vec3& c = fast_placed.*members[m];
            const Vec3& d = slow_placed.*members[m];
            const double scale = 1.0 + b.norm();
            EXPECT_LE((a - b).norm(), 1e-12 * scale) << "member " << m << " order " << order;
            EXPECT_LE((c - d).norm(), 1e-12 * (scale + 10.0)) << "member " << m;
            // Placed = rotated (and translated, for the point) body-frame value.
            const Vec3 expected = m == 0 ? X.apply_point(b) : X.apply_vector(b);
            EXPECT_LE((d - expected).norm(), 1e-12 * (scale + 10.0)) << "member " << m;
          }
          if (HasFailure()) return;
        }
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Exactly at knots and ends: the value is continuous across every knot (the pieces meet), and
// the domain ends are reached exactly.

TEST(Evaluation, PiecesMeetAtKnotsAndEnds) {
  EXTREMAL_SEEDED_RNG(rng);
  const int p = 3, q = 2, nu = 8, nv = 6;
  const Nurbs_surface_3 s(p, q, nu, nv, random_poles(rng, nu * nv),
                          random_clamped_knots(rng, p, nu, 0, 1, 0.5),
                          random_unclamped_knots(rng, q, nv, 0, 1, 0.3),
                          random_weights(rng, nu * nv, 0.2, 5.0));
  const double size = bbox_size(s.hull_bbox());
  Surface_point at, beside;
  for (int i = p; i <= nu; ++i)
    for (double v : sample_parameters(s.knots_v(), nv, q, 7)) {
      const double u = s.knots_u()[i];
      s.evaluate(u, v, at, 1);
      for (double side : {s.u_min(), s.u_max()}) {
        const double w = std::nextafter(u, side);
        if (w < s.u_min() || w > s.u_max()) continue;
        s.evaluate(w, v, beside, 1);
        // One ulp away the point moves by about |f_u| ulp; anything more is a jump.
        const double tol = 1e-14 * size + 2 * std::max(at.du.norm(), beside.du.norm()) * std::abs(w - u);
        EXPECT_LE((at.p - beside.p).norm(), tol) << "u knot " << u << ", v = " << v;
      }
    }
  // Clamped ends interpolate the corner poles.
  Surface_point c;
  s.evaluate(s.u_min(), s.v_min(), c, 0);
  EXPECT_TRUE(std::isfinite(c.p.norm()));
  s.evaluate(s.u_max(), s.v_max(), c, 2);
  EXPECT_TRUE(c.p.allFinite() && c.du.allFinite() && c.duu.allFinite() && c.dvv.allFinite());

  const Nurbs_surface_3 b = make_freeform(3, 3, 4, 4, random_poles(rng, 16),
                                          random_weights(rng, 16, 0.2, 5.0));
  for (int i : {0, 3})
    for (int j : {0, 3}) {
      b.evaluate(i / 3.0, j / 3.0, c, 2);
      EXPECT_LE((c.p - to_vec3(b.pole(i, j))).norm(), 1e-15 * 4) << i << ", " << j;
    }
}

// A span hint (the tracker's: the spans of its last evaluation) must give exactly the values of
// the span search, in particular at a knot, where the search takes the span to its right: a C0
// knot (double interior knot) makes the two sides' derivatives differ, so a hint kept across it
// would show. Hints from another patch or stale ones only cost the search.
TEST(Evaluation, SpanHintGivesTheValuesOfTheSearch) {
  EXTREMAL_SEEDED_RNG(rng);
  const int p = 2, q = 3, nu = 9, nv = 7;
  const std::vector<double> ku = {0, 0, 0, 0.2, 0.4, 0.5, 0.5, 0.7, 0.85, 1, 1, 1};  // C0 at 0.5
  const Nurbs_surface_3 s(p, q, nu, nv, random_poles(rng, nu * nv), ku,
                          random_unclamped_knots(rng, q, nv, -1.0, 0.4, 0.3),
                          random_weights(rng, nu * nv, 0.2, 5.0));
  ASSERT_EQ(s.knots_u()[5], s.knots_u()[6]);
  const Rigid_pose_3 X = Rigid_pose_3::from_quaternion(Vec3(1.0, -2.0, 0.5), 0.9, 0.2, -0.3, 0.1);
  std::vector<double> us, vs;
  for (double k : s.knots_u())
    if (k >= s.u_min() && k <= s.u_max()) us.insert(us.end(), {k, std::nextafter(k, -1.0)});
  for (double k : s.knots_v())
    if (k >= s.v_min() && k <= s.v_max()) vs.insert(vs.end(), {k, std::nextafter(k, 1e9)});
  for (int i = 0; i < 40; ++i) {
    us.push_back(uniform(rng, s.u_min(), s.u_max()));
    vs.push_back(uniform(rng, s.v_min(), s.v_max()));
  }
  const auto in_domain = [&](double u, double v) {
    return u >= s.u_min() && u <= s.u_max() && v >= s.v_min() && v <= s.v_max();
  };
  // A hint carried through parameters in order and out of order, and one from a patch with more
  // spans than this one has.
  for (Span_hint start : {Span_hint{}, Span_hint{11, 9}, Span_hint{4, 4}}) {
    Span_hint hint = start;
    for (int pass = 0; pass < 2; ++pass) {
      if (pass == 1) std::shuffle(us.begin(), us.end(), rng);
      for (double u : us)
        for (double v : vs) {
          if (!in_domain(u, v)) continue;
          double with[6][4], without[6][4];
          s.evaluate_placed_rows(u, v, X.rotation(), X.translation(), with, 2, &hint);
          s.evaluate_placed_rows(u, v, X.rotation(), X.translation(), without, 2);
          for (int r = 0; r < 6; ++r)
            for (int c = 0; c < 3; ++c)
              ASSERT_EQ(with[r][c], without[r][c]) << "u = " << u << ", v = " << v << ", row " << r;
          EXPECT_TRUE(s.knots_u()[hint.u] <= u && s.knots_v()[hint.v] <= v);
        }
    }
  }
  // The hint never waives the domain check, on either parameter, at either end, nor for the
  // spans before the domain of an unclamped knot vector.
  const double u_in = 0.1, v_in = 0.5 * (s.v_min() + s.v_max());
  // Inside the knot span before v_min where it is not empty (so a hint on it would match).
  const double before = s.knots_v()[q - 1];
  const double below_v = before < s.v_min() ? 0.5 * (before + s.v_min()) : s.v_min() - 0.1;
  double rows[6][4];
  for (Span_hint start : {Span_hint{}, Span_hint{2, q - 1}}) {
    for (auto [u, v] : {std::pair{-0.1, v_in}, {1.1, v_in}, {std::nan(""), v_in},
                        {u_in, s.v_max() + 1.0}, {u_in, below_v}, {u_in, std::nan("")}}) {
      Span_hint hint = start;
      s.evaluate_placed_rows(u_in, v_in, X.rotation(), X.translation(), rows, 2, &hint);
      if (start.v == q - 1) hint.v = q - 1;  // a span before v_min: in the knots, not the domain
      EXPECT_THROW(s.evaluate_placed_rows(u, v, X.rotation(), X.translation(), rows, 2, &hint),
                   Precondition_violation)
          << "u = " << u << ", v = " << v;
    }
  }
}

TEST(Evaluation, PointAgreesWithEvaluate) {
  const Nurbs_surface_3 s = make_torus(2, 0.5);
  Surface_point sp;
  s.evaluate(1.25, 4.5, sp, 2);
  EXPECT_EQ(to_vec3(s.point(1.25, 4.5)), sp.p);
  const Nurbs_curve_3 c = make_circle(2);
  Curve_point cp;
  c.evaluate(5.0, cp, 2);
  EXPECT_EQ(to_vec3(c.point(5.0)), cp.p);
}

}  // namespace
}  // namespace extremal
