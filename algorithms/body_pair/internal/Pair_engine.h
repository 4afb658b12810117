// An engine of a body-pair tracker: what answers a step once the facade's pose gate lets it
// through (Body_pair_tracker.cpp). Three exist: the NURBS stages (Stage_engine.h), the
// certified mesh front (Mesh_pair_stage.h), and a ball tracked as its centre (Ball_pair.h),
// which owns two of the first. Each owns its state and returns what it found. Not API.
#pragma once

#include "algorithms/body_pair/Pair_report.h"
#include "algorithms/body_pair/Tracking_model.h"
#include "algorithms/body_pair/internal/Pair_answer.h"
#include "kernel/Rigid_pose_3.h"

namespace extremal::internal {

// One step's input: the time, the poses and twists of the engine's bodies, the step length,
// and the error budget this step is certified at (the options' own, or a ball's, Ball_pair).
struct Pair_step {
  double t = 0.0, dt = 0.0;
  const Rigid_pose_3& X_WA;
  const Twist_3& V_A;
  const Rigid_pose_3& X_WB;
  const Twist_3& V_B;
  Error_budget budget;
};

// The distance between two models' boxes at these poses (the world boxes of their body-frame
// boxes): a lower bound on the bodies' distance.
double boxes_apart(const Tracking_model& a, const Rigid_pose_3& X_WA, const Tracking_model& b,
                   const Rigid_pose_3& X_WB);

// Adds the counters of `from` to `to` (every field of Pair_statistics but the gauges of the
// last step, trackers and candidates).
void add_counters(Pair_statistics& to, const Pair_statistics& from);

class Pair_engine {
 public:
  virtual ~Pair_engine() = default;
  // A converged solve at rest at these poses (the first step does it if not called).
  virtual void start(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) = 0;
  // The answer at this step; the trackers then advance over [t, t + dt].
  virtual const Pair_answer& step(const Pair_step& step) = 0;
  // A lower bound on the bodies' distance from their boxes alone (the pose gate's `farther`).
  virtual double box_bound(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) const = 0;
  // The pair was beyond the threshold at this step, at relative pose X_AB `relative`, with
  // boxes `box_bound` apart: the next step starts again.
  virtual void farther(double box_bound, const Rigid_pose_3& relative) = 0;
  // Adds its work since construction to `s` (counters), and sets the gauges of its last step
  // (trackers, candidates).
  virtual void add_statistics(Pair_statistics& s) const = 0;
  // The wall time its last step spent in audits, in microseconds.
  virtual double audit_time_us() const { return 0.0; }
};

}  // namespace extremal::internal
