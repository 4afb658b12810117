// A peg pressed into a box's top sliding off past its side, or onto the top from beside it.
// Past the box's edge the depth changes hands between the top and the side: the shallower is
// the depth (the least translation that parts them), and the pair that came in through
// contact may stop being it without the bodies moving far. Upright, every row has a closed
// form; tilted, sampled rows are checked against the certified signed distance.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <string>

#include "algorithms/Body_pair_tracker.h"
#include "algorithms/Penetration_depth.h"
#include "io/Model_reader.h"
#include "kernel/Shapes.h"

namespace extremal {
namespace {

std::string shared_data(const std::string& rel) { return std::string(EXTREMAL_SHARED_DATA) + "/" + rel; }

constexpr double k_radius = 10.0, k_height = 40.0;  // the peg, mm; its origin is its base centre

// pr2ct's box: a 200 mm cube from a STEP file, [0, 200]^3.
const Body& box() {
  static const io::Model m = io::read_model(shared_data("step/pr2ct.stp"));
  return m.bodies.at(0);
}

// The upright peg's base at (x, 100, z) against the box, z < 200: its depth is the top's,
// 200 - z, or the side's, 210 - x, whichever is less; past x = 210 it is beside the box.
double upright_exact(double x, double z) {
  const double side = 210.0 - x;
  return side <= 0.0 ? -side : -std::min(200.0 - z, side);
}

// The upright peg, its base at height z, from x0 at vx for 1 s in 100 steps: the largest
// |reported - exact|; wrong_sign counts rows read apart while 1e-3 deep, or the reverse, and
// solved the rows no tracker held (the certified solver's, solved again each such step).
double worst_upright(double x0, double vx, double z, int& wrong_sign, int& solved) {
  const Body peg = make_cylinder_body(k_radius, k_height);
  Body_pair_tracker tracker(peg, box());
  const double dt = 0.01;
  const Vec3 v(vx, 0.0, 0.0);
  double worst = 0.0;
  wrong_sign = solved = 0;
  for (int i = 0; i <= 100; ++i) {
    const double t = i * dt, x = x0 + vx * t;
    const Pair_report& r = tracker.step(t, Rigid_pose_3(Mat3::Identity(), Vec3(x, 100.0, z)),
                                        Twist_3{v, Vec3::Zero()}, box().placement, Twist_3{}, dt);
    EXPECT_TRUE(std::isfinite(r.distance)) << "t = " << t;
    const double exact = upright_exact(x, z);
    worst = std::max(worst, std::abs(r.distance - exact));
    if (std::abs(exact) > 1e-3 && (r.distance > 0.0) != (exact > 0.0)) ++wrong_sign;
    if (r.solved) ++solved;
  }
  return worst;
}

// Slid off past the side (x from 170 or 180): the side's depth takes over once shallower.
// - 4 deep: the box's top edge against the peg's side, the side's point outside the box,
//   read 4.6 growing to 9.4 (their normals perpendicular: the edge's other face, the side,
//   is the one the peg's normal opposes, and it points the other way). The side's depth then
//   read 4 (the top's) for three steps past where it was shallower, until the motion check.
// - 1 and 8 deep: the top's depth held a step or two past the side's (by 0.2 and 0.4).
// A translation that parts the boxes parts the bodies: a reading deeper than the boxes'
// overlap is no depth, and the check runs once the tracked one is deeper than it. Every row is
// a tracker's: 8 deep, the hulls' pair on the side sat at the box's top edge, where neither
// witness is inside the other body, and no tracker took it (8 rows solved again each step)
// until it started from the faces at that edge.
TEST(EdgeSlide, APegSlidOffABoxsSideReadsTheShallowerDepth) {
  struct Run {
    double x0, vx, z;
  };
  for (const Run run : {Run{170.0, 60.0, 196.0}, Run{180.0, 40.0, 199.0}, Run{170.0, 60.0, 192.0}}) {
    int wrong_sign = 0, solved = 0;
    EXPECT_LE(worst_upright(run.x0, run.vx, run.z, wrong_sign, solved), 1e-8) << "z = " << run.z;
    EXPECT_EQ(wrong_sign, 0) << "z = " << run.z;
    EXPECT_EQ(solved, 0) << "z = " << run.z;
  }
}

// Slid onto the top from beside the box, 4 deep: the side's pair it came in by went on
// deepening past the top's depth (4.6 to 6.4 against 4), the top's pair not reached through
// contact. Past the boxes' bound no reading holds, and the hulls' pair, on the box's top edge,
// is tracked from the faces there (before, 26 rows were solved again each step). Further on,
// the box's top edge through the peg's side read 0 'contact' (the edge crossing the side, not
// touching it), and the peg's side past the box, outside it, read 2.8 to 0.4 deep against the
// edge.
TEST(EdgeSlide, APegSlidOntoABoxsTopFromItsSideReadsTheShallowerDepth) {
  int wrong_sign = 0, solved = 0;
  EXPECT_LE(worst_upright(230.0, -60.0, 196.0, wrong_sign, solved), 1e-8);
  EXPECT_EQ(wrong_sign, 0);
  EXPECT_EQ(solved, 0);
}

// Tilted 0.3 rad about y, 2 deep, slid off the side and back onto the top: the tilted cap's rim
// crossing the side face read 0 'contact' with the peg 3.3 to 4.4 deep. Every other row of the
// transition (t from 0.2 to 0.6) against the certified signed distance.
TEST(EdgeSlide, ATiltedPegSlidAcrossABoxsEdgeReadsItsDepth) {
  const Body peg = make_cylinder_body(k_radius, k_height);
  const Mat3 tilt = Eigen::AngleAxisd(0.3, Vec3::UnitY()).toRotationMatrix();
  for (const double vx : {60.0, -60.0}) {
    Body_pair_tracker tracker(peg, box());
    const double dt = 0.01;
    const Vec3 v(vx, 0.0, 0.0), start(vx > 0.0 ? 170.0 : 230.0, 100.0, 198.0);
    double worst = 0.0;
    int compared = 0;
    for (int i = 0; i <= 60; ++i) {
      const double t = i * dt;
      const Rigid_pose_3 X_peg(tilt, start + v * t);
      const Pair_report& r =
          tracker.step(t, X_peg, Twist_3{v, Vec3::Zero()}, box().placement, Twist_3{}, dt);
      EXPECT_TRUE(std::isfinite(r.distance)) << "t = " << t;
      if (i < 20 || i % 2 != 0) continue;
      const Signed_distance_result e = signed_distance(peg, X_peg, box(), box().placement);
      EXPECT_TRUE(e.is_certified()) << "t = " << t;
      worst = std::max(worst, std::abs(r.distance - e.distance));
      ++compared;
    }
    EXPECT_EQ(compared, 21);
    EXPECT_LE(worst, 1e-6) << "vx = " << vx;
  }
}

}  // namespace
}  // namespace extremal
