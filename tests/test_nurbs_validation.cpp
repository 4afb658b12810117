// Every invalid construction throws Invalid_input with a message naming the problem; evaluation
// outside the domain throws Precondition_violation naming the parameter.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "kernel/Error.h"
#include "kernel/Nurbs_curve_3.h"
#include "kernel/Nurbs_surface_3.h"
#include "kernel/Shapes.h"
#include "tests/support/Nurbs_test_support.h"

namespace extremal {
namespace {

using namespace extremal::test;

const double k_nan = std::numeric_limits<double>::quiet_NaN();
const double k_inf = std::numeric_limits<double>::infinity();

// Runs `make`, which must throw E with a message containing every one of `parts`.
template <class E>
void expect_throw_with(const std::function<void()>& make, const std::vector<std::string>& parts) {
  try {
    make();
    ADD_FAILURE() << "no exception; expected one mentioning \"" << parts.front() << "\"";
  } catch (const E& e) {
    const std::string what = e.what();
    for (const auto& part : parts)
      EXPECT_NE(what.find(part), std::string::npos)
          << "message \"" << what << "\" does not mention \"" << part << "\"";
  } catch (const std::exception& e) {
    ADD_FAILURE() << "wrong exception type: " << e.what();
  }
}

std::vector<Point_3> line_poles(int n) {
  std::vector<Point_3> p;
  for (int i = 0; i < n; ++i) p.emplace_back(i, 0.5 * i, -i);
  return p;
}

std::vector<double> clamped(int p, int n) {
  std::vector<double> k(p + 1, 0.0);
  for (int i = 1; i < n - p; ++i) k.push_back(static_cast<double>(i) / (n - p));
  k.insert(k.end(), p + 1, 1.0);
  return k;
}

// ---------------------------------------------------------------------------------------------
// Curves: a table of invalid constructions and the words their message must contain.

struct Invalid_curve {
  const char* name;
  std::function<void()> make;
  std::vector<std::string> message;
};

class Invalid_curves : public ::testing::TestWithParam<Invalid_curve> {};

TEST_P(Invalid_curves, ThrowInvalidInputNamingTheProblem) {
  expect_throw_with<Invalid_input>(GetParam().make, GetParam().message);
}

std::vector<Invalid_curve> invalid_curves() {
  return {
      {"KnotCountLow", [] { Nurbs_curve_3(2, line_poles(4), {0, 0, 0, 1, 1, 1}); },
       {"NURBS curve knots", "knot count is 6, expected 7"}},
      {"KnotCountHigh", [] { Nurbs_curve_3(2, line_poles(4), {0, 0, 0, 0.5, 0.7, 1, 1, 1}); },
       {"knot count is 8, expected 7", "4 control points + degree 2 + 1"}},
      {"DecreasingKnots", [] { Nurbs_curve_3(2, line_poles(4), {0, 0, 0, 0.6, 0.5, 1, 1}); },
       {"knots decrease at index 4", "0.6 then 0.5"}},
      {"DecreasingAtEnd", [] { Nurbs_curve_3(1, line_poles(3), {0, 0, 1, 1, 0.9}); },
       {"knots decrease at index 4"}},
      {"InteriorMultiplicityAboveDegree",
       [] { Nurbs_curve_3(2, line_poles(6), {0, 0, 0, 0.5, 0.5, 0.5, 1, 1, 1}); },
       {"knot 0.5 has multiplicity 3, more than 2 allowed inside the domain"}},
      {"EndMultiplicityAboveDegreePlusOne",
       [] { Nurbs_curve_3(2, line_poles(4), {0, 0, 0, 0, 1, 1, 1}); },
       {"knot 0 has multiplicity 4, more than 3 allowed"}},
      {"NonFiniteKnot", [] { Nurbs_curve_3(2, line_poles(4), {0, 0, 0, k_nan, 1, 1, 1}); },
       {"knot 3 is not finite"}},
      {"InfiniteKnot", [] { Nurbs_curve_3(1, line_poles(2), {0, 0, 1, k_inf}); },
       {"knot 3 is not finite"}},
      {"EmptyDomain", [] { Nurbs_curve_3(1, line_poles(2), {0, 1, 1, 2}); },
       {"domain", "is empty"}},
      {"WeightZero", [] { Nurbs_curve_3(2, line_poles(3), clamped(2, 3), {1, 0, 1}); },
       {"weight 1 is 0", "finite and > 0"}},
      {"WeightNegative", [] { Nurbs_curve_3(2, line_poles(3), clamped(2, 3), {1, 1, -0.5}); },
       {"weight 2 is -0.5"}},
      {"WeightNaN", [] { Nurbs_curve_3(2, line_poles(3), clamped(2, 3), {k_nan, 1, 1}); },
       {"weight 0 is nan", "finite and > 0"}},
      {"WeightInfinite", [] { Nurbs_curve_3(2, line_poles(3), clamped(2, 3), {1, k_inf, 1}); },
       {"weight 1 is inf"}},
      {"WeightCount", [] { Nurbs_curve_3(2, line_poles(3), clamped(2, 3), {1, 1}); },
       {"2 weights for 3 control points"}},
      {"NaNCoordinate",
       [] {
         auto p = line_poles(3);
         p[1] = Point_3(0, k_nan, 0);
         Nurbs_curve_3(2, p, clamped(2, 3));
       },
       {"control point 1 has a non-finite coordinate"}},
      {"InfiniteCoordinate",
       [] {
         auto p = line_poles(3);
         p[2] = Point_3(0, 0, -k_inf);
         Nurbs_curve_3(2, p, clamped(2, 3));
       },
       {"control point 2 has a non-finite coordinate"}},
      {"DegreeZero", [] { Nurbs_curve_3(0, line_poles(2), {0, 0.5, 1}); },
       {"degree 0 is outside 1..25"}},
      {"DegreeNegative", [] { Nurbs_curve_3(-1, line_poles(2), {0, 1}); },
       {"degree -1 is outside 1..25"}},
      {"Degree26", [] { Nurbs_curve_3(26, line_poles(27), clamped(26, 27)); },
       {"degree 26 is outside 1..25"}},
      {"TooFewPoles", [] { Nurbs_curve_3(3, line_poles(3), {0, 0, 0, 0, 1, 1, 1}); },
       {"3 control points are too few for degree 3", "need at least 4"}},
      {"NoPoles", [] { Nurbs_curve_3(1, {}, {0, 1}); }, {"0 control points are too few"}},
      {"CircleRadius", [] { make_circle(0.0); }, {"circle radius must be finite and > 0"}},
  };
}

INSTANTIATE_TEST_SUITE_P(Kernel, Invalid_curves, ::testing::ValuesIn(invalid_curves()),
                         [](const auto& info) { return std::string(info.param.name); });

// ---------------------------------------------------------------------------------------------
// Surfaces.

struct Invalid_surface {
  const char* name;
  std::function<void()> make;
  std::vector<std::string> message;
};

class Invalid_surfaces : public ::testing::TestWithParam<Invalid_surface> {};

TEST_P(Invalid_surfaces, ThrowInvalidInputNamingTheProblem) {
  expect_throw_with<Invalid_input>(GetParam().make, GetParam().message);
}

std::vector<Point_3> grid_poles(int nu, int nv) {
  std::vector<Point_3> p;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) p.emplace_back(i, j, 0.1 * i * j);
  return p;
}

Nurbs_surface_3 grid(int p, int q, int nu, int nv, std::vector<Point_3> poles,
                     std::vector<double> weights = {}) {
  return Nurbs_surface_3(p, q, nu, nv, std::move(poles), clamped(p, nu), clamped(q, nv),
                         std::move(weights));
}

std::vector<Invalid_surface> invalid_surfaces() {
  return {
      {"GridCountMismatch", [] { grid(2, 2, 3, 4, grid_poles(3, 3)); },
       {"NURBS surface: 9 control points for a 3 x 4 grid"}},
      {"EmptyGrid", [] { Nurbs_surface_3(1, 1, 0, 2, {}, {0, 1}, {0, 0, 1, 1}); },
       {"control grid 0 x 2 is empty"}},
      {"UKnotCount",
       [] { Nurbs_surface_3(2, 2, 3, 3, grid_poles(3, 3), {0, 0, 0, 1, 1}, clamped(2, 3)); },
       {"NURBS surface u knots", "knot count is 5, expected 6"}},
      {"VKnotCount",
       [] { Nurbs_surface_3(2, 1, 3, 3, grid_poles(3, 3), clamped(2, 3), {0, 0, 1, 1}); },
       {"NURBS surface v knots", "knot count is 4, expected 5"}},
      {"DecreasingVKnots",
       [] {
         Nurbs_surface_3(1, 1, 3, 3, grid_poles(3, 3), clamped(1, 3), {0, 0, 0.7, 0.2, 1});
       },
       {"NURBS surface v knots", "knots decrease at index 3"}},
      {"UMultiplicity",
       [] {
         Nurbs_surface_3(1, 1, 4, 2, grid_poles(4, 2), {0, 0, 0.5, 0.5, 1, 1}, clamped(1, 2));
       },
       {"NURBS surface u knots", "knot 0.5 has multiplicity 2, more than 1 allowed inside"}},
      {"UDegreeZero",
       [] { Nurbs_surface_3(0, 1, 2, 2, grid_poles(2, 2), {0, 0.5, 1}, clamped(1, 2)); },
       {"NURBS surface u knots", "degree 0 is outside 1..25"}},
      {"VDegree26", [] { grid(1, 26, 2, 27, grid_poles(2, 27)); },
       {"NURBS surface v knots", "degree 26 is outside 1..25"}},
      {"TooFewPolesInV", [] { Nurbs_surface_3(2, 3, 3, 3, grid_poles(3, 3), clamped(2, 3), {0, 0, 0, 0, 1, 1, 1}); },
       {"NURBS surface v knots", "3 control points are too few for degree 3"}},
      {"WeightCount", [] { grid(1, 1, 2, 2, grid_poles(2, 2), {1, 1, 1}); },
       {"3 weights for 4 control points"}},
      {"WeightZero", [] { grid(1, 1, 2, 2, grid_poles(2, 2), {1, 1, 0, 1}); },
       {"weight of control point (1, 0) is 0", "finite and > 0"}},
      {"WeightNegative", [] { grid(1, 1, 2, 2, grid_poles(2, 2), {1, -2, 1, 1}); },
       {"weight of control point (0, 1) is -2"}},
      {"WeightNaN", [] { grid(1, 1, 2, 2, grid_poles(2, 2), {1, 1, 1, k_nan}); },
       {"weight of control point (1, 1) is nan"}},
      {"NaNCoordinate",
       [] {
         auto p = grid_poles(3, 2);
         p[3] = Point_3(k_nan, 0, 0);  // pole (1, 1)
         grid(1, 1, 3, 2, p);
       },
       {"control point (1, 1) has a non-finite coordinate"}},
      {"InfiniteCoordinate",
       [] {
         auto p = grid_poles(2, 2);
         p[2] = Point_3(0, k_inf, 0);  // pole (1, 0)
         grid(1, 1, 2, 2, p);
       },
       {"control point (1, 0) has a non-finite coordinate"}},
      {"FreeformTooSmall", [] { make_freeform(3, 2, 3, 3, grid_poles(3, 3)); },
       {"freeform patch: a 3 x 3 grid is too small for degrees 3 x 2"}},
      {"FreeformBadWeight", [] { make_freeform(1, 1, 2, 2, grid_poles(2, 2), {1, 1, 1, -1}); },
       {"weight of control point (1, 1) is -1"}},
      {"FromHomogeneousZeroWeight",
       [] {
         Nurbs_surface_3::Homogeneous h(4, Eigen::Vector4d(1, 2, 3, 1));
         h[2].w() = 0.0;
         Nurbs_surface_3::from_homogeneous(1, 1, 2, 2, h, clamped(1, 2), clamped(1, 2));
       },
       {"weight"}},
      {"SphereRadiusZero", [] { make_sphere(0.0); }, {"sphere radius must be finite and > 0, got 0"}},
      {"SphereRadiusNaN", [] { make_sphere(k_nan); }, {"sphere radius must be finite and > 0"}},
      {"EllipsoidNegativeAxis", [] { make_ellipsoid(1, -2, 1); },
       {"ellipsoid semi-axis b must be finite and > 0, got -2"}},
      {"EllipsoidInfiniteAxis", [] { make_ellipsoid(1, 2, k_inf); },
       {"ellipsoid semi-axis c must be finite and > 0"}},
      {"TorusMinor", [] { make_torus(2, 0); }, {"torus minor radius must be finite and > 0"}},
      {"TorusMajor", [] { make_torus(-1, 0.5); }, {"torus major radius must be finite and > 0"}},
      {"CylinderHeight", [] { make_cylinder_side(1, 0); }, {"cylinder height must be finite and > 0"}},
      {"DiskRadius", [] { make_disk(-1, 0, true); }, {"disk radius must be finite and > 0"}},
      {"PlaneWidth", [] { make_plane(k_nan, 1); }, {"plane width must be finite and > 0"}},
      {"SphereBody", [] { make_sphere_body(-3); }, {"sphere radius"}},
      {"CylinderBody", [] { make_cylinder_body(1, -1); }, {"cylinder height"}},
  };
}

INSTANTIATE_TEST_SUITE_P(Kernel, Invalid_surfaces, ::testing::ValuesIn(invalid_surfaces()),
                         [](const auto& info) { return std::string(info.param.name); });

// ---------------------------------------------------------------------------------------------
// Valid limits: degree 25 is accepted and evaluates (partition of unity, exact constant),
// multiplicity p + 1 at the ends and p inside is accepted.

TEST(Validation, LimitsAreAccepted) {
  const int p = 25;
  std::vector<Point_3> poles(p + 1, Point_3(1.5, -2, 3));
  const Nurbs_curve_3 c(p, poles, clamped(p, p + 1));
  Curve_point cp;
  for (double t : {0.0, 0.1, 0.5, 0.999, 1.0}) {
    c.evaluate(t, cp, 2);
    EXPECT_LE((cp.p - Vec3(1.5, -2, 3)).norm(), 1e-14);
    EXPECT_LE(cp.d1.norm(), 1e-10);
    EXPECT_LE(cp.d2.norm(), 1e-8);
  }
  const Nurbs_surface_3 s(p, 1, p + 1, 2, std::vector<Point_3>(2 * (p + 1), Point_3(1, 1, 1)),
                          clamped(p, p + 1), clamped(1, 2));
  Surface_point sp;
  s.evaluate(0.3, 0.6, sp, 2);
  EXPECT_LE((sp.p - Vec3(1, 1, 1)).norm(), 1e-14);
  EXPECT_NO_THROW(Nurbs_curve_3(2, line_poles(6), {0, 0, 0, 0.5, 0.5, 0.7, 1, 1, 1}));
  EXPECT_NO_THROW(Nurbs_curve_3(1, line_poles(2), {0, 0, 1, 1}));
  // Unclamped, with a knot repeated p times outside the domain.
  EXPECT_NO_THROW(Nurbs_curve_3(2, line_poles(4), {-1, -1, 0, 1, 2, 3, 4}));
}

// ---------------------------------------------------------------------------------------------
// Evaluation outside the domain.

TEST(Validation, EvaluationOutsideTheDomainThrows) {
  const Nurbs_surface_3 s = make_ellipsoid(3, 2, 1.5);
  Surface_point sp;
  const double u_over = std::nextafter(2 * k_pi, 10.0), v_under = std::nextafter(-k_pi / 2, -10.0);
  expect_throw_with<Precondition_violation>([&] { s.evaluate(-0.1, 0.0, sp); },
                                            {"precondition violated", "u = -0.1 outside"});
  expect_throw_with<Precondition_violation>([&] { s.evaluate(u_over, 0.0, sp); }, {"u = "});
  expect_throw_with<Precondition_violation>([&] { s.evaluate(1.0, v_under, sp); },
                                            {"v = ", "outside"});
  expect_throw_with<Precondition_violation>([&] { s.evaluate(1.0, 2.0, sp, 0); }, {"v = 2 outside"});
  expect_throw_with<Precondition_violation>([&] { s.evaluate(k_nan, 0.0, sp); }, {"u = nan"});
  expect_throw_with<Precondition_violation>([&] { s.evaluate(0.0, k_nan, sp); }, {"v = nan"});
  expect_throw_with<Precondition_violation>([&] { s.evaluate(0.0, k_inf, sp); }, {"v = inf"});
  expect_throw_with<Precondition_violation>([&] { s.evaluate(1.0, 0.0, sp, 3); }, {"order"});
  expect_throw_with<Precondition_violation>([&] { s.evaluate(1.0, 0.0, sp, -1); }, {"order"});
  EXPECT_THROW(s.point(7.0, 0.0), Precondition_violation);
  // The ends themselves are inside.
  EXPECT_NO_THROW(s.evaluate(2 * k_pi, k_pi / 2, sp));
  EXPECT_NO_THROW(s.evaluate(0.0, -k_pi / 2, sp));

  const Nurbs_curve_3 c(2, line_poles(4), {-1, -0.5, 0, 1, 2, 3, 3.5});  // unclamped: [0, 2]
  Curve_point cp;
  expect_throw_with<Precondition_violation>([&] { c.evaluate(-0.5, cp); },
                                            {"t = -0.5 outside [0, 2]"});
  expect_throw_with<Precondition_violation>([&] { c.evaluate(2.5, cp); }, {"t = 2.5 outside"});
  expect_throw_with<Precondition_violation>([&] { c.evaluate(k_nan, cp); }, {"t = nan"});
  expect_throw_with<Precondition_violation>([&] { c.evaluate(1.0, cp, 3); }, {"order"});
  EXPECT_THROW(c.point(std::nextafter(2.0, 3.0)), Precondition_violation);
  EXPECT_NO_THROW(c.evaluate(0.0, cp));
  EXPECT_NO_THROW(c.evaluate(2.0, cp));
}

}  // namespace
}  // namespace extremal
