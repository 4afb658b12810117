// A cylinder's rim pressed into a flat face: a peg tilted over a plate or a sheet, tumbling on a
// box. The deepest point is on an edge of the cylinder (a cap's rim), where neither surface's
// normal gives the pair's direction: the plate's does, and its witness is the foot of the rim
// point. Every case has a closed form (the rim's lowest point below the face), checked at every
// row.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <string>

#include "algorithms/body_pair/Body_pair_tracker.h"
#include "algorithms/distance/Distance_hierarchy.h"
#include "algorithms/distance/Penetration_depth.h"
#include "io/Model_reader.h"
#include "kernel/Shapes.h"

namespace extremal {
namespace {

std::string shared_data(const std::string& rel) { return std::string(EXTREMAL_SHARED_DATA) + "/" + rel; }

constexpr double k_radius = 10.0, k_height = 40.0;  // the peg, mm; its origin is its base centre

// The peg turned by `tilt` about x with its base centre at `base`.
Rigid_pose_3 peg_pose(const Vec3& base, double tilt) {
  return Rigid_pose_3(Eigen::AngleAxisd(tilt, Vec3::UnitX()).toRotationMatrix(), base);
}

// Height of the peg's lowest point above the plane z = top, its base at `base`, turned by `tilt`
// (either rim's lowest point: the far one once the axis points below the horizontal).
double lowest_above(const Vec3& base, double tilt, double top) {
  const double rim = k_radius * std::abs(std::sin(tilt));
  return base.z() - top + std::min(-rim, k_height * std::cos(tilt) - rim);
}

// The peg tilted by each of `tilts`, its base from 5 mm above the plane z = 200 (x = y = 100)
// down at 5 mm/s for 2 s, 100 steps a second, against `plate` at rest: every row is the rim's
// lowest point below the plane, never of the wrong sign.
void expect_rim_depth(const Body& plate, const Rigid_pose_3& X_plate,
                      std::initializer_list<double> tilts) {
  const Body peg = make_cylinder_body(k_radius, k_height);
  const double dt = 0.01;
  const Vec3 v(0.0, 0.0, -5.0);
  for (const double tilt : tilts) {
    Body_pair_tracker tracker(peg, plate);
    double worst = 0.0;  // largest |reported - exact|
    int wrong_sign = 0;  // rows read apart while overlapping by more than 1e-3, or the reverse
    for (int i = 0; i <= 200; ++i) {
      const double t = i * dt;
      const Vec3 base = Vec3(100.0, 100.0, 205.0) + v * t;
      const Pair_report& r =
          tracker.step(t, peg_pose(base, tilt), Twist_3{v, Vec3::Zero()}, X_plate, Twist_3{}, dt);
      EXPECT_TRUE(std::isfinite(r.distance)) << "t = " << t;
      const double exact = lowest_above(base, tilt, 200.0);
      worst = std::max(worst, std::abs(r.distance - exact));
      if (std::abs(exact) > 1e-3 && (r.distance > 0.0) != (exact > 0.0)) ++wrong_sign;
    }
    EXPECT_LE(worst, 1e-8) << "tilt " << tilt;
    EXPECT_EQ(wrong_sign, 0) << "tilt " << tilt;
  }
}

// Into an open sheet: with the cap's rim held on its edge, the pair's sign was read from the
// cap's normal, which says nothing there, and the depth read as a gap; the side's and the cap's
// trackers off the rim read along their own normals (-4.77 for a rim 7.96 deep). The sign of a
// pair held on A's edge is B's normal's, whose witness is the foot of d.
TEST(RimContact, ATiltedPegPressedIntoASheetReadsItsRimsDepth) {
  const Body sheet = make_plane_body(400.0, 400.0);
  expect_rim_depth(sheet, Rigid_pose_3(Mat3::Identity(), Vec3(100.0, 100.0, 200.0)), {0.05, 0.3});
}

// Into pr2ct's box (a 200 mm cube from a STEP file, its top at z = 200): Newton let the rim
// go at random, the normal form's row for the held rim parameter being one no step can zero on a
// flat cap, and the cap's interior then read along its own normal; deeper, the projection
// form counted the rim parameter's error (0.3) as the pair being far, sought a minimum and slid
// off the deepest rim point. Rows read up to 10.7 off (tilt 1), or apart by 0.8 with the rim
// 5.1 deep (the cap's rim point above the face).
TEST(RimContact, ATiltedPegPressedIntoABoxReadsItsRimsDepth) {
  const io::Model m = io::read_model(shared_data("step/pr2ct.stp"));
  ASSERT_EQ(m.bodies.size(), 1u);
  expect_rim_depth(m.bodies[0], m.bodies[0].placement, {0.05, 0.3, 1.0});
}

// The one-shot solver's common-point search started on the rim: its minimum-norm step pushed
// the cap's radius past the rim, and clamped there it stalled. The bodies read 7e-11 apart,
// 'converged' and certified, with the rim 5.1 deep.
TEST(RimContact, TheOneShotSolverSeesARimCrossingAFace) {
  const io::Model m = io::read_model(shared_data("step/pr2ct.stp"));
  ASSERT_EQ(m.bodies.size(), 1u);
  const Body& box = m.bodies[0];
  const Body peg = make_cylinder_body(k_radius, k_height);
  for (const double z : {197.85, 197.9, 199.0}) {
    const Vec3 base(100.0, 100.0, z);
    const Signed_distance_result r = signed_distance(peg, peg_pose(base, 0.3), box, box.placement);
    EXPECT_TRUE(r.is_certified()) << "z = " << z;
    EXPECT_EQ(r.overlap, Overlap_kind::Surfaces_meet) << "z = " << z;
    EXPECT_NEAR(r.distance, lowest_above(base, 0.3, 200.0), 1e-8) << "z = " << z;
  }
}

// A peg turned by `tilt`, its base from `base` down at `v` for 100 steps of 0.02 s against
// `other` at rest: the largest |reported - signed_distance| over the rows from `from` on, every
// `stride`-th (`compared` counts them).
double worst_against_certified(const Body& peg, const Body& other, const Mat3& tilt,
                               const Vec3& base, const Vec3& v, double from, int stride,
                               int& compared) {
  Body_pair_tracker tracker(peg, other);
  const double dt = 0.02;
  double worst = 0.0;
  compared = 0;
  for (int i = 0; i <= 100; ++i) {
    const double t = i * dt;
    const Rigid_pose_3 X_peg(tilt, base + v * t);
    const Pair_report& r =
        tracker.step(t, X_peg, Twist_3{v, Vec3::Zero()}, Rigid_pose_3(), Twist_3{}, dt);
    EXPECT_TRUE(std::isfinite(r.distance)) << "t = " << t;
    if (t < from || i % stride != 0) continue;
    const Signed_distance_result e = signed_distance(peg, X_peg, other, Rigid_pose_3());
    EXPECT_TRUE(e.is_certified()) << "t = " << t;
    worst = std::max(worst, std::abs(r.distance - e.distance));
    ++compared;
  }
  return worst;
}

// The peg tilted 0.4 rad about y, its base centre 2 mm inside a sheet's border (x = 100), down
// at 3 mm/s through the sheet: its cap's tracker sat where the cap crosses the sheet, d = 0 with
// the normals 0.39 rad apart, and read 'contact' while 0.02 to 1.6 deep (30 rows). At d = 0 a
// singular system is a touching edge only where a witness is on an edge; two faces' interior
// points there are a crossing. Every other row from t = 0.9 (the crossing starts near 1.05)
// against the certified signed distance.
TEST(RimContact, ATiltedPegThroughASheetsBorderReadsItsDepth) {
  int compared = 0;
  const double worst = worst_against_certified(
      make_cylinder_body(k_radius, k_height), make_plane_body(200.0, 200.0),
      Eigen::AngleAxisd(0.4, Vec3::UnitY()).toRotationMatrix(), Vec3(98.0, 0.0, 4.0),
      Vec3(0.0, 0.0, -3.0), 0.9, 2, compared);
  EXPECT_GT(compared, 20);
  EXPECT_LE(worst, 1e-6);
}

// A peg of radius 0.01 tilted 0.5 rad, its rim pressed onto the top of a ball of radius 0.025,
// near the ball's pole: holding the rim by the height over the ball's tangent plane there (the
// pole's limit normal) kept the ball's witness on its pole, up to 2.6 times too deep (28 rows).
// Past the first two rows of the contact (near t = 0.65) every third row is the certified
// signed distance.
TEST(RimContact, ATiltedPegsRimOnASmallBallsPoleReadsItsDepth) {
  int compared = 0;
  const double worst = worst_against_certified(
      make_cylinder_body(0.01, 0.04), make_sphere_body(0.025),
      Eigen::AngleAxisd(0.5, Vec3::UnitX()).toRotationMatrix(), Vec3(0.0, 0.009, 0.033),
      Vec3(0.0, 0.0, -0.005), 0.7, 3, compared);
  EXPECT_GT(compared, 15);
  EXPECT_LE(worst, 0.025 * 1e-7);  // 1e-7 of the ball's radius
}

// Tumbling on the box about its base centre, the base first flush on the top face: the
// bottom rim's depth grows to 10 at a quarter turn, then the far rim enters and goes deeper
// (25.7 at 2 rad). The tracker on the bottom rim kept it, -9.1: the hulls' depth, deeper than
// every tracked pair, with each witness inside the other body, is a pair of the bodies' own
// that no tracker saw arise, and gets one. Between the checks (each time the box's centre has
// moved a tenth of the peg's size relative to it) a new rim can go unseen for a few steps.
TEST(RimContact, APegTumblingOnABoxReadsItsFarRimOnceItIsTheDeeper) {
  const io::Model m = io::read_model(shared_data("step/pr2ct.stp"));
  ASSERT_EQ(m.bodies.size(), 1u);
  const Body& box = m.bodies[0];
  const Body peg = make_cylinder_body(k_radius, k_height);
  const double dt = 0.01, spin = 1.0;
  const Vec3 base(100.0, 100.0, 200.0);
  // Either order: the check reads either body's centre as seen from the other (with only the
  // box's centre in the peg's frame, the box first left the far rim unseen 20 steps, 7.9 off).
  for (const bool peg_first : {true, false}) {
    Body_pair_tracker tracker(peg_first ? peg : box, peg_first ? box : peg);
    double worst_late = 0.0, worst = 0.0;
    int wrong_sign = 0;
    for (int i = 0; i <= 200; ++i) {
      const double t = i * dt;
      const Rigid_pose_3 X_peg = peg_pose(base, spin * t);
      const Twist_3 V_peg{Vec3::Zero(), Vec3(spin, 0.0, 0.0)};
      const Pair_report& r =
          peg_first ? tracker.step(t, X_peg, V_peg, box.placement, Twist_3{}, dt)
                    : tracker.step(t, box.placement, Twist_3{}, X_peg, V_peg, dt);
      EXPECT_TRUE(std::isfinite(r.distance)) << "t = " << t;
      const double exact = std::min(0.0, lowest_above(base, spin * t, 200.0));
      const double error = std::abs(r.distance - exact);
      worst = std::max(worst, error);
      if (t >= 1.7) worst_late = std::max(worst_late, error);
      if (exact < -1e-3 && r.distance > 0.0) ++wrong_sign;
    }
    EXPECT_LE(worst_late, 1e-6) << (peg_first ? "peg first" : "box first");
    // The far rim, unseen for at most five steps at 0.4 a step.
    EXPECT_LE(worst, 2.0) << (peg_first ? "peg first" : "box first");
    EXPECT_EQ(wrong_sign, 0) << (peg_first ? "peg first" : "box first");
  }
}

// as1 (an assembly of 18 solids): a bolt's round head seated on a bracket's flange, its rim
// at the flange's edge, and a nut seated under the plate. The tracker's normal form held the
// head's rim point and a point of the flange 0.475 from it, d along the head's normal and across
// the flange's face (no foot there): read as a 0.475 interference, and 0.025 for the nut. The
// parts touch, flush.
TEST(RimContact, PartsSeatedFlushInAnAssemblyTouchWithoutInterference) {
  const io::Model m = io::read_model(shared_data("step/as1-oc-214-mat.stp"));
  auto body = [&](const char* name) -> const Body& {
    for (const Body& b : m.bodies)
      if (b.name == name) return b;
    ADD_FAILURE() << "no body " << name;
    return m.bodies.front();
  };
  struct Seated {
    const char *a, *b;
  };
  for (const Seated s : {Seated{"bolt_1#3", "l-bracket_1#1"}, Seated{"nut_3#2", "plate_1"},
                         Seated{"bolt_1#4", "l-bracket_1#2"}}) {
    const Body &a = body(s.a), &b = body(s.b);
    Body_pair_tracker tracker(a, b);
    const Pair_report& r = tracker.step(0.0, a.placement, Twist_3{}, b.placement, Twist_3{}, 1e-3);
    EXPECT_LE(std::abs(r.distance), 1e-6) << s.a << " on " << s.b;
    EXPECT_EQ(r.status, Pair_status::Contact) << s.a << " on " << s.b;
    EXPECT_NEAR(r.normal.norm(), 1.0, 1e-9) << s.a << " on " << s.b;
  }
  // The truth, independently: no point of the bolt's faces (sampled on an 8 x 8 grid of each)
  // lies inside the bracket, whose hole fits the shank (radius 5, axis at x = 47.5, y = 87.99).
  const Body &bolt = body("bolt_1#3"), &bracket = body("l-bracket_1#1");
  const Distance_hierarchy H(bracket);
  int sampled = 0, inside = 0;
  for (const Face& f : bolt.faces)
    for (int i = 0; i < 8; ++i)
      for (int j = 0; j < 8; ++j) {
        const Nurbs_surface_3& s = f.surface;
        const double u = s.u_min() + (s.u_max() - s.u_min()) * i / 7.0;
        const double v = s.v_min() + (s.v_max() - s.v_min()) * j / 7.0;
        if (!f.contains(u, v)) continue;
        const Point_3 p = s.point(u, v);
        ++sampled;
        if (inside_body(H, bracket.placement, bolt.placement.apply_point(Vec3(p.x(), p.y(), p.z()))))
          ++inside;
      }
  EXPECT_GT(sampled, 200);
  EXPECT_EQ(inside, 0);
  const double axis_x = 47.5, axis_y = 87.990381, z = 25.0;  // in the flange, round the hole
  EXPECT_FALSE(inside_body(H, bracket.placement, Vec3(axis_x + 4.9, axis_y, z)));
  EXPECT_TRUE(inside_body(H, bracket.placement, Vec3(axis_x + 5.1, axis_y, z)));
}

}  // namespace
}  // namespace extremal
