// The seed's experiment (its Figures 6 and 7): two ellipsoids in rigid motion, the tracker
// started away from the extremal pair, its error measured against the certified support-function
// reference at every step. Shared by the experiment program and the tests.
#pragma once

#include <vector>

#include "algorithms/pair/Extremal_tracker.h"
#include "kernel/Rigid_pose_3.h"

namespace extremal::experiments {

struct Ellipsoid_setup {
  Vec3 axes_a{3.0, 2.0, 1.5};
  Vec3 axes_b{2.0, 1.2, 1.0};
  Rigid_pose_3 pose_a;  // at t = 0
  Rigid_pose_3 pose_b;
  Twist_3 twist_a;
  Twist_3 twist_b;
  Vec4 start;  // tracker's initial parameters, away from the extremal pair
};

// Both bodies rotating, B translating towards A; they stay apart for t in [0, 6].
Ellipsoid_setup default_ellipsoid_setup();

struct Ellipsoid_sample {
  double t;
  double distance;        // tracked
  double reference;       // certified (upper bound)
  double reference_gap;   // upper - lower bound of the certificate
  Vec4 normalised_errors;
  Track_status status;
};

struct Ellipsoid_run {
  std::vector<Ellipsoid_sample> samples;
  double max_error_after(double t0) const;  // max |distance - reference| for t >= t0
  // Exponential decay rate of max_k |normalised error_k| fitted (least squares on the log)
  // over the samples where it lies in [lo, hi] and at least 100 times above the final floor.
  double decay_rate(double lo = 1e-9, double hi = 1e-2) const;
};

Ellipsoid_run run_ellipsoid_experiment(const Ellipsoid_setup& setup,
                                       const Tracker_options& options, double dt,
                                       double duration);

}  // namespace extremal::experiments
