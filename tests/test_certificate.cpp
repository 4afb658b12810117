// The error budget's certificate (Body_pair_options::tolerance, Pair_report::lower_bound):
// every apart row of seeded random scenes carries a lower bound that the certified one-shot
// solver at the same poses confirms (at most the true distance), and the row's distance is
// within the budget of the true one, at budgets 1e-3 and 1e-9.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "algorithms/body_pair/Body_pair_tracker.h"
#include "algorithms/distance/Global_distance.h"
#include "io/Model_reader.h"
#include "kernel/Motion.h"
#include "kernel/Shapes.h"
#include "support/Random.h"

namespace extremal {
namespace {

// Two spheres in one body: two basins of every pair with a third body, often nearly tied.
Body twin_spheres() {
  Body b = make_sphere_body(1.0, "twins");
  b.faces.clear();
  b.faces.push_back({transformed(make_sphere(1.0), Rigid_pose_3(Mat3::Identity(), Vec3(-1.6, 0, 0))), "left"});
  b.faces.push_back({transformed(make_sphere(1.0), Rigid_pose_3(Mat3::Identity(), Vec3(1.6, 0, 0))), "right"});
  return b;
}

// A bumpy bicubic sheet 6 x 6 (non-convex, open).
Body bumpy_sheet() {
  std::vector<Point_3> poles;
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 5; ++i)
      poles.emplace_back(-3.0 + 1.5 * i, -3.0 + 1.5 * j, ((i + j) % 2 == 0 ? 0.6 : -0.4));
  Body b;
  b.name = "sheet";
  b.faces.push_back({make_freeform(3, 3, 5, 5, poles), "bumps"});
  return b;
}

struct Budget_run {
  int apart_rows = 0, checked_rows = 0, uncertified_rows = 0;
  double worst_excess = 0.0;  // largest (row distance - true distance) / budget
};

// B moves by a random screw motion past A (static at the origin), tracked at the budget;
// every apart row is checked against the one-shot solver at 1e-12.
Budget_run run_scene(const Body& a, const Body& b, std::mt19937_64& rng, double spread,
                     const Error_budget& budget, int steps) {
  Body_pair_options options;
  options.tolerance = budget;
  Body_pair_tracker tracker(a, b, options);
  const Rigid_pose_3 start = test::random_pose(rng, spread);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Twist_3 v;
  v.linear = Vec3(u(rng), u(rng), u(rng)) * (0.5 * spread);
  v.angular = Vec3(u(rng), u(rng), u(rng)) * 1.5;
  const Motion motion = Motion::twist(start, v, 0.0);
  Distance_request reference;
  reference.absolute_tolerance = 1e-12;
  reference.relative_tolerance = 1e-12;
  Budget_run run;
  const double dt = 0.01;
  for (int i = 0; i <= steps; ++i) {
    const double t = i * dt;
    const Rigid_pose_3 X_WB = motion.pose_at(t);
    const Pair_report& r = tracker.step(t, Rigid_pose_3(), Twist_3{}, X_WB, motion.twist_at(t), dt);
    const bool apart = r.status == Pair_status::Tracking || r.status == Pair_status::Boundary ||
                       r.status == Pair_status::Fallback || r.status == Pair_status::Uncertified;
    if (!apart) {
      EXPECT_FALSE(r.lower_bound) << "t = " << t << ": a bound on a " << to_string(r.status) << " row";
      continue;
    }
    ++run.apart_rows;
    run.uncertified_rows += r.status == Pair_status::Uncertified;
    EXPECT_TRUE(r.lower_bound) << "t = " << t << ": an apart row without a bound";
    if (!r.lower_bound) continue;
    EXPECT_LE(*r.lower_bound, r.distance) << "t = " << t;
    if (r.status != Pair_status::Uncertified) {
      EXPECT_GE(*r.lower_bound, r.distance - budget.at(r.distance) * (1.0 + 1e-12)) << "t = " << t;
    }
    const Distance_result ref = extremal_distance(a, Rigid_pose_3(), b, X_WB, reference);
    if (!ref.is_certified() || ref.status == Distance_status::Intersecting) continue;
    ++run.checked_rows;
    const double rounding = 1e-12 * (1.0 + ref.upper_bound);
    // The bound holds: at most the true distance (itself at most the solver's upper bound).
    EXPECT_LE(*r.lower_bound, ref.upper_bound + rounding)
        << "t = " << t << ": bound " << *r.lower_bound << ", true " << ref.upper_bound;
    // The row is a distance between points of the bodies, and within the budget of the truth.
    EXPECT_GE(r.distance, ref.lower_bound - rounding) << "t = " << t;
    if (r.status != Pair_status::Uncertified)
      run.worst_excess = std::max(run.worst_excess,
                                  (r.distance - ref.upper_bound - rounding) / budget.at(r.distance));
  }
  return run;
}

void add(Budget_run& total, const Budget_run& run) {
  total.apart_rows += run.apart_rows;
  total.checked_rows += run.checked_rows;
  total.uncertified_rows += run.uncertified_rows;
  total.worst_excess = std::max(total.worst_excess, run.worst_excess);
}

void expect_certified(const Budget_run& run, const char* scene) {
  std::cout << scene << ": " << run.checked_rows << " apart rows checked, worst excess "
            << run.worst_excess << " budgets\n";
  EXPECT_GT(run.checked_rows, 20) << scene;
  EXPECT_LE(run.worst_excess, 1.0) << scene << ": a row more than its budget above the truth";
  EXPECT_EQ(run.uncertified_rows, 0) << scene;
}

class Certificate : public ::testing::TestWithParam<double> {};

TEST_P(Certificate, EveryApartRowsLowerBoundHoldsAgainstTheOneShotSolver) {
  const Error_budget budget{GetParam(), GetParam()};
  std::mt19937_64 rng = test::seeded_rng(20261204);
  const Body torus = make_torus_body(3.0, 1.0);
  const Body ellipsoid = make_ellipsoid_body(1.5, 1.0, 0.6);
  const Body twins = twin_spheres();
  const Body sheet = bumpy_sheet();
  const Body ball = make_sphere_body(0.5);
  const Body point = make_point_body();
  Budget_run runs[4];
  for (int k = 0; k < 3; ++k) {
    add(runs[0], run_scene(torus, ellipsoid, rng, 5.0, budget, 40));
    add(runs[1], run_scene(twins, ball, rng, 4.0, budget, 40));
    add(runs[2], run_scene(sheet, ellipsoid, rng, 4.0, budget, 40));
    add(runs[3], run_scene(torus, point, rng, 4.0, budget, 40));
  }
  expect_certified(runs[0], "torus, ellipsoid");
  expect_certified(runs[1], "twin spheres, ball");
  expect_certified(runs[2], "bumpy sheet, ellipsoid");
  expect_certified(runs[3], "torus, point");
}

TEST_P(Certificate, RowsOfARealPartHoldTheirBound) {
  const Error_budget budget{GetParam(), GetParam()};
  std::mt19937_64 rng = test::seeded_rng(41);
  const io::Model m = io::read_model(std::string(EXTREMAL_SHARED_DATA) + "/step/linkrods.step");
  const Body& part = m.bodies.at(0);
  const Body ball = make_sphere_body(0.4);
  Budget_run run;
  for (int k = 0; k < 2; ++k) add(run, run_scene(part, ball, rng, 3.0, budget, 30));
  expect_certified(run, "linkrods, ball");
}

INSTANTIATE_TEST_SUITE_P(Budgets, Certificate, ::testing::Values(1e-3, 1e-9),
                         [](const ::testing::TestParamInfo<double>& info) {
                           return info.param > 1e-6 ? std::string("Loose") : std::string("Default");
                         });

// The rows of a pair beyond the threshold carry the boxes' distance as their bound.
TEST(Certificate, AFartherPairsBoundIsItsBoxesDistance) {
  Body_pair_options options;
  options.threshold = 1.0;
  Body_pair_tracker tracker(make_sphere_body(1.0), make_sphere_body(1.0), options);
  const Rigid_pose_3 far(Mat3::Identity(), Vec3(10.0, 0.0, 0.0));
  const Pair_report& r = tracker.step(0.0, Rigid_pose_3(), Twist_3{}, far, Twist_3{}, 0.01);
  ASSERT_EQ(r.status, Pair_status::Farther);
  ASSERT_TRUE(r.lower_bound);
  EXPECT_EQ(*r.lower_bound, r.distance);
  EXPECT_NEAR(r.distance, 8.0, 1e-9);  // the unit balls' boxes, 10 apart
}

}  // namespace
}  // namespace extremal
