// Tracks the extremal pair between two bodies made of many primitives (faces, B-rep edges,
// curves, a point, mesh triangles), through contact and penetration (docs/design.md,
// "The body-pair tracker"). A step runs named stages, each with the state it owns:
//   - the live set: an Extremal_tracker (or a closed form, between mesh triangles) on each
//     tracked primitive pair, stepped, its reading judged by the reading rules, handed across
//     edges and patch sides when its point leaves its primitive, merged with another that
//     reached the same pair;
//   - the depth monitor: where the bodies overlap, whether the tracked pair is still the depth;
//   - the candidate stage: the primitive pairs that may hold the minimum (a broad phase over
//     body-frame boxes), and the certificate that those without a tracker hold nothing closer
//     (kept proofs of restricted solves), seeding a tracker where one does;
//   - re-seeding by the certified global solver when no tracker holds a pair, and audits.
// After any stage that changed the live set, its new trackers are stepped. The answer is the
// minimum over the readings that hold, with face ids and parameters, or the solver's.
// Two bodies each a mesh or a point run none of these: a certified front between their
// hierarchies (Mesh_front.h) is carried across steps instead (internal/Mesh_pair_stage.h).
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

  const std::vector<Feature>& features_a() const;
  const std::vector<Feature>& features_b() const;
  const Tracking_model& model_a() const;
  const Tracking_model& model_b() const;

 private:
  struct Stages;
  std::unique_ptr<Stages> m;
};

// The features of a body: its faces, then its curves; a point body is its origin.
std::vector<Feature> features_of(const Body& body);

}  // namespace extremal
