// The tracker: convergence from poor starts, agreement with Newton at rest, the seed's
// ellipsoid experiment (shortened) against the certified reference, singular Jacobians, and no
// heap allocation per step.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>

#include "algorithms/distance/Ellipsoid_distance.h"
#include "algorithms/pair/Extremal_tracker.h"
#include "experiments/Ellipsoid_experiment.h"
#include "kernel/Error.h"
#include "kernel/Shapes.h"

#include "support/Allocation_counter.h"

namespace extremal {
namespace {

using experiments::default_ellipsoid_setup;
using experiments::run_ellipsoid_experiment;

TEST(ExtremalTracker, DecayRateFollowsTheGain) {
  const auto setup = default_ellipsoid_setup();
  for (double K : {5.0, 10.0, 20.0}) {
    const auto run = run_ellipsoid_experiment(setup, Tracker_options::with_gain(K), 1e-3, 3.0);
    const double rate = run.decay_rate();
    EXPECT_NEAR(rate / K, 1.0, 0.10) << "K = " << K << " measured rate " << rate;
  }
}

TEST(ExtremalTracker, EllipsoidsAt100HzWithinOneE8OfSize) {
  const auto setup = default_ellipsoid_setup();
  const double dt = 1e-2;
  const auto run = run_ellipsoid_experiment(setup, Tracker_options::with_gain(1.0 / dt), dt, 4.0);
  const double size = setup.axes_a.maxCoeff();
  EXPECT_LE(run.max_error_after(0.5), 1e-8 * size);
  for (const auto& s : run.samples) {
    EXPECT_LE(s.reference_gap, 1e-13);  // the certificate itself is tight
    EXPECT_TRUE(std::isfinite(s.distance));
  }
}

TEST(ExtremalTracker, EllipsoidsAt1kHzWithinOneE11OfSize) {
  const auto setup = default_ellipsoid_setup();
  const double dt = 1e-3;
  const auto run = run_ellipsoid_experiment(setup, Tracker_options::with_gain(1.0 / dt), dt, 2.0);
  EXPECT_LE(run.max_error_after(0.5), 1e-11 * setup.axes_a.maxCoeff());
}

TEST(ExtremalTracker, SubstepsAndRk4ConvergeToo) {
  const auto setup = default_ellipsoid_setup();
  Tracker_options rk4 = Tracker_options::with_gain(20.0);
  rk4.integrator = Integrator::Rk4;
  const auto run_rk4 = run_ellipsoid_experiment(setup, rk4, 1e-2, 3.0);
  Tracker_options sub = Tracker_options::with_gain(20.0);
  sub.substeps = 4;
  const auto run_sub = run_ellipsoid_experiment(setup, sub, 1e-2, 3.0);
  // At K = 20 the transient is over after ~1.5 s; RK4 follows the motion far more closely.
  EXPECT_LE(run_rk4.max_error_after(2.0), 1e-9);
  EXPECT_LE(run_sub.max_error_after(2.0), 1e-5);
  EXPECT_LT(run_rk4.max_error_after(2.0), run_sub.max_error_after(2.0));
}

TEST(ExtremalTracker, AtRestEqualsNewtonSolveFromPoorStarts) {
  const Nurbs_surface_3 a = make_ellipsoid(3, 2, 1.5), b = make_ellipsoid(2, 1.2, 1);
  const Feature A = Feature::surface(a), B = Feature::surface(b);
  const Rigid_pose_3 XA = Rigid_pose_3::from_quaternion(Vec3::Zero(), 1, 0.2, 0.1, 0);
  const Rigid_pose_3 XB = Rigid_pose_3::from_quaternion(Vec3(6, 2, 1), 1, 0, 0.3, 0.1);
  const auto ref = ellipsoid_distance({XA, Vec3(3, 2, 1.5)}, {XB, Vec3(2, 1.2, 1)});
  for (const Vec4& start : {Vec4(1.0, 0.6, 2.0, -0.5), Vec4(5.5, -0.9, 4.0, 0.9),
                            Vec4(0.2, 0.0, 3.4, 0.1)}) {
    Extremal_tracker tracker(A, B, start, Tracker_options::with_gain(50.0));
    const Twist_3 still;
    Track_result r;
    for (int i = 0; i < 2000; ++i) r = tracker.step(i * 1e-2, XA, still, XB, still, 1e-2);
    EXPECT_NEAR(r.distance, ref.upper_bound, 1e-12) << "start " << start.transpose();
    const Newton_result newton =
        solve_pair_at_rest({&A, &XA, nullptr}, {&B, &XB, nullptr}, tracker.params());
    EXPECT_LE((newton.params - tracker.params()).norm(), 1e-12);
    // Normal from A to B and witness points consistent.
    EXPECT_NEAR((r.point_b - r.point_a - r.distance * r.normal).norm(), 0.0, 1e-14);
  }
}

// At distance zero the result's normal is no longer (b - a) / |b - a| but the reference
// surface's unit outward normal (A's, else minus B's): the system keeps that normal unnormalised
// (Pair_system::outward_a), so a missed normalisation shows here as a normal of length 16.
TEST(ExtremalTracker, AtZeroDistanceTheNormalIsTheUnitOutwardNormal) {
  Nurbs_surface_3 plane = make_plane(4, 4);  // outward +z, |t_u x t_v| = 16
  Nurbs_surface_3 inward = make_plane(4, 4);
  inward.set_outward_sign(-1);
  const Rigid_pose_3 X;
  const Vec4 centre(0.5, 0.5, 0.5, 0.5);
  for (const Nurbs_surface_3* a : {&plane, &inward}) {
    const Feature A = Feature::surface(*a), B = Feature::surface(plane);
    Extremal_tracker tracker(A, B, centre, Tracker_options::with_gain(1.0));
    const Track_result& r = tracker.evaluate(0.0, X, X);
    EXPECT_EQ(r.distance, 0.0);
    EXPECT_EQ(r.normal, Vec3(0, 0, a->outward_sign()));
  }
  const Feature P = Feature::point(Vec3::Zero()), B = Feature::surface(plane);
  Extremal_tracker tracker(P, B, Vec4(0.5, 0.5, 0, 0), Tracker_options::with_gain(1.0));
  const Track_result& r = tracker.evaluate(0.0, X, X);
  EXPECT_EQ(r.distance, 0.0);
  EXPECT_EQ(r.normal, Vec3(0, 0, -1));
}

TEST(ExtremalTracker, EveryPairKindTracksAMovingPair) {
  // Curve (a rational circle), surface (a torus), point: each pair tracked under motion stays
  // stationary (normalised errors small) and agrees with Newton at rest at sampled times.
  const Nurbs_curve_3 circle = make_circle(1.5);
  const Nurbs_surface_3 torus = make_torus(3.0, 1.0);
  const Nurbs_surface_3 sphere = make_sphere(1.0);
  const Feature point = Feature::point(Vec3::Zero());
  const Feature curve = Feature::curve(circle);
  const Feature surf = Feature::surface(torus);
  const Feature surf2 = Feature::surface(sphere);
  struct Case {
    const char* name;
    Feature a, b;
    Vec4 start;
  };
  const Case cases[] = {{"point-curve", point, curve, Vec4(0.4, 0, 0, 0)},
                        {"point-surface", point, surf, Vec4(0.3, 0.2, 0, 0)},
                        {"curve-curve", curve, curve, Vec4(0.2, 3.0, 0, 0)},
                        {"curve-surface", curve, surf, Vec4(0.1, 0.4, 0.3, 0)},
                        {"surface-surface", surf2, surf, Vec4(3.0, 0.1, 0.2, 0.1)}};
  for (const Case& c : cases) {
    const Rigid_pose_3 XA0 = Rigid_pose_3::from_quaternion(Vec3(7, 0.5, 1), 1, 0.1, 0.2, 0.0);
    const Rigid_pose_3 XB0;
    Twist_3 VA, VB;
    VA.linear = Vec3(-0.3, 0.1, 0.05);
    VA.angular = Vec3(0.1, 0.2, -0.1);
    VB.angular = Vec3(0.0, 0.0, 0.2);
    Extremal_tracker tracker(c.a, c.b, c.start, Tracker_options::with_gain(0.0));
    const double dt = 1e-3;
    for (int i = 0; i <= 3000; ++i) {
      const double t = i * dt;
      const Rigid_pose_3 XA = advance(XA0, VA, t), XB = advance(XB0, VB, t);
      const Track_result r = tracker.step(t, XA, VA, XB, VB, dt);
      ASSERT_TRUE(std::isfinite(r.distance)) << c.name;
      ASSERT_EQ(r.status, Track_status::Tracking) << c.name << " at t = " << t;
      if (i >= 500 && i % 500 == 0) {
        EXPECT_LE(r.normalised_errors.cwiseAbs().maxCoeff(), 1e-6) << c.name << " t = " << t;
        const Newton_result n =
            solve_pair_at_rest({&c.a, &XA, nullptr}, {&c.b, &XB, nullptr}, r.params);
        Pair_system s;
        build_pair_system({&c.a, &XA, nullptr}, {&c.b, &XB, nullptr}, n.params, s, false);
        EXPECT_NEAR(r.distance, s.d.norm(), 1e-10) << c.name << " t = " << t;
      }
    }
  }
}

TEST(ExtremalTracker, PairHeldAtTheEndOfBsCurveConvergesQuadratically) {
  // A segment (B) leaving a unit sphere (A): the nearest pair is the segment's start, held on
  // its bound, over the sphere's point towards it. With B's parameter held, the corrections
  // solve the sphere's 2 x 2 Newton system: quadratic convergence. (The held row's identity
  // padding was negated with B's rows, which shifted the Hessian to about twice itself: half
  // steps, linear convergence, every correction spent.)
  const Nurbs_surface_3 sphere = make_sphere(1.0);
  const Vec3 start(0.3, 0.2, 2.0), end(2.0, 1.0, 4.0);
  const Nurbs_curve_3 segment(1, {Point_3(start.x(), start.y(), start.z()),
                                  Point_3(end.x(), end.y(), end.z())}, {0, 0, 1, 1});
  const Feature a = Feature::surface(sphere), b = Feature::curve(segment);
  Tracker_options options = Tracker_options::with_gain(0.0);
  options.corrections = 10;
  // Sphere parameters about 0.05 off the solution's, the segment 0.2 along.
  const double u = std::atan2(start.y(), start.x()), v = std::asin(start.z() / start.norm());
  Extremal_tracker tracker(a, b, Vec4(u + 0.05, v - 0.05, 0.2, 0.0), options);
  const Rigid_pose_3 X;
  const Track_result r = tracker.step(0.0, X, Twist_3{}, X, Twist_3{}, 1e-3);
  EXPECT_NEAR(r.distance, start.norm() - 1.0, 1e-13);
  EXPECT_EQ(r.params[2], 0.0);
  EXPECT_LE(r.iterations, 8) << "linear solves spent (all 11 before)";
}

TEST(ExtremalTracker, SingularJacobianFallsBackWithoutMovingAndSaysSo) {
  // A point at the centre of a sphere: every point is extremal, M vanishes.
  const Nurbs_surface_3 sphere = make_sphere(1.0);
  const Feature A = Feature::surface(sphere), B = Feature::point(Vec3::Zero());
  const Vec4 start(1.0, 0.3, 0, 0);
  Extremal_tracker tracker(A, B, start, Tracker_options::with_gain(100.0));
  const Rigid_pose_3 X;
  const Twist_3 still;
  const Track_result& r = tracker.step(0.0, X, still, X, still, 1e-2);
  EXPECT_EQ(r.status, Track_status::Singular_fallback);
  EXPECT_EQ(r.degeneracy, Degeneracy::Singular);
  // Damped least squares: no step along the null space (here every direction).
  EXPECT_LE((tracker.params() - start).norm(), 1e-12);
  EXPECT_NEAR(r.distance, -1.0, 1e-14);  // the point is inside the sphere
  EXPECT_TRUE(r.normal.allFinite());
  EXPECT_TRUE(r.normalised_errors.allFinite());
}

TEST(ExtremalTracker, RejectsBadOptions) {
  const Nurbs_surface_3 sphere = make_sphere(1.0);
  const Feature A = Feature::surface(sphere), B = Feature::point(Vec3::Zero());
  Tracker_options bad = Tracker_options::with_gain(-1.0);
  EXPECT_THROW(Extremal_tracker t(A, B, Vec4::Zero(), bad), Precondition_violation);
  Tracker_options zero_sub;
  zero_sub.substeps = 0;
  EXPECT_THROW(Extremal_tracker t(A, B, Vec4::Zero(), zero_sub), Precondition_violation);
  Extremal_tracker ok(A, B, Vec4(1, 0, 0, 0));
  const Rigid_pose_3 X(Mat3::Identity(), Vec3(3, 0, 0));
  EXPECT_THROW((void)ok.step(0.0, X, Twist_3{}, Rigid_pose_3{}, Twist_3{}, 0.0),
               Precondition_violation);
}

TEST(ExtremalTracker, StepAllocatesNothing) {
  const auto setup = default_ellipsoid_setup();
  const Nurbs_surface_3 a = make_ellipsoid(3, 2, 1.5), b = make_ellipsoid(2, 1.2, 1);
  for (Integrator integ : {Integrator::Euler, Integrator::Rk4}) {
    Tracker_options o = Tracker_options::with_gain(100.0);
    o.integrator = integ;
    o.substeps = 2;
    Extremal_tracker tracker(Feature::surface(a), Feature::surface(b), setup.start, o);
    const long before = test::g_allocations.load();
    double sum = 0.0;
    for (int i = 0; i < 100; ++i) {
      const Rigid_pose_3 XA = advance(setup.pose_a, setup.twist_a, i * 1e-2);
      const Rigid_pose_3 XB = advance(setup.pose_b, setup.twist_b, i * 1e-2);
      sum += tracker.step(i * 1e-2, XA, setup.twist_a, XB, setup.twist_b, 1e-2).distance;
    }
    EXPECT_EQ(test::g_allocations.load() - before, 0);
    EXPECT_GT(sum, 0.0);
  }
}

}  // namespace
}  // namespace extremal
