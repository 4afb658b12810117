// The candidate stage of a body-pair tracker: which primitive pairs may hold the minimum (the
// broad phase), and the certificate that those without a tracker hold nothing closer than the
// tracked minimum, seeding a tracker where one does. Kept_proof_stage is the one in use; a
// certified front carried across steps replaces it behind this interface. Not API.
#pragma once

#include "algorithms/body_pair/Pair_report.h"
#include "kernel/Rigid_pose_3.h"

namespace extremal::internal {

// What certify_apart found: whether a certified pair's surfaces meet (the bodies are not
// apart), and the certified lower bound on the bodies' distance it made at this step.
struct Apart_certificate {
  bool meet = false;
  double lower = -HUGE_VAL;
};

class Candidate_stage {
 public:
  virtual ~Candidate_stage() = default;
  // Forgets every candidate (the tracker starts again).
  virtual void clear() = 0;
  // The candidates made anew: every primitive pair whose boxes lie within `reach` at these
  // poses.
  virtual void refresh(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB, double reach) = 0;
  // Each step with a finite tracked minimum `best`: the candidates made anew where they may
  // miss a pair within |best| plus the broad margin (inside, the tracked pair's own primitives
  // lie |best| apart).
  virtual void update(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB, double best) = 0;
  // Apart (`best` above the contact tolerance): certifies that no candidate pair without a
  // tracker, nor a tracked pair's other basin, holds a pair closer than `best`, seeding those
  // that do.
  virtual Apart_certificate certify_apart(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB,
                                          double best) = 0;
  // In contact: seeds the candidate pairs without a tracker once (and again once the motion may
  // have closed the gap a seed's solve certified). True if it seeded.
  virtual bool seed_in_contact(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) = 0;
  // A tracker another stage placed on pair (pa, pb): the pair becomes a candidate (its bound
  // unknown) if it is not one.
  virtual void track(int pa, int pb, const Rigid_pose_3& relative) = 0;
  // Live candidate pairs.
  virtual int size() const = 0;
  // The candidates of the last broad phase would not fit Body_pair_options::memory_limit: it
  // kept none, certify_apart certifies nothing and seed_in_contact seeds nothing until one
  // fits again (each update tries).
  virtual bool over_limit() const = 0;
  // Its work so far (the broad phases, checks, solves and seeds of Pair_statistics).
  virtual const Pair_statistics& statistics() const = 0;
};

}  // namespace extremal::internal
