// The signed extremal distance (algorithms/Penetration_depth.h): overlapping and nested spheres
// and a point inside a sphere against their closed forms, overlapping ellipsoids against a brute
// force minimisation of the analytic overlap(n), certified bounds that bracket the truth,
// separated bodies exactly as the plain certified distance, containment (winding numbers,
// closedness) on spheres, the cylinder and the non-convex B-rep bracket, a point inside the
// bracket against its certified distance to the surface, and budgets.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "algorithms/distance/Global_distance.h"
#include "algorithms/distance/Penetration_depth.h"
#include "kernel/Bracket.h"
#include "kernel/Error.h"
#include "kernel/Shapes.h"
#include "support/Random.h"

namespace extremal {
namespace {

Rigid_pose_3 random_pose(std::mt19937_64& rng, const Vec3& position) {
  std::normal_distribution<double> g(0.0, 1.0);
  const Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
  return Rigid_pose_3::from_quaternion(position, q.w(), q.x(), q.y(), q.z());
}

void expect_brackets(const Signed_distance_result& r, double truth, double tol) {
  EXPECT_LE(r.lower_bound, truth + 1e-12) << "lower bound above the truth";
  EXPECT_GE(r.upper_bound, truth - 1e-12) << "upper bound below the truth";
  EXPECT_LE(r.lower_bound, r.distance);
  EXPECT_LE(r.distance, r.upper_bound);
  EXPECT_LE(r.upper_bound - r.lower_bound, tol + 1e-15);
  EXPECT_NEAR(r.distance, truth, tol);
}

TEST(PenetrationDepth, OverlappingSpheresMatchTheClosedForm) {
  auto rng = test::seeded_rng();
  const Body A = make_sphere_body(1.0), B = make_sphere_body(0.7);
  for (int k = 0; k < 4; ++k) {
    std::uniform_real_distribution<double> u(-0.8, 0.8);
    const Vec3 cA(u(rng), u(rng), u(rng)), offset(u(rng), u(rng), u(rng));
    const Vec3 cB = cA + offset.normalized() * (0.5 + 0.3 * k);  // 0.5 .. 1.4 < 1.7 apart
    const Rigid_pose_3 X_WA = random_pose(rng, cA), X_WB = random_pose(rng, cB);
    Signed_distance_request req;
    req.absolute_tolerance = 1e-10;
    req.relative_tolerance = 0.0;
    const Signed_distance_result r = signed_distance(A, X_WA, B, X_WB, req);
    const double truth = (cB - cA).norm() - 1.7;
    ASSERT_EQ(r.status, Signed_distance_status::Penetrating) << to_string(r.status);
    EXPECT_EQ(r.overlap, Overlap_kind::Surfaces_meet);
    EXPECT_TRUE(r.depth_is_translation_distance);
    expect_brackets(r, truth, 1e-10);
    const Vec3 n = (cB - cA).normalized();
    EXPECT_NEAR((r.normal - n).norm(), 0.0, 1e-4);
    // Support points: A's along n, B's along -n; p - q = overlap * n, so q - p = s * n.
    EXPECT_NEAR((r.point_a - (cA + 1.0 * n)).norm(), 0.0, 1e-4);
    EXPECT_NEAR((r.point_b - (cB - 0.7 * n)).norm(), 0.0, 1e-4);
    // The direction is resolved to about the square root of the tolerance.
    EXPECT_NEAR((r.point_b - r.point_a - r.distance * r.normal).norm(), 0.0, 1e-4);
    EXPECT_EQ(r.face_a, 0);
    EXPECT_EQ(r.face_b, 0);
  }
}

// A ball of radius r_in at offset o inside a ball of radius r_out (surfaces apart:
// |o| + r_in < r_out): overlap(n) = n.o + r_in + r_out, smallest at n = -o / |o|, so
// s = |o| - r_in - r_out: A must move by r_in + r_out - |o| along o to come out and touch B
// from outside. The same for B inside A (overlap(-n) of the swapped pair).
TEST(PenetrationDepth, NestedSpheresAreDetectedAndMatchTheClosedForm) {
  const Body inner = make_sphere_body(1.0), outer = make_sphere_body(3.0);
  const Vec3 o(0.5, 0.3, -0.2);
  const Rigid_pose_3 X_in = Rigid_pose_3::from_quaternion(o, 0.9, 0.1, 0.3, 0.2);
  const Rigid_pose_3 X_out = Rigid_pose_3::from_quaternion(Vec3::Zero(), 0.7, 0.2, 0.1, 0.6);
  const double truth = o.norm() - 1.0 - 3.0;
  Signed_distance_request req;
  req.absolute_tolerance = 1e-10;
  req.relative_tolerance = 0.0;
  const Signed_distance_result r = signed_distance(inner, X_in, outer, X_out, req);
  ASSERT_EQ(r.status, Signed_distance_status::Penetrating) << to_string(r.status);
  EXPECT_EQ(r.overlap, Overlap_kind::A_inside_B);
  EXPECT_GT(r.apart.lower_bound, 1.0);  // the surfaces are well apart
  EXPECT_GT(r.winding_cells, 0);
  expect_brackets(r, truth, 1e-10);
  EXPECT_NEAR((r.normal + o.normalized()).norm(), 0.0, 1e-4);

  const Signed_distance_result swapped = signed_distance(outer, X_out, inner, X_in, req);
  ASSERT_EQ(swapped.status, Signed_distance_status::Penetrating);
  EXPECT_EQ(swapped.overlap, Overlap_kind::B_inside_A);
  expect_brackets(swapped, truth, 1e-10);
}

// A point body inside a closed body: s = -(depth to the boundary of the hull) = |a| - r.
TEST(PenetrationDepth, PointInsideASphereIsItsDepth) {
  const Body p = make_point_body(), ball = make_sphere_body(2.0);
  const Vec3 a(0.3, -0.4, 0.5);
  Signed_distance_request req;
  req.absolute_tolerance = 1e-10;
  req.relative_tolerance = 0.0;
  const Signed_distance_result r =
      signed_distance(p, Rigid_pose_3(Mat3::Identity(), a), ball, Rigid_pose_3(), req);
  ASSERT_EQ(r.status, Signed_distance_status::Penetrating) << to_string(r.status);
  EXPECT_EQ(r.overlap, Overlap_kind::A_inside_B);
  EXPECT_TRUE(r.depth_is_translation_distance);
  expect_brackets(r, a.norm() - 2.0, 1e-10);
  EXPECT_EQ(r.kind_a, Element_kind::Point);
  // Outside, it is the plain distance.
  const Signed_distance_result out =
      signed_distance(p, Rigid_pose_3(Mat3::Identity(), Vec3(0, 0, 5)), ball, Rigid_pose_3(), req);
  EXPECT_EQ(out.status, Signed_distance_status::Converged);
  EXPECT_NEAR(out.distance, 3.0, 1e-10);
}

// Overlapping ellipsoids: the truth is the minimum of the analytic overlap(n) =
// h_A(n) + h_B(-n), h(n) = n.c + sqrt(n^T P n), P = R diag(s^2) R^T, found by brute force on a
// fine (theta, phi) grid and zoomed grids around the best point.
double brute_force_min_overlap(const Rigid_pose_3& XA, const Vec3& sa, const Rigid_pose_3& XB,
                               const Vec3& sb) {
  const Mat3 PA = XA.rotation() * sa.cwiseAbs2().asDiagonal() * XA.rotation().transpose();
  const Mat3 PB = XB.rotation() * sb.cwiseAbs2().asDiagonal() * XB.rotation().transpose();
  auto overlap = [&](double th, double ph) {
    const Vec3 n(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
    return n.dot(XA.translation()) + std::sqrt(n.dot(PA * n)) - n.dot(XB.translation()) +
           std::sqrt(n.dot(PB * n));
  };
  double best = HUGE_VAL, bt = 0, bp = 0;
  const int N = 400;
  for (int i = 0; i <= N; ++i)
    for (int j = 0; j < 2 * N; ++j) {
      const double th = M_PI * i / N, ph = M_PI * j / N;
      const double v = overlap(th, ph);
      if (v < best) {
        best = v;
        bt = th;
        bp = ph;
      }
    }
  double h = M_PI / N;
  for (int level = 0; level < 40; ++level) {
    const double t0 = bt, p0 = bp;
    for (int i = -10; i <= 10; ++i)
      for (int j = -10; j <= 10; ++j) {
        const double th = t0 + h * i / 5, ph = p0 + h * j / 5;
        const double v = overlap(th, ph);
        if (v < best) {
          best = v;
          bt = th;
          bp = ph;
        }
      }
    h *= 0.5;
  }
  return best;
}

TEST(PenetrationDepth, OverlappingEllipsoidsMatchABruteForceMinimisation) {
  auto rng = test::seeded_rng();
  const Vec3 sa(3, 2, 1.5), sb(2, 1.2, 1);
  const Body A = make_ellipsoid_body(sa.x(), sa.y(), sa.z());
  const Body B = make_ellipsoid_body(sb.x(), sb.y(), sb.z());
  for (int k = 0; k < 3; ++k) {
    std::uniform_real_distribution<double> u(-1.5, 1.5);
    const Rigid_pose_3 XA = random_pose(rng, Vec3::Zero());
    const Rigid_pose_3 XB = random_pose(rng, Vec3(2.5 + u(rng), u(rng), 0.5 * u(rng)));
    const double truth = -brute_force_min_overlap(XA, sa, XB, sb);
    Signed_distance_request req;
    req.absolute_tolerance = 1e-9;
    req.relative_tolerance = 0.0;
    const Signed_distance_result r = signed_distance(A, XA, B, XB, req);
    if (truth > 0.0) {  // this placement left them apart: the plain distance
      EXPECT_EQ(r.overlap, Overlap_kind::None);
      continue;
    }
    ASSERT_EQ(r.status, Signed_distance_status::Penetrating) << to_string(r.status);
    EXPECT_TRUE(r.depth_is_translation_distance);
    expect_brackets(r, truth, 1e-9);
    // The extremal pair: support points along +n and -n, p - q parallel to n.
    const Vec3 d = r.point_a - r.point_b;
    EXPECT_LE(d.cross(r.normal).norm(), 1e-4 * std::max(1.0, d.norm()));
  }
}

TEST(PenetrationDepth, SeparatedBodiesGiveThePlainCertifiedDistance) {
  const Body A = make_ellipsoid_body(3, 2, 1.5), B = make_sphere_body(1.0);
  const Rigid_pose_3 XA = Rigid_pose_3::from_quaternion(Vec3::Zero(), 0.9, 0.1, 0.3, 0.2);
  const Rigid_pose_3 XB(Mat3::Identity(), Vec3(6, 1, 0));
  Signed_distance_request req;
  req.absolute_tolerance = 1e-10;
  req.relative_tolerance = 0.0;
  const Signed_distance_result r = signed_distance(A, XA, B, XB, req);
  Distance_request dreq;
  dreq.absolute_tolerance = 1e-10;
  dreq.relative_tolerance = req.relative_tolerance;
  const Distance_result plain = extremal_distance(A, XA, B, XB, dreq);
  EXPECT_EQ(r.status, Signed_distance_status::Converged);
  EXPECT_EQ(r.overlap, Overlap_kind::None);
  EXPECT_EQ(r.distance, plain.distance);
  EXPECT_EQ(r.lower_bound, plain.lower_bound);
  EXPECT_EQ(r.upper_bound, plain.upper_bound);
  EXPECT_EQ(r.point_a, plain.point_a);
  EXPECT_EQ(r.point_b, plain.point_b);
  EXPECT_GT(r.distance, 1.0);
}

// The hull depth of separated convex bodies is minus their distance: the same number by two
// independent certificates.
TEST(PenetrationDepth, HullDepthOfSeparatedConvexBodiesIsTheirDistance) {
  const Body A = make_ellipsoid_body(3, 2, 1.5), B = make_ellipsoid_body(2, 1.2, 1);
  const Rigid_pose_3 XA = Rigid_pose_3::from_quaternion(Vec3::Zero(), 0.9, 0.1, 0.3, 0.2);
  const Rigid_pose_3 XB = Rigid_pose_3::from_quaternion(Vec3(6.5, 1, 0.5), 0.7, 0.2, 0.1, 0.6);
  const Distance_hierarchy HA(A), HB(B);
  Signed_distance_request req;
  req.absolute_tolerance = 1e-9;
  const Signed_distance_result hull = hull_signed_distance(HA, XA, HB, XB, req);
  Distance_request dreq;
  dreq.absolute_tolerance = 1e-10;
  const Distance_result plain = extremal_distance(HA, XA, HB, XB, dreq);
  ASSERT_EQ(hull.status, Signed_distance_status::Penetrating) << to_string(hull.status);
  EXPECT_LE(hull.lower_bound, plain.upper_bound + 1e-12);
  EXPECT_GE(hull.upper_bound, plain.lower_bound - 1e-12);
  EXPECT_NEAR(hull.distance, plain.distance, 1e-9);
}

TEST(PenetrationDepth, SupportBoundsHoldAndCloseOnASphere) {
  const Body ball = make_sphere_body(2.0);
  const Distance_hierarchy H(ball);
  const Rigid_pose_3 X = Rigid_pose_3::from_quaternion(Vec3(1, -2, 3), 0.9, 0.1, 0.3, 0.2);
  for (const Vec3& dir : {Vec3(1, 0, 0), Vec3(0.3, -0.5, 0.8), Vec3(0, 0, -1), Vec3(-1, 1, 1)}) {
    const Vec3 n = dir.normalized();
    Support_request req;
    req.tolerance = 1e-12;
    const Support_bound s = support_bound(H, X, n, req);
    const double truth = n.dot(X.translation()) + 2.0;
    ASSERT_TRUE(s.converged);
    EXPECT_LE(s.lower, truth + 1e-13);
    EXPECT_GE(s.upper, truth - 1e-13);
    EXPECT_LE(s.upper - s.lower, 1e-12);
    EXPECT_NEAR((s.point - (X.translation() + 2.0 * n)).norm(), 0.0, 1e-6);
    // Without the Newton polish the net search alone still certifies it.
    req.newton_polish = false;
    const Support_bound raw = support_bound(H, X, n, req);
    EXPECT_LE(raw.lower, truth + 1e-13);
    EXPECT_GE(raw.upper, truth - 1e-13);
  }
}

TEST(PenetrationDepth, ClosednessOfShapes) {
  EXPECT_TRUE(body_closedness(make_sphere_body(1)).closed);
  EXPECT_TRUE(body_closedness(make_torus_body(3, 1)).closed);
  EXPECT_TRUE(body_closedness(make_cylinder_body(1, 2)).closed);  // side meets both caps
  EXPECT_TRUE(body_closedness(make_bracket_body()).closed);       // B-rep: two faces per edge
  const Closedness plane = body_closedness(make_plane_body(2, 2));
  EXPECT_FALSE(plane.closed);
  EXPECT_NE(plane.reason.find("free boundary"), std::string::npos) << plane.reason;
  Body side;
  side.name = "side";
  side.faces.push_back({make_cylinder_side(1, 2), "cylinder"});
  EXPECT_FALSE(body_closedness(side).closed);
  EXPECT_FALSE(body_closedness(make_point_body()).closed);
  EXPECT_TRUE(is_certified_convex(make_sphere_body(1)));
  EXPECT_TRUE(is_certified_convex(make_point_body()));
  EXPECT_FALSE(is_certified_convex(make_torus_body(3, 1)));
  EXPECT_FALSE(is_certified_convex(make_bracket_body()));
}

TEST(PenetrationDepth, WindingNumbersOfClosedBodies) {
  const Body torus = make_torus_body(3, 1);
  const Distance_hierarchy H(torus);
  const Rigid_pose_3 X = Rigid_pose_3::from_quaternion(Vec3(1, 2, 3), 0.9, 0.1, 0.3, 0.2);
  // In the tube, in the hole, outside, and close to the surface (1e-6 inside).
  const Winding_number tube = winding_number(H, X, X.apply_point(Vec3(3, 0, 0.2)), 0.8);
  const Winding_number hole = winding_number(H, X, X.apply_point(Vec3(0, 0, 0)), 2.0);
  const Winding_number far = winding_number(H, X, X.apply_point(Vec3(0, 9, 0)), 5.0);
  const Winding_number near = winding_number(H, X, X.apply_point(Vec3(0, 4 - 1e-6, 0)), 0.9e-6);
  EXPECT_TRUE(tube.inside());
  EXPECT_NEAR(tube.value, 1.0, 1e-3);
  EXPECT_FALSE(hole.inside());
  EXPECT_NEAR(hole.value, 0.0, 1e-3);
  EXPECT_NEAR(far.value, 0.0, 1e-3);
  EXPECT_TRUE(near.inside());
  EXPECT_NEAR(near.value, 1.0, 1e-2);
}

// A point in the bracket's wall (x from 2.5 to 4), 0.4 from the slot's side and 1 below the
// top: its depth is its distance to the surface, 0.4, the translation that takes it out, not
// the depth of the bracket's hull (1, to the hull's top; the slot is in the hull). Swapped, the
// same.
TEST(PenetrationDepth, PointInsideANonConvexPartIsItsDistanceToTheSurface) {
  const Body bracket = make_bracket_body(), p = make_point_body();
  Signed_distance_request req;
  req.absolute_tolerance = 1e-10;
  req.relative_tolerance = 0.0;
  const Rigid_pose_3 X_P(Mat3::Identity(), Vec3(2.9, 1.0, 3.0));
  const Signed_distance_result r = signed_distance(p, X_P, bracket, Rigid_pose_3(), req);
  ASSERT_EQ(r.status, Signed_distance_status::Penetrating) << to_string(r.status);
  EXPECT_EQ(r.overlap, Overlap_kind::A_inside_B);
  EXPECT_TRUE(r.depth_is_translation_distance);
  expect_brackets(r, -0.4, 1e-10);
  EXPECT_NEAR((r.point_b - r.point_a - r.distance * r.normal).norm(), 0.0, 1e-9);
  EXPECT_NEAR((r.point_b - Vec3(2.5, 1.0, 3.0)).norm(), 0.0, 1e-8);  // the slot's side
  // The certified unsigned distance, negated.
  Distance_request dreq;
  dreq.absolute_tolerance = 1e-10;
  dreq.relative_tolerance = 0.0;
  const Distance_result g = extremal_distance(p, X_P, bracket, Rigid_pose_3(), dreq);
  EXPECT_NEAR(r.distance, -g.distance, 1e-10);
  const Signed_distance_result swapped = signed_distance(bracket, Rigid_pose_3(), p, X_P, req);
  EXPECT_EQ(swapped.overlap, Overlap_kind::B_inside_A);
  expect_brackets(swapped, -0.4, 1e-10);
  EXPECT_NEAR((swapped.point_b - swapped.point_a - swapped.distance * swapped.normal).norm(), 0.0, 1e-9);
}

// The U-shaped bracket (8 x 10 x 4, slot 5 wide down to the floor at z = 1): a ball in the slot
// that touches nothing is apart (positive distance, not nested, though it lies in the bracket's
// hull); a ball inside a wall (1.5 thick) is nested, with a negative hull depth.
TEST(PenetrationDepth, NonConvexBracketCavityIsApartAndItsWallNests) {
  const Body bracket = make_bracket_body();
  const Body ball = make_sphere_body(1.0), bead = make_sphere_body(0.5);
  Signed_distance_request req;
  req.absolute_tolerance = 1e-9;
  req.relative_tolerance = 0.0;
  const Signed_distance_result cavity = signed_distance(
      ball, Rigid_pose_3(Mat3::Identity(), Vec3(0, 0, 2.5)), bracket, Rigid_pose_3(), req);
  EXPECT_EQ(cavity.status, Signed_distance_status::Converged) << to_string(cavity.status);
  EXPECT_EQ(cavity.overlap, Overlap_kind::None);
  EXPECT_TRUE(cavity.closed_b.closed);
  EXPECT_NEAR(cavity.distance, 0.5, 1e-9);  // above the slot floor at z = 1
  EXPECT_GT(cavity.winding_cells, 0);

  const Signed_distance_result wall = signed_distance(
      bead, Rigid_pose_3(Mat3::Identity(), Vec3(3.25, 1, 2.5)), bracket, Rigid_pose_3(), req);
  EXPECT_EQ(wall.overlap, Overlap_kind::A_inside_B);
  EXPECT_FALSE(wall.depth_is_translation_distance);
  EXPECT_TRUE(wall.is_certified()) << to_string(wall.status);
  EXPECT_LT(wall.upper_bound, 0.0);
  EXPECT_LE(wall.lower_bound, wall.distance);
  EXPECT_LE(wall.distance, wall.upper_bound);
  // The hull's nearest face to the bead is the wall's outer face x = 4 (flat for z in [1, 4]):
  // overlap(-x) = -2.75 + 4 = 1.25, and every other direction costs more (the hull's top,
  // bottom and end faces are farther), so s = -1.25, a kink of overlap(n) (a hull face).
  expect_brackets(wall, -1.25, 1e-9);
  EXPECT_NEAR((wall.normal - Vec3(-1, 0, 0)).norm(), 0.0, 1e-6);
}

// A body that is not closed contains nothing: a ball under an open plane stays apart.
TEST(PenetrationDepth, OpenBodiesContainNothing) {
  const Body ball = make_sphere_body(0.5);
  const Body cup = make_plane_body(4, 4);
  const Signed_distance_result r = signed_distance(
      ball, Rigid_pose_3(Mat3::Identity(), Vec3(0, 0, -1)), cup, Rigid_pose_3());
  EXPECT_EQ(r.overlap, Overlap_kind::None);
  EXPECT_FALSE(r.closed_b.closed);
  EXPECT_NEAR(r.distance, 0.5, 1e-9);
}

// A ball of radius 0.5 through a 4 x 4 plane, its centre at height 0.2 above (x, y), the whole
// placed at random: s = 0.2 - 0.5 along the plane's normal. The plane attains its support at
// every point, so the witness on it must be the one under the ball's deepest point, with
// point_b - point_a = s n (a corner of the plane has the same support value).
TEST(PenetrationDepth, FlatSupportFaceGivesTheWitnessAlignedWithTheNormal) {
  auto rng = test::seeded_rng();
  const Body ball = make_sphere_body(0.5), plane = make_plane_body(4, 4);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  for (int k = 0; k < 4; ++k) {
    const Rigid_pose_3 X = random_pose(rng, Vec3(u(rng), u(rng), u(rng)));
    const double x = u(rng), y = u(rng);
    const Rigid_pose_3 X_ball(X.rotation(), X.apply_point(Vec3(x, y, 0.2)));
    const Signed_distance_result r = signed_distance(plane, X, ball, X_ball);
    ASSERT_EQ(r.status, Signed_distance_status::Penetrating) << to_string(r.status);
    EXPECT_NEAR(r.distance, -0.3, 1e-8);
    const Vec3 up = X.apply_vector(Vec3::UnitZ());
    EXPECT_NEAR(std::abs(r.normal.dot(up)), 1.0, 1e-9);
    EXPECT_NEAR((r.point_b - r.point_a - r.distance * r.normal).norm(), 0.0, 1e-9);
    EXPECT_NEAR((r.point_a - X.apply_point(Vec3(x, y, 0.0))).norm(), 0.0, 1e-6) << "case " << k;
  }
}

// Concentric balls: every direction minimises overlap(n), so the certificate needs the whole
// sphere of directions resolved; a small budget stops with bounds that still hold.
TEST(PenetrationDepth, DegenerateMinimumExhaustsTheBudgetWithValidBounds) {
  const Body inner = make_sphere_body(1.0), outer = make_sphere_body(2.0);
  const Distance_hierarchy HI(inner), HO(outer);
  Signed_distance_request req;
  req.absolute_tolerance = 1e-12;
  req.max_cells = 400;
  const Signed_distance_result r = hull_signed_distance(HI, Rigid_pose_3(), HO, Rigid_pose_3(), req);
  EXPECT_EQ(r.status, Signed_distance_status::Budget_exhausted);
  EXPECT_FALSE(r.is_certified());
  EXPECT_LE(r.lower_bound, -3.0 + 1e-12);
  EXPECT_GE(r.upper_bound, -3.0 - 1e-12);
  EXPECT_NEAR(r.distance, -3.0, 1e-6);
}

// A capped cylinder (radius 0.3, z from -2 to 2) through a unit ball off its axis by c in the
// xy-plane: overlap(n) = 1 - n.c + 0.3 |n_xy| + 2 |n_z|, smallest across the axis towards c:
// s = |c| - 1.3. The minimum is a kink (the cylinder's support is a whole generator there, and
// jumps to a rim across it), which Newton's method cannot polish; the expanding polytope and the
// differences on both sides of the kink still certify it to the tolerance.
TEST(PenetrationDepth, KinkOfACylinderThroughABall) {
  const Body ball = make_sphere_body(1.0), cylinder = make_cylinder_body(0.3, 4);
  Signed_distance_request req;
  req.absolute_tolerance = 1e-9;
  req.relative_tolerance = 0.0;
  const Signed_distance_result r = signed_distance(
      ball, Rigid_pose_3(), cylinder, Rigid_pose_3(Mat3::Identity(), Vec3(0.2, 0.1, -2)), req);
  ASSERT_EQ(r.status, Signed_distance_status::Penetrating) << to_string(r.status);
  EXPECT_EQ(r.overlap, Overlap_kind::Surfaces_meet);
  EXPECT_FALSE(r.depth_is_translation_distance);  // a cylinder is not certified convex here
  expect_brackets(r, std::sqrt(0.05) - 1.3, 1e-9);
  EXPECT_NEAR((r.normal - Vec3(0.2, 0.1, 0).normalized()).norm(), 0.0, 1e-4);
  // The cylinder's support is a generator: its witness is the one across from the ball's.
  EXPECT_NEAR((r.point_b - r.point_a - r.distance * r.normal).norm(), 0.0, 1e-9);
}

TEST(PenetrationDepth, BadRequestsThrow) {
  const Body a = make_sphere_body(1), b = make_sphere_body(1);
  Signed_distance_request req;
  req.absolute_tolerance = 0.0;
  EXPECT_THROW((void)signed_distance(a, Rigid_pose_3(), b, Rigid_pose_3(), req), Precondition_violation);
  req.absolute_tolerance = 1e-9;
  req.max_cells = 0;
  EXPECT_THROW((void)signed_distance(a, Rigid_pose_3(), b, Rigid_pose_3(), req), Precondition_violation);
}

}  // namespace
}  // namespace extremal
