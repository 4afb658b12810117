// A peg pressed into a box's top sliding off past its side, or onto the top from beside it.
// Past the box's edge the depth changes hands between the top and the side: the shallower is
// the depth (the least translation that parts them), and the pair that came in through
// contact may stop being it without the bodies moving far. Upright, every row has a closed
// form; tilted, sampled rows are checked against the certified signed distance.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <string>

#include "algorithms/body_pair/Body_pair_tracker.h"
#include "algorithms/distance/Penetration_depth.h"
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

// The upright peg's base at (x, y, z) against the box, z < 200 < z + 40: both bodies are prisms
// (a disc and a square swept along z), so their signed distance combines the disc's against the
// square in the plane with the heights'. Both overlapping, the shallower of the two depths (the
// plane's: the disc's depth across the square's nearest side, or past a corner its depth to the
// corner); the disc clear of the square, its gap (past x = 210 at y = 100 the peg is beside the
// box).
double upright_exact(double x, double y, double z) {
  const double dx = std::max({0.0, -x, x - 200.0}), dy = std::max({0.0, -y, y - 200.0});
  const double plane = dx > 0.0 || dy > 0.0
                           ? std::hypot(dx, dy) - k_radius
                           : -(k_radius + std::min({x, 200.0 - x, y, 200.0 - y}));
  return plane > 0.0 ? plane : std::max(plane, z - 200.0);
}

// The upright peg, its base at height z, from (x0, y0) at (vx, vy) for 1 s in 100 steps, each
// row against the closed form: the largest |reported - exact| and the rows off by more than
// 1e-8; wrong_sign counts rows read apart while 1e-3 deep, or the reverse, and solved the rows
// no tracker held (the certified solver's, solved again each such step).
struct Upright_run {
  double worst = 0.0;
  int off = 0, wrong_sign = 0, solved = 0;
};
Upright_run run_upright(double x0, double y0, double vx, double vy, double z) {
  const Body peg = make_cylinder_body(k_radius, k_height);
  Body_pair_tracker tracker(peg, box());
  const double dt = 0.01;
  const Vec3 v(vx, vy, 0.0);
  Upright_run run;
  for (int i = 0; i <= 100; ++i) {
    const double t = i * dt, x = x0 + vx * t, y = y0 + vy * t;
    const Pair_report& r = tracker.step(t, Rigid_pose_3(Mat3::Identity(), Vec3(x, y, z)),
                                        Twist_3{v, Vec3::Zero()}, box().placement, Twist_3{}, dt);
    EXPECT_TRUE(std::isfinite(r.distance)) << "t = " << t;
    const double exact = upright_exact(x, y, z), error = std::abs(r.distance - exact);
    run.worst = std::max(run.worst, error);
    if (error > 1e-8) ++run.off;
    if (std::abs(exact) > 1e-3 && (r.distance > 0.0) != (exact > 0.0)) ++run.wrong_sign;
    if (r.solved) ++run.solved;
  }
  return run;
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
    const Upright_run r = run_upright(run.x0, 100.0, run.vx, 0.0, run.z);
    EXPECT_LE(r.worst, 1e-8) << "z = " << run.z;
    EXPECT_EQ(r.wrong_sign, 0) << "z = " << run.z;
    EXPECT_EQ(r.solved, 0) << "z = " << run.z;
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
  const Upright_run r = run_upright(230.0, 100.0, -60.0, 0.0, 196.0);
  EXPECT_LE(r.worst, 1e-8);
  EXPECT_EQ(r.wrong_sign, 0);
  EXPECT_EQ(r.solved, 0);
}

// The upright peg at 50 mm/s, `degrees` to x, through (205, 205) past the box's corner a
// `phase` (a fraction of a step) before t = 0.55, its base at z; prints the run's figures.
Upright_run run_past_corner(double degrees, double phase, double z) {
  const double a = degrees * M_PI / 180.0, vx = 50.0 * std::cos(a), vy = 50.0 * std::sin(a);
  const double before = 0.55 - 0.01 * phase;
  const Upright_run r = run_upright(205.0 - before * vx, 205.0 - before * vy, vx, vy, z);
  std::printf("z = %g, %g degrees, phase %.2f: worst %.3g, %d rows off, %d solved\n", z, degrees,
              phase, r.worst, r.off, r.solved);
  return r;
}

// Slid off the box's corner, 2 to 8 deep, in five directions at three phases, and diagonally 3
// deep from three starts: past the corner the disc's depth to it becomes the least, and no
// frame axis bounds that (along each the boxes overlap by more). The corner's pair (the peg's
// side against the top face's border or the box's top edge there) was tracked from its first
// depth, but what was reported was the cap's stale depth, the deeper, until the motion check:
// the corner's pair held nothing, not having come in through contact, or held and was
// shallower. Its becoming the shallower depth now triggers that check. Before, 33 of these 63
// runs had rows off (up to 2.76).
TEST(EdgeSlide, APegSlidOffABoxsCornerReadsTheShallowerDepth) {
  for (const double start : {180.0, 181.5, 182.5}) {
    const Upright_run r = run_upright(start, start, 40.0, 40.0, 197.0);
    EXPECT_LE(r.worst, 1e-8) << "start " << start;
    EXPECT_EQ(r.wrong_sign, 0) << "start " << start;
    EXPECT_EQ(r.solved, 0) << "start " << start;
  }
  for (const double z : {192.0, 195.0, 197.0, 198.0})
    for (const double degrees : {20.0, 30.0, 45.0, 60.0, 75.0})
      for (const double phase : {0.0, 1.0 / 3.0, 2.0 / 3.0}) {
        const Upright_run r = run_past_corner(degrees, phase, z);
        EXPECT_LE(r.worst, 1e-8) << degrees << " degrees, phase " << phase << ", z = " << z;
        EXPECT_EQ(r.wrong_sign, 0) << degrees << " degrees, phase " << phase << ", z = " << z;
        // (2 deep at 30 and 60 degrees, one or two rows are the certified solver's: exact,
        // but no tracker held them.)
        EXPECT_LE(r.solved, z < 198.0 ? 0 : 2)
            << degrees << " degrees, phase " << phase << ", z = " << z;
      }
}

// Slid off the box's corner 1 deep, in the five directions at three phases, diagonally from two
// starts, and 5 deep diagonally from 187.45 (50 mm/s). Two things kept the cap's stale depth for
// the last rows before the peg came apart (1 deep: 11 of the 15 runs, up to 0.51 off, diagonally
// 0.76; 5 deep: 4 rows, up to 1.76):
// - the corner's pair (the peg's side against the box's vertical edge) had no tracker while the
//   peg was inside: seeded apart, it had moved onto a face's pair, and a pair was seeded once
//   in contact. A pair seeded apart is now seeded again once the motion may have closed the gap
//   its seed's solve certified;
// - the corner's pair held and was shallower, the deep check dropped the cap's pair as stale,
//   and the contact seeding seeded it again at once. A seed deeper than the depth now runs the
//   deep check before it is read.
// Some rows are the certified solver's (exact; up to 4 of a run at 30, 60 and 75 degrees):
// past the corner, the cap's pair sits on a continuum of equal depth whose centre has left the
// top face, and no tracker holds until the corner's depth is seeded.
TEST(EdgeSlide, APegOneDeepSlidOffABoxsCornerReadsTheShallowerDepth) {
  for (const double degrees : {20.0, 30.0, 45.0, 60.0, 75.0})
    for (const double phase : {0.0, 1.0 / 3.0, 2.0 / 3.0}) {
      const Upright_run r = run_past_corner(degrees, phase, 199.0);
      EXPECT_LE(r.worst, 1e-8) << degrees << " degrees, phase " << phase;
      EXPECT_EQ(r.wrong_sign, 0) << degrees << " degrees, phase " << phase;
      EXPECT_LE(r.solved, 4) << degrees << " degrees, phase " << phase;
    }
  for (const double start : {180.0, 182.5}) {
    const Upright_run r = run_upright(start, start, 40.0, 40.0, 199.0);
    EXPECT_LE(r.worst, 1e-8) << "start " << start;
    EXPECT_EQ(r.wrong_sign, 0) << "start " << start;
    EXPECT_EQ(r.solved, 0) << "start " << start;
  }
  const Upright_run r = run_upright(187.4546, 187.4546, 35.3553, 35.3553, 195.0);
  EXPECT_LE(r.worst, 1e-8);
  EXPECT_EQ(r.wrong_sign, 0);
  EXPECT_EQ(r.solved, 0);
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
