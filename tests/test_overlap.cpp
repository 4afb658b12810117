// One definition of overlap for every pairing of body kinds (docs/behaviour.md, "Overlap: when
// a row reads penetrating"): each test moves B along a line from apart, through overlap where
// the pairing can overlap, and out, with a Body_pair_tracker, and checks at every step against
// the certified one-shot (signed_distance) and, where one exists, the closed form:
//   - no NaN;
//   - the row reads `penetrating` only while the one-shot finds the bodies overlapping (its
//     overlap kind), and, for a pairing with an inside or two sheets, at every such step;
//   - a pairing without an inside (curves, points, open meshes against bodies without one)
//     never reads below 0, and reads 0 while the bodies meet (the one-shot too);
//   - apart rows within 1e-6 of the certified distance, their lower bound at or below it;
//   - the closed form of the value (a point or a ball against a box or a cylinder: exact).
// The kinds: solid (a cylinder, an ellipsoid), open sheet (a plane), curve (a segment), closed
// mesh (a box of 12 triangles), open mesh (a square of 2 triangles), point, ball (a sphere).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>

#include "algorithms/body_pair/Body_pair_tracker.h"
#include "algorithms/distance/Penetration_depth.h"
#include "kernel/Shapes.h"
#include "support/Mesh_test_support.h"

namespace extremal {
namespace {

using test::mesh_body;

constexpr double k_apart_tolerance = 1e-6;  // apart rows against the certified distance
constexpr double k_contact = 1e-9;          // Body_pair_options::contact_tolerance

// A box of 12 triangles, outward, half sizes h about the origin (a closed mesh).
Body box_mesh(const Vec3& h, const std::string& name) {
  Triangle_mesh box;
  for (int k = 0; k < 8; ++k)
    box.vertices.emplace_back(k & 1 ? h.x() : -h.x(), k & 2 ? h.y() : -h.y(), k & 4 ? h.z() : -h.z());
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    box.triangles.push_back({f[0], f[1], f[2]});
    box.triangles.push_back({f[0], f[2], f[3]});
  }
  return mesh_body(box, name);
}

// A square of side `side` in the xy plane about the origin, two triangles (an open mesh).
Body square_mesh(double side, const std::string& name) {
  Triangle_mesh m;
  const double h = 0.5 * side;
  m.vertices = {Point_3(-h, -h, 0), Point_3(h, -h, 0), Point_3(h, h, 0), Point_3(-h, h, 0)};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return mesh_body(m, name);
}

// A straight segment from a to b (a body of one curve).
Body segment(const Vec3& a, const Vec3& b, const std::string& name) {
  Body body;
  body.name = name;
  body.curves.push_back(Nurbs_curve_3(1, {to_point(a), to_point(b)}, {0, 0, 1, 1}));
  return body;
}

Mat3 about_x(double angle) { return Eigen::AngleAxisd(angle, Vec3::UnitX()).toRotationMatrix(); }
Mat3 about_z(double angle) { return Eigen::AngleAxisd(angle, Vec3::UnitZ()).toRotationMatrix(); }

// Signed distance of the point p to the box of half sizes h about the origin (exact).
double box_signed_distance(const Vec3& h, const Vec3& p) {
  const Vec3 q = p.cwiseAbs() - h;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

// Signed distance of the point p to the cylinder of radius r about the z axis, z in [0, h].
double cylinder_signed_distance(double r, double h, const Vec3& p) {
  const double radial = std::hypot(p.x(), p.y()) - r;
  const double axial = std::max(-p.z(), p.z() - h);
  return std::hypot(std::max(radial, 0.0), std::max(axial, 0.0)) + std::min(std::max(radial, axial), 0.0);
}

// Whether a pairing has a side to be inside of: a closed body on either side, or two sheets.
enum class Sides { Signed, Unsigned };

struct Sweep {
  const Body* a = nullptr;  // at the origin, unturned
  const Body* b = nullptr;  // turned by `turn_b`, its origin moved from `from` to `to`
  Mat3 turn_b = Mat3::Identity();
  Vec3 from = Vec3::Zero(), to = Vec3::Zero();
  int steps = 48;
  Sides sides = Sides::Signed;
  // The closed form of the row at B's origin (NaN where there is none), within `tolerance`;
  // the one-shot's too where `one_shot_exact` (apart rows are checked against it anyway).
  std::function<double(const Vec3&)> exact;
  double tolerance = 1e-9;
  bool one_shot_exact = true;
};

struct Sweep_counts {
  int steps = 0, overlapping = 0, penetrating = 0, apart = 0, exact = 0;
  double max_exact_error = 0.0, max_apart_error = 0.0, least = HUGE_VAL;
};

// Runs the sweep, checking every step (see the file's comment); returns what it saw.
Sweep_counts run(const char* name, const Sweep& s) {
  const Distance_hierarchy HA(*s.a), HB(*s.b);
  Body_pair_tracker tracker(*s.a, *s.b);
  const double dt = 0.01;
  Twist_3 still, moving;
  moving.linear = (s.to - s.from) / (s.steps * dt);
  const Rigid_pose_3 X_WA;
  Sweep_counts c;
  for (int i = 0; i <= s.steps; ++i) {
    const Vec3 at = s.from + (s.to - s.from) * (static_cast<double>(i) / s.steps);
    const Rigid_pose_3 X_WB(s.turn_b, at);
    const Pair_report& r = tracker.step(i * dt, X_WA, still, X_WB, moving, dt);
    const Signed_distance_result ref = signed_distance(*s.a, HA, X_WA, *s.b, HB, X_WB);
    SCOPED_TRACE(testing::Message() << name << ", step " << i << " at (" << at.transpose()
                                    << "): row " << r.distance << " " << to_string(r.status)
                                    << ", one-shot " << ref.distance << " "
                                    << to_string(ref.overlap) << " " << to_string(ref.status));
    ++c.steps;
    if (std::getenv("OVERLAP_TRACE"))  // (every step printed, to diagnose a sweep)
      std::printf("  %s %d z=%.4f row %.6g %s lb %s src %d features %d/%d edges %d/%d | ref %.6g %s\n",
                  name, i, at.z(), r.distance, to_string(r.status),
                  r.lower_bound ? std::to_string(*r.lower_bound).c_str() : "-",
                  static_cast<int>(r.solved), r.feature_a, r.feature_b, r.edge_a, r.edge_b,
                  ref.distance, to_string(ref.overlap));
    EXPECT_TRUE(std::isfinite(r.distance) && r.point_a.allFinite() && r.point_b.allFinite() &&
                r.normal.allFinite());
    if (!std::isfinite(r.distance)) continue;
    EXPECT_TRUE(ref.is_certified());
    c.least = std::min(c.least, r.distance);
    const bool overlapping = ref.overlap != Overlap_kind::None;
    const bool penetrating = r.status == Pair_status::Penetrating;
    c.overlapping += overlapping;
    c.penetrating += penetrating;
    // Penetrating only while the bodies overlap by evidence.
    if (penetrating) { EXPECT_TRUE(overlapping); }
    if (overlapping && s.sides == Sides::Signed) {
      EXPECT_TRUE(penetrating);
      EXPECT_LT(r.distance, -k_contact);
    }
    if (s.sides == Sides::Unsigned) {
      EXPECT_GE(r.distance, -k_contact);
      EXPECT_GE(ref.distance, -k_contact);
      if (overlapping) {
        EXPECT_NEAR(r.distance, 0.0, k_apart_tolerance);
        EXPECT_NEAR(ref.distance, 0.0, k_apart_tolerance);
      }
    }
    if (!overlapping) {
      ++c.apart;
      const double error = std::abs(r.distance - ref.distance);
      c.max_apart_error = std::max(c.max_apart_error, error);
      EXPECT_LE(error, k_apart_tolerance);
      EXPECT_GT(r.distance, 0.0);
      EXPECT_TRUE(r.lower_bound.has_value());
      if (r.lower_bound) { EXPECT_LE(*r.lower_bound, ref.upper_bound + k_contact); }
    }
    if (s.exact) {
      const double e = s.exact(at);
      if (!std::isnan(e)) {
        ++c.exact;
        c.max_exact_error = std::max(c.max_exact_error, std::abs(r.distance - e));
        EXPECT_NEAR(r.distance, e, s.tolerance);
        if (s.one_shot_exact) { EXPECT_NEAR(ref.distance, e, std::max(s.tolerance, 1e-8)); }
      }
    }
  }
  std::printf("[ sweep    ] %-28s %d steps: %d overlapping, %d penetrating, %d apart; least %.4f; "
              "apart error %.1e, closed-form error %.1e over %d\n",
              name, c.steps, c.overlapping, c.penetrating, c.apart, c.least, c.max_apart_error,
              c.max_exact_error, c.exact);
  return c;
}

// Checks that a sweep went from apart through overlap and out.
void expect_through(const Sweep_counts& c) {
  EXPECT_GT(c.overlapping, 0);
  EXPECT_GT(c.apart, 1);
}

// ---- The bodies ---------------------------------------------------------------------------

const Body& cylinder() {  // radius 1 about the z axis, z in [0, 1]
  static const Body b = make_cylinder_body(1.0, 1.0, "cylinder");
  return b;
}
const Body& ellipsoid() {
  static const Body b = make_ellipsoid_body(0.2, 0.3, 0.4, "ellipsoid");
  return b;
}
const Body& plane() {  // 4 x 4 in the xy plane, normal +z
  static const Body b = make_plane_body(4.0, 4.0, "plane");
  return b;
}
const Body& rod() {  // along x, length 3
  static const Body b = segment(Vec3(-1.5, 0, 0), Vec3(1.5, 0, 0), "rod");
  return b;
}
const Body& point() {
  static const Body b = make_point_body("point");
  return b;
}
const Vec3 k_small_box(0.2, 0.2, 0.2), k_large_box(0.5, 0.5, 0.5);
const Body& small_box() {
  static const Body b = box_mesh(k_small_box, "small_box");
  return b;
}
const Body& large_box() {
  static const Body b = box_mesh(k_large_box, "large_box");
  return b;
}
const Body& square() {  // 0.8 x 0.8: turned 30 degrees about x it spans z in [-0.2, 0.2]
  static const Body b = square_mesh(0.8, "square");
  return b;
}
const Body& floor_square() {  // 1 x 1, flat
  static const Body b = square_mesh(1.0, "floor_square");
  return b;
}
const double k_tilt = M_PI / 6.0;  // the square's: sin = 1/2

// ---- Solid against ... ----------------------------------------------------------------------

TEST(Overlap, SolidSolidReadsTheDepthReachedThroughContactWhileTheyOverlap) {
  // An ellipsoid (c = 0.4 along z) down the axis of a cylinder and out of its bottom. Two
  // convex bodies: the depth is the translation distance, through the cap nearer the centre
  // (the side wall's is 1.2); a stale depth is off by at most 2% of the ellipsoid's size.
  Sweep s;
  s.a = &cylinder();
  s.b = &ellipsoid();
  s.from = Vec3(0, 0, 1.83);
  s.to = Vec3(0, 0, -0.81);
  s.exact = [](const Vec3& p) {
    if (p.z() > 1.4) return p.z() - 1.4;
    if (p.z() < -0.4) return -p.z() - 0.4;
    return -std::min(1.4 - p.z(), p.z() + 0.4);
  };
  s.tolerance = 0.02;
  expect_through(run("solid-solid", s));
}

TEST(Overlap, APartCarriedIntoASolidInOneStepReadsItsDepth) {
  // The ellipsoid jumps from above the cylinder to inside it, its surface never meeting the
  // cylinder's at a step: inside, its depth is the translation distance out through a cap.
  const Body& a = cylinder();
  const Body& b = ellipsoid();
  Body_pair_tracker tracker(a, b);
  const Rigid_pose_3 X_WA;
  const double dt = 0.01;
  const Vec3 at[] = {Vec3(0, 0, 2.0), Vec3(0, 0, 1.9), Vec3(0, 0, 0.5), Vec3(0, 0, 0.45),
                     Vec3(0, 0, 0.4)};
  for (int i = 0; i < 5; ++i) {
    const Rigid_pose_3 X_WB(Mat3::Identity(), at[i]);
    const Pair_report& r = tracker.step(i * dt, X_WA, Twist_3{}, X_WB, Twist_3{}, dt);
    const double exact = at[i].z() > 1.4 ? at[i].z() - 1.4 : -std::min(1.4 - at[i].z(), at[i].z() + 0.4);
    SCOPED_TRACE(testing::Message() << "step " << i << ": row " << r.distance << " "
                                    << to_string(r.status));
    EXPECT_NEAR(r.distance, exact, 0.02);
    if (exact < 0.0) {
      EXPECT_EQ(r.status, Pair_status::Penetrating);
      EXPECT_FALSE(r.lower_bound.has_value());
    }
  }
}

TEST(Overlap, SolidThroughASheetKeepsItsEntrySidesDepthWhileTheSurfacesMeet) {
  Sweep s;
  s.a = &plane();
  s.b = &ellipsoid();
  s.from = Vec3(0.1, 0.2, 1.03);
  s.to = Vec3(0.1, 0.2, -0.97);
  s.exact = [](const Vec3& p) { return std::abs(p.z()) >= 0.4 ? std::abs(p.z()) - 0.4 : p.z() - 0.4; };
  s.tolerance = 1e-6;
  s.one_shot_exact = false;  // (the hulls' depth)
  expect_through(run("solid-sheet", s));
}

TEST(Overlap, ACurveInASolidReadsTheDepthReachedThroughContact) {
  // A rod across the cylinder, down and out: inside, the translation out through the nearer
  // cap (the rod's middle is as deep: the rod is convex).
  Sweep s;
  s.a = &cylinder();
  s.b = &rod();
  s.from = Vec3(0, 0, 1.73);
  s.to = Vec3(0, 0, -0.71);
  s.exact = [](const Vec3& p) {
    if (p.z() > 1.0) return p.z() - 1.0;
    if (p.z() < 0.0) return -p.z();
    return -std::min(1.0 - p.z(), p.z());
  };
  s.tolerance = 0.02;
  expect_through(run("solid-curve", s));
}

TEST(Overlap, DISABLED_SolidAndClosedMeshReadTheDepthReachedThroughContact) {  // not yet: see the point 2
  Sweep s;
  s.a = &cylinder();
  s.b = &small_box();
  s.from = Vec3(0, 0, 1.63);
  s.to = Vec3(0, 0, -0.61);
  s.exact = [](const Vec3& p) {
    if (p.z() > 1.2) return p.z() - 1.2;
    if (p.z() < -0.2) return -p.z() - 0.2;
    return -std::min(1.2 - p.z(), p.z() + 0.2);
  };
  s.tolerance = 0.02;
  expect_through(run("solid-closed mesh", s));
}

TEST(Overlap, AnOpenMeshInASolidReadsTheDepthReachedThroughContact) {
  // A square turned 30 degrees (z in [-0.2, 0.2] about its centre) down the cylinder's axis.
  Sweep s;
  s.a = &cylinder();
  s.b = &square();
  s.turn_b = about_x(k_tilt);
  s.from = Vec3(0, 0, 1.63);
  s.to = Vec3(0, 0, -0.61);
  s.exact = [](const Vec3& p) {
    if (p.z() > 1.2) return p.z() - 1.2;
    if (p.z() < -0.2) return -p.z() - 0.2;
    return -std::min(1.2 - p.z(), p.z() + 0.2);
  };
  s.tolerance = 0.02;
  expect_through(run("solid-open mesh", s));
}

TEST(Overlap, APointInASolidReadsMinusItsDistanceToTheSurface) {
  Sweep s;
  s.a = &cylinder();
  s.b = &point();
  s.from = Vec3(0.3, 0, 1.53);
  s.to = Vec3(0.3, 0, -0.47);
  s.exact = [](const Vec3& p) { return cylinder_signed_distance(1.0, 1.0, p); };
  s.tolerance = 1e-8;
  expect_through(run("solid-point", s));
}

TEST(Overlap, ABallInASolidReadsItsCentresSignedDistanceLessItsRadius) {
  static const Body ball = make_sphere_body(0.2, "ball");
  Sweep s;
  s.a = &cylinder();
  s.b = &ball;
  s.from = Vec3(0.3, 0, 1.53);
  s.to = Vec3(0.3, 0, -0.47);
  s.exact = [](const Vec3& p) { return cylinder_signed_distance(1.0, 1.0, p) - 0.2; };
  s.tolerance = 1e-8;
  expect_through(run("solid-ball", s));
}

// ---- Open sheet against ... -----------------------------------------------------------------

TEST(Overlap, TwoSheetsReadPenetratingOnlyWhileTheyCross) {
  // A 2 x 2 plane stood on its edge (turned about x), down through the floor plane and out:
  // crossing, the row is the crossing's local pair (no closed form: its sign is checked).
  static const Body wall = make_plane_body(2.0, 2.0, "wall");
  Sweep s;
  s.a = &plane();
  s.b = &wall;
  s.turn_b = about_x(M_PI / 2);
  s.from = Vec3(0.1, 0.2, 1.53);
  s.to = Vec3(0.1, 0.2, -1.47);
  s.exact = [](const Vec3& p) { return std::abs(p.z()) > 1.0 ? std::abs(p.z()) - 1.0 : NAN; };
  s.tolerance = 1e-6;
  expect_through(run("sheet-sheet", s));
}

TEST(Overlap, ACurveThroughASheetIsUnsignedAndZeroWhileItPiercesIt) {
  static const Body slanted = segment(Vec3(-1.5, 0, -0.6), Vec3(1.5, 0, 0.6), "slanted_rod");
  Sweep s;
  s.a = &plane();
  s.b = &slanted;
  s.sides = Sides::Unsigned;
  s.from = Vec3(0.1, 0.2, 1.03);
  s.to = Vec3(0.1, 0.2, -0.97);
  s.exact = [](const Vec3& p) { return std::max(std::abs(p.z()) - 0.6, 0.0); };
  s.tolerance = 1e-8;
  expect_through(run("sheet-curve", s));
}

TEST(Overlap, AClosedMeshThroughASheetKeepsItsEntrySidesDepthWhileTheSurfacesMeet) {
  Sweep s;
  s.a = &plane();
  s.b = &small_box();
  s.from = Vec3(0.1, 0.2, 0.73);
  s.to = Vec3(0.1, 0.2, -0.67);
  s.exact = [](const Vec3& p) { return std::abs(p.z()) >= 0.2 ? std::abs(p.z()) - 0.2 : p.z() - 0.2; };
  s.tolerance = 1e-6;
  s.one_shot_exact = false;  // (the hulls' depth)
  expect_through(run("sheet-closed mesh", s));
}

TEST(Overlap, AnOpenMeshThroughASheetIsUnsignedAndZeroWhileTheyCross) {
  Sweep s;
  s.a = &plane();
  s.b = &square();
  s.turn_b = about_x(k_tilt);
  s.sides = Sides::Unsigned;
  s.from = Vec3(0.1, 0.2, 0.73);
  s.to = Vec3(0.1, 0.2, -0.67);
  s.exact = [](const Vec3& p) { return std::max(std::abs(p.z()) - 0.2, 0.0); };
  s.tolerance = 1e-8;
  expect_through(run("sheet-open mesh", s));
}

TEST(Overlap, APointThroughASheetReadsItsUnsignedDistance) {
  // Through the plane at step 24 exactly: 0 there.
  Sweep s;
  s.a = &plane();
  s.b = &point();
  s.sides = Sides::Unsigned;
  s.from = Vec3(0.1, 0.2, 0.6);
  s.to = Vec3(0.1, 0.2, -0.6);
  s.exact = [](const Vec3& p) { return std::abs(p.z()); };
  s.tolerance = 1e-9;
  expect_through(run("sheet-point", s));
}

TEST(Overlap, ABallThroughASheetKeepsItsEntrySidesDepthWhileTheSurfacesMeet) {
  static const Body ball = make_sphere_body(0.3, "ball");
  Sweep s;
  s.a = &plane();
  s.b = &ball;
  s.from = Vec3(0.1, 0.2, 0.83);
  s.to = Vec3(0.1, 0.2, -0.77);
  s.exact = [](const Vec3& p) { return std::abs(p.z()) >= 0.3 ? std::abs(p.z()) - 0.3 : p.z() - 0.3; };
  s.tolerance = 1e-6;
  s.one_shot_exact = false;  // (the hulls' depth)
  expect_through(run("sheet-ball", s));
}

// ---- Curve against ... ----------------------------------------------------------------------

TEST(Overlap, TwoCurvesReadTheirUnsignedDistanceZeroWhereTheyCross) {
  Sweep s;
  s.a = &rod();
  s.b = &rod();
  s.turn_b = about_z(M_PI / 2);
  s.sides = Sides::Unsigned;
  s.from = Vec3(0.1, 0.2, 0.6);
  s.to = Vec3(0.1, 0.2, -0.6);
  s.exact = [](const Vec3& p) { return std::abs(p.z()); };
  s.tolerance = 1e-9;
  expect_through(run("curve-curve", s));
}

TEST(Overlap, ACurveInAClosedMeshReadsTheHullsDepth) {
  Sweep s;
  s.a = &large_box();
  s.b = &rod();
  s.from = Vec3(0, 0, 1.23);
  s.to = Vec3(0, 0, -1.17);
  s.exact = [](const Vec3& p) { return std::abs(p.z()) - 0.5; };
  s.tolerance = 0.02;
  expect_through(run("curve-closed mesh", s));
}

TEST(Overlap, ACurveThroughAnOpenMeshIsUnsignedAndZeroWhileItPiercesIt) {
  // A vertical rod (length 3) down through the flat square: it pierces it while |z| < 1.5.
  static const Body post = segment(Vec3(0, 0, -1.5), Vec3(0, 0, 1.5), "post");
  Sweep s;
  s.a = &floor_square();
  s.b = &post;
  s.sides = Sides::Unsigned;
  s.from = Vec3(0.1, 0.2, 2.23);
  s.to = Vec3(0.1, 0.2, -2.17);
  s.exact = [](const Vec3& p) { return std::max(std::abs(p.z()) - 1.5, 0.0); };
  s.tolerance = 1e-8;
  expect_through(run("curve-open mesh", s));
}

TEST(Overlap, APointThroughACurveReadsItsUnsignedDistance) {
  Sweep s;
  s.a = &rod();
  s.b = &point();
  s.sides = Sides::Unsigned;
  s.from = Vec3(0.5, 0, 0.6);
  s.to = Vec3(0.5, 0, -0.6);
  s.exact = [](const Vec3& p) { return std::abs(p.z()); };
  s.tolerance = 1e-9;
  expect_through(run("curve-point", s));
}

TEST(Overlap, ACurveThroughABallReadsTheBallsDepthAtItsNearestPoint) {
  // The centre's distance to the rod less the radius: the rod's point nearest the centre is
  // the deepest.
  static const Body ball = make_sphere_body(0.3, "ball");
  Sweep s;
  s.a = &rod();
  s.b = &ball;
  s.from = Vec3(0.2, 0, 0.83);
  s.to = Vec3(0.2, 0, -0.77);
  s.exact = [](const Vec3& p) { return std::abs(p.z()) - 0.3; };
  s.tolerance = 1e-5;  // (the step into overlap is the contact tracker's: 4.2e-6 off, then 1e-9)
  expect_through(run("curve-ball", s));
}

// ---- Closed mesh against ... ----------------------------------------------------------------

TEST(Overlap, TwoClosedMeshesReadTheirHullsDepthWhileTheyOverlap) {
  // Two convex boxes: the hulls' depth is the translation distance, along z until the side
  // (0.6 across x) is shallower.
  Sweep s;
  s.a = &large_box();
  s.b = &small_box();
  s.from = Vec3(0.1, 0, 1.03);
  s.to = Vec3(0.1, 0, -0.97);
  s.exact = [](const Vec3& p) {
    return std::abs(p.z()) >= 0.7 ? std::abs(p.z()) - 0.7 : -std::min(0.7 - std::abs(p.z()), 0.6);
  };
  s.tolerance = 1e-6;
  expect_through(run("closed mesh-closed mesh", s));
}

TEST(Overlap, AClosedMeshThroughAnOpenMeshKeepsItsEntrySidesDepthWhileTheSurfacesMeet) {
  // The small box (half size 0.2) down through the flat square, larger than it, and out.
  Sweep s;
  s.a = &floor_square();
  s.b = &small_box();
  s.from = Vec3(0.05, 0.1, 0.63);
  s.to = Vec3(0.05, 0.1, -0.57);
  s.exact = [](const Vec3& p) { return std::abs(p.z()) >= 0.2 ? std::abs(p.z()) - 0.2 : p.z() - 0.2; };
  s.tolerance = 1e-6;
  s.one_shot_exact = false;  // (the hulls' depth)
  expect_through(run("open mesh-closed mesh", s));
}

TEST(Overlap, AnOpenMeshInAClosedMeshReadsTheHullsDepth) {
  Sweep s;
  s.a = &large_box();
  s.b = &square();
  s.turn_b = about_x(k_tilt);
  s.from = Vec3(0, 0, 1.03);
  s.to = Vec3(0, 0, -0.97);
  // Out along z (0.7 - |z|: the square spans 0.2 above and below its centre), or, near the
  // middle, along the square's normal m = (0, -1/2, sqrt(3)/2): the box's support there is
  // (1 + sqrt(3)) / 4, less the centre's offset along m.
  s.exact = [](const Vec3& p) {
    const double along_normal = 0.25 * (1.0 + std::sqrt(3.0)) - 0.5 * std::sqrt(3.0) * std::abs(p.z());
    return std::abs(p.z()) - 0.7 >= 0.0 ? std::abs(p.z()) - 0.7
                                         : -std::min(0.7 - std::abs(p.z()), along_normal);
  };
  s.tolerance = 1e-6;
  expect_through(run("closed mesh-open mesh", s));
}

TEST(Overlap, APointInAClosedMeshReadsMinusItsDistanceToTheSurface) {
  Sweep s;
  s.a = &large_box();
  s.b = &point();
  s.from = Vec3(0.3, 0, 0.83);
  s.to = Vec3(0.3, 0, -0.77);
  s.exact = [](const Vec3& p) { return box_signed_distance(k_large_box, p); };
  s.tolerance = 1e-9;
  expect_through(run("closed mesh-point", s));
}

TEST(Overlap, ABallInAClosedMeshReadsItsCentresSignedDistanceLessItsRadius) {
  // (Off the wall: at x = 0.3 the ball would touch it from within all the way.)
  static const Body ball = make_sphere_body(0.2, "ball");
  Sweep s;
  s.a = &large_box();
  s.b = &ball;
  s.from = Vec3(0.2, 0, 1.03);
  s.to = Vec3(0.2, 0, -0.97);
  s.exact = [](const Vec3& p) { return box_signed_distance(k_large_box, p) - 0.2; };
  s.tolerance = 1e-8;
  expect_through(run("closed mesh-ball", s));
}

// ---- Open mesh against ... ------------------------------------------------------------------

TEST(Overlap, TwoOpenMeshesAreUnsignedAndZeroWhileTheyCross) {
  Sweep s;
  s.a = &floor_square();
  s.b = &square();
  s.turn_b = about_x(k_tilt);
  s.sides = Sides::Unsigned;
  s.from = Vec3(0.05, 0, 0.73);
  s.to = Vec3(0.05, 0, -0.67);
  s.exact = [](const Vec3& p) { return std::max(std::abs(p.z()) - 0.2, 0.0); };
  s.tolerance = 1e-9;
  expect_through(run("open mesh-open mesh", s));
}

TEST(Overlap, APointThroughAnOpenMeshReadsItsUnsignedDistance) {
  Sweep s;
  s.a = &floor_square();
  s.b = &point();
  s.sides = Sides::Unsigned;
  s.from = Vec3(0.1, 0.2, 0.6);
  s.to = Vec3(0.1, 0.2, -0.6);
  s.exact = [](const Vec3& p) { return std::abs(p.z()); };
  s.tolerance = 1e-9;
  expect_through(run("open mesh-point", s));
}

TEST(Overlap, ABallThroughAnOpenMeshKeepsItsEntrySidesDepthWhileTheSurfacesMeet) {
  static const Body ball = make_sphere_body(0.3, "ball");
  Sweep s;
  s.a = &floor_square();
  s.b = &ball;
  s.from = Vec3(0.1, 0.1, 0.83);
  s.to = Vec3(0.1, 0.1, -0.77);
  s.exact = [](const Vec3& p) { return std::abs(p.z()) >= 0.3 ? std::abs(p.z()) - 0.3 : p.z() - 0.3; };
  s.tolerance = 1e-6;
  s.one_shot_exact = false;  // (the hulls' depth)
  expect_through(run("open mesh-ball", s));
}

// ---- Point and ball against ... -------------------------------------------------------------

TEST(Overlap, TwoPointsReadTheirDistanceZeroWhereTheyMeet) {
  Sweep s;
  s.a = &point();
  s.b = &point();
  s.sides = Sides::Unsigned;
  s.from = Vec3(0, 0, 0.6);
  s.to = Vec3(0, 0, -0.6);
  s.exact = [](const Vec3& p) { return std::abs(p.z()); };
  s.tolerance = 1e-12;
  expect_through(run("point-point", s));
}

TEST(Overlap, APointInABallReadsMinusItsDistanceToTheSphere) {
  static const Body ball = make_sphere_body(0.3, "ball");
  Sweep s;
  s.a = &point();
  s.b = &ball;
  s.from = Vec3(0.1, 0, 0.83);
  s.to = Vec3(0.1, 0, -0.77);
  s.exact = [](const Vec3& p) { return p.norm() - 0.3; };
  s.tolerance = 1e-9;
  expect_through(run("point-ball", s));
}

TEST(Overlap, TwoBallsReadTheirCentresDistanceLessTheRadii) {
  static const Body a = make_sphere_body(0.5, "ball_a"), b = make_sphere_body(0.3, "ball_b");
  Sweep s;
  s.a = &a;
  s.b = &b;
  s.from = Vec3(0.2, 0, 1.23);
  s.to = Vec3(0.2, 0, -1.17);
  s.exact = [](const Vec3& p) { return p.norm() - 0.8; };
  s.tolerance = 1e-9;
  expect_through(run("ball-ball", s));
}

}  // namespace
}  // namespace extremal
