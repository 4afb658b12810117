// Time per tracker step (evaluation of both features with second derivatives, the 4x4 solve,
// the Euler update) for surface-surface pairs under motion, K dt = 1.
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "algorithms/pair/Extremal_tracker.h"
#include "experiments/Ellipsoid_experiment.h"
#include "kernel/Shapes.h"

namespace {

using namespace extremal;

struct Motion_table {
  std::vector<Rigid_pose_3> a, b;
};

Motion_table poses(const Rigid_pose_3& A0, const Twist_3& VA, const Rigid_pose_3& B0,
                   const Twist_3& VB, double dt, int n) {
  Motion_table m;
  for (int i = 0; i < n; ++i) {
    m.a.push_back(advance(A0, VA, i * dt));
    m.b.push_back(advance(B0, VB, i * dt));
  }
  return m;
}

void run(benchmark::State& state, const Nurbs_surface_3& sa, const Nurbs_surface_3& sb,
         const Rigid_pose_3& A0, const Twist_3& VA, const Rigid_pose_3& B0, const Twist_3& VB,
         const Vec4& start) {
  const double dt = 1e-3;
  const int n = 4096;  // poses precomputed: the benchmark times the tracker, not the motion
  const Motion_table m = poses(A0, VA, B0, VB, dt, n);
  Extremal_tracker tracker(Feature::surface(sa), Feature::surface(sb), start);
  for (int i = 0; i < 200; ++i) (void)tracker.step(i * dt, m.a[i], VA, m.b[i], VB, dt);
  int i = 200;
  double worst = 0.0;
  for (auto _ : state) {
    const Track_result& r = tracker.step(i * dt, m.a[i], VA, m.b[i], VB, dt);
    benchmark::DoNotOptimize(r.distance);
    // The table restarts at t = 0 after n steps: skip the re-convergence after the jump.
    if (i >= 20) worst = std::max(worst, r.normalised_errors.cwiseAbs().maxCoeff());
    if (++i == n) i = 0;
  }
  state.counters["max_norm_error"] = worst;
}

void BM_StepEllipsoids(benchmark::State& state) {
  const auto s = experiments::default_ellipsoid_setup();
  const Nurbs_surface_3 a = make_ellipsoid(3, 2, 1.5), b = make_ellipsoid(2, 1.2, 1);
  run(state, a, b, s.pose_a, s.twist_a, s.pose_b, s.twist_b, s.start);
}
BENCHMARK(BM_StepEllipsoids);

Nurbs_surface_3 bicubic(double bulge) {
  std::vector<Point_3> grid;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      grid.emplace_back(i - 1.5, j - 1.5, bulge * ((i == 1 || i == 2) && (j == 1 || j == 2) ? 1.0 : 0.0));
  return make_freeform(3, 3, 4, 4, grid);
}

void BM_StepBicubicPatches(benchmark::State& state) {
  const Nurbs_surface_3 a = bicubic(0.8), b = bicubic(-0.8);
  // B above A, facing it, both moving slowly.
  const Rigid_pose_3 A0;
  const Rigid_pose_3 B0 = Rigid_pose_3::from_quaternion(Vec3(0.1, -0.05, 2.0), 1, 0.02, 0.01, 0);
  Twist_3 VA, VB;
  VA.angular = Vec3(0.0, 0.0, 0.2);
  VB.linear = Vec3(0.05, 0.03, 0.0);
  VB.angular = Vec3(0.03, -0.02, 0.1);
  run(state, a, b, A0, VA, B0, VB, Vec4(0.5, 0.5, 0.5, 0.5));
}
BENCHMARK(BM_StepBicubicPatches);

}  // namespace

BENCHMARK_MAIN();
