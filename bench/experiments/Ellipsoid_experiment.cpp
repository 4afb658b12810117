#include "Ellipsoid_experiment.h"

#include <algorithm>
#include <cmath>

#include "algorithms/distance/Ellipsoid_distance.h"
#include "kernel/Shapes.h"

namespace extremal::experiments {

Ellipsoid_setup default_ellipsoid_setup() {
  Ellipsoid_setup s;
  s.pose_a = Rigid_pose_3::from_quaternion(Vec3(0, 0, 0), 0.9, 0.1, 0.3, 0.2);
  s.pose_b = Rigid_pose_3::from_quaternion(Vec3(7.5, 1.0, 0.5), 0.8, -0.2, 0.1, 0.4);
  s.twist_a.angular = Vec3(0.2, -0.1, 0.3);
  s.twist_b.linear = Vec3(-0.35, 0.1, 0.05);
  s.twist_b.angular = Vec3(-0.1, 0.3, 0.2);
  // (u, v) on A and (r, s) on B: longitude / latitude, well away from the extremal pair.
  s.start = Vec4(0.9, 0.5, 2.3, -0.45);
  return s;
}

double Ellipsoid_run::max_error_after(double t0) const {
  double e = 0.0;
  for (const auto& s : samples)
    if (s.t >= t0) e = std::max(e, std::abs(s.distance - s.reference));
  return e;
}

double Ellipsoid_run::decay_rate(double lo, double hi) const {
  // The errors settle on a floor set by the integration error of the motion over one step
  // (about dt |motion| / K for Euler); fit only well above it.
  std::vector<double> tail;
  for (std::size_t i = samples.size() * 2 / 3; i < samples.size(); ++i)
    tail.push_back(samples[i].normalised_errors.cwiseAbs().maxCoeff());
  double floor_level = 0.0;
  if (!tail.empty()) {
    std::nth_element(tail.begin(), tail.begin() + tail.size() / 2, tail.end());
    floor_level = tail[tail.size() / 2];
  }
  lo = std::max(lo, 100.0 * floor_level);
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (const auto& s : samples) {
    const double e = s.normalised_errors.cwiseAbs().maxCoeff();
    if (e < lo || e > hi) continue;
    const double y = std::log(e);
    sx += s.t;
    sy += y;
    sxx += s.t * s.t;
    sxy += s.t * y;
    ++n;
  }
  if (n < 3) return 0.0;
  const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  return -slope;
}

Ellipsoid_run run_ellipsoid_experiment(const Ellipsoid_setup& setup,
                                       const Tracker_options& options, double dt,
                                       double duration) {
  const Nurbs_surface_3 sa = make_ellipsoid(setup.axes_a.x(), setup.axes_a.y(), setup.axes_a.z());
  const Nurbs_surface_3 sb = make_ellipsoid(setup.axes_b.x(), setup.axes_b.y(), setup.axes_b.z());
  Extremal_tracker tracker(Feature::surface(sa), Feature::surface(sb), setup.start, options);
  Ellipsoid_run run;
  const int steps = static_cast<int>(std::llround(duration / dt));
  run.samples.reserve(steps + 1);
  Vec3 normal = Vec3::Zero();
  for (int i = 0; i <= steps; ++i) {
    const double t = i * dt;
    const Rigid_pose_3 A = advance(setup.pose_a, setup.twist_a, t);
    const Rigid_pose_3 B = advance(setup.pose_b, setup.twist_b, t);
    const Track_result& r = tracker.step(t, A, setup.twist_a, B, setup.twist_b, dt);
    const Ellipsoid_distance_result ref =
        ellipsoid_distance({A, setup.axes_a}, {B, setup.axes_b}, normal);
    normal = ref.normal;
    run.samples.push_back({t, r.distance, ref.upper_bound, ref.upper_bound - ref.lower_bound,
                           r.normalised_errors, r.status});
  }
  return run;
}

}  // namespace extremal::experiments
