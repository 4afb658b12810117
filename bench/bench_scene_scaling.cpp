// Scaling of a body-pair step with the number of faces: a wavy (non-convex) sheet of k x k
// bicubic Bezier patches (10, 100, 1,000 and 10,000 faces, each patch 1 x 1, neighbours sharing
// their boundary control points) against an ellipsoid gliding and turning over it at 1 kHz.
// The moving body always covers about the same number of patches, so the time per step should
// follow the near face pairs (counter `candidates`), not the face count. Each run checks the
// tracked minimum against the certified global solver at its last step (counter `rel_error`).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "algorithms/body_pair/Body_pair_tracker.h"
#include "algorithms/distance/Global_distance.h"
#include "kernel/Shapes.h"

using namespace extremal;

namespace {

constexpr double k_pi = 3.14159265358979323846;

double height(double x, double y) { return 0.35 * std::sin(1.7 * x) * std::cos(1.3 * y); }

// k x k patches over [0, k]^2: poles on a (3k + 1)^2 grid, patch (i, j) takes its 4 x 4 block.
Body wavy_sheet(int k) {
  Body b;
  b.name = "sheet";
  const int n = 3 * k + 1;
  std::vector<Point_3> grid;
  grid.reserve(static_cast<std::size_t>(n) * n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) grid.emplace_back(i / 3.0, j / 3.0, height(i / 3.0, j / 3.0));
  b.faces.reserve(static_cast<std::size_t>(k) * k);
  for (int pi = 0; pi < k; ++pi)
    for (int pj = 0; pj < k; ++pj) {
      std::vector<Point_3> poles;
      for (int a = 0; a < 4; ++a)
        for (int c = 0; c < 4; ++c) poles.push_back(grid[(3 * pi + a) * n + 3 * pj + c]);
      b.faces.emplace_back(Nurbs_surface_3(3, 3, 4, 4, poles, {0, 0, 0, 0, 1, 1, 1, 1},
                                           {0, 0, 0, 0, 1, 1, 1, 1}),
                           "bezier");
    }
  return b;
}

struct Glide {
  double cx, cy;
  Rigid_pose_3 pose(double t) const {
    const double w = 2.0 * k_pi / 4.0;  // a lap in 4 s
    const Vec3 p(cx + 1.5 * std::cos(w * t), cy + 1.5 * std::sin(w * t), 0.95);
    return Rigid_pose_3(Eigen::AngleAxisd(0.5 * t, Vec3(0.2, 0.1, 1.0).normalized()).toRotationMatrix(), p);
  }
  Twist_3 twist(double t) const {
    const double w = 2.0 * k_pi / 4.0;
    Twist_3 v;
    v.linear = Vec3(-1.5 * w * std::sin(w * t), 1.5 * w * std::cos(w * t), 0.0);
    v.angular = 0.5 * Vec3(0.2, 0.1, 1.0).normalized();
    return v;
  }
};

void BM_SheetAgainstGlidingEllipsoid(benchmark::State& state) {
  const int k = static_cast<int>(state.range(0));
  const Body sheet = wavy_sheet(k);
  const Body ellipsoid = make_ellipsoid_body(0.7, 0.5, 0.4);
  Body_pair_tracker tracker(sheet, ellipsoid);
  const Glide glide{0.5 * k, 0.5 * k};
  const double dt = 1e-3;
  long i = 0;
  // Warm-up: the certified start and the first lap's seeds.
  for (; i < 4000; ++i) {
    const double t = i * dt;
    benchmark::DoNotOptimize(tracker.step(t, Rigid_pose_3(), Twist_3{}, glide.pose(t), glide.twist(t), dt));
  }
  (void)tracker.step(i * dt, Rigid_pose_3(), Twist_3{}, glide.pose(i * dt), glide.twist(i * dt), dt);
  const Pair_statistics& stats = tracker.statistics();
  const long transitions0 = stats.transitions, checks0 = stats.vacated_checks,
             solves0 = stats.vacated_solves;
  ++i;
  long steps = 0;
  double candidates = 0.0, trackers = 0.0;
  for (auto _ : state) {
    const double t = i * dt;
    benchmark::DoNotOptimize(
        tracker.step(t, Rigid_pose_3(), Twist_3{}, glide.pose(t), glide.twist(t), dt));
    candidates += stats.candidates;
    trackers += stats.trackers;
    ++steps;
    ++i;
  }
  const double t = i * dt;
  const Pair_report& r = tracker.step(t, Rigid_pose_3(), Twist_3{}, glide.pose(t), glide.twist(t), dt);
  Distance_request req;
  req.absolute_tolerance = 1e-13;
  req.relative_tolerance = 1e-11;
  const Distance_result g = extremal_distance(tracker.model_a().hierarchy(), Rigid_pose_3(),
                                              tracker.model_b().hierarchy(), glide.pose(t), req);
  state.counters["faces"] = static_cast<double>(sheet.faces.size());
  state.counters["candidates"] = candidates / std::max(steps, 1L);
  state.counters["trackers"] = trackers / std::max(steps, 1L);
  state.counters["transitions"] = static_cast<double>(stats.transitions - transitions0);
  // Per timed step: candidate pairs without a tracker checked, and restricted solves run.
  state.counters["checks"] = static_cast<double>(stats.vacated_checks - checks0) / std::max(steps, 1L);
  state.counters["solves"] = static_cast<double>(stats.vacated_solves - solves0) / std::max(steps, 1L);
  state.counters["rel_error"] = std::abs(r.distance - g.distance) / g.distance;
  state.counters["steps_per_s"] = benchmark::Counter(static_cast<double>(steps), benchmark::Counter::kIsRate);
}

// Peer in the same run: the certified global solver from scratch at the same poses (what a
// step would cost without tracking), 1e-9 relative tolerance.
void BM_SheetGlobalQueryPeer(benchmark::State& state) {
  const int k = static_cast<int>(state.range(0));
  const Body sheet = wavy_sheet(k);
  const Body ellipsoid = make_ellipsoid_body(0.7, 0.5, 0.4);
  const Distance_hierarchy ha(sheet), hb(ellipsoid);
  Distance_workspace ws;
  Distance_request req;
  const Glide glide{0.5 * k, 0.5 * k};
  long i = 4000;
  for (auto _ : state) {
    const double t = i * 1e-3;
    benchmark::DoNotOptimize(extremal_distance(ha, Rigid_pose_3(), hb, glide.pose(t), req, ws));
    ++i;
  }
  state.counters["faces"] = static_cast<double>(sheet.faces.size());
}

}  // namespace

BENCHMARK(BM_SheetGlobalQueryPeer)->Arg(3)->Arg(10)->Arg(32)->Arg(100)->Unit(benchmark::kMicrosecond);
// k = 3, 10, 32, 100: 9, 100, 1,024 and 10,000 faces.
BENCHMARK(BM_SheetAgainstGlidingEllipsoid)->Arg(3)->Arg(10)->Arg(32)->Arg(100)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
