// Tracks the extremal pair between two bodies made of many primitives (faces, B-rep edges,
// curves, a point, mesh triangles), through contact and penetration (docs/design.md,
// "Architecture"). A step goes through one pose gate (a pair whose relative pose is bit for
// bit the one its answer was made at keeps that answer; a pair whose boxes lie beyond the
// threshold reads `farther`), then one engine answers it:
//   - the NURBS stages (internal/Stage_engine.h): trackers on primitive pairs, the depth
//     monitor, the candidate stage that certifies that no other pair is closer, the certified
//     global solver where no tracker holds;
//   - two bodies each a mesh or a point: a certified front between their hierarchies carried
//     across steps (internal/Mesh_pair_stage.h);
//   - a ball against a closed body, a point or a ball: its centre's stages, the answer moved
//     out by the radius (internal/Ball_pair.h);
// and one mapping makes the report row and its status from the engine's answer.
#pragma once

#include <memory>
#include <vector>

#include "algorithms/body_pair/Body_pair_options.h"
#include "algorithms/body_pair/Pair_report.h"
#include "algorithms/body_pair/Tracking_model.h"
#include "kernel/Body.h"
#include "kernel/Rigid_pose_3.h"

namespace extremal {

class Body_pair_tracker {
 public:
  // The bodies must outlive the tracker.
  Body_pair_tracker(const Body& a, const Body& b, const Body_pair_options& options = {});
  // With prepared models (shared between the pairs of a scene); they must outlive the tracker.
  Body_pair_tracker(std::shared_ptr<const Tracking_model> a, std::shared_ptr<const Tracking_model> b,
                    const Body_pair_options& options = {});
  ~Body_pair_tracker();
  Body_pair_tracker(Body_pair_tracker&&) noexcept;
  Body_pair_tracker& operator=(Body_pair_tracker&&) noexcept;

  // Converged solve at rest at poses X_WA, X_WB: a tracker on the certified global pair, and
  // the candidate pairs (in contact, the first step seeds them). Called by the first step if
  // not before.
  void start(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB);

  // The pair at time t at these poses and twists; the trackers then advance over [t, t + dt].
  const Pair_report& step(double t, const Rigid_pose_3& X_WA, const Twist_3& V_A,
                          const Rigid_pose_3& X_WB, const Twist_3& V_B, double dt);

  // The work done since the start (not part of the reading).
  const Pair_statistics& statistics() const;
  // The wall time the last step spent in audits (Body_pair_options::audit_every), in
  // microseconds: timed apart so that a scene's step times are the tracking's own.
  double audit_time_us() const;

  const std::vector<Feature>& features_a() const;
  const std::vector<Feature>& features_b() const;
  const Tracking_model& model_a() const;
  const Tracking_model& model_b() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> m;
};

// The features of a body: its faces, then its curves; a point body is its origin.
std::vector<Feature> features_of(const Body& body);

}  // namespace extremal
