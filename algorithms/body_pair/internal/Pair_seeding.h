// Seeding trackers, shared by every stage of a body-pair tracker: on one primitive pair from
// the certified solver restricted to it, on a global solver's pair, on a penetration pair. A
// tracker placed on a pair that has one already moves it there (another basin). Not API.
#pragma once

#include "algorithms/body_pair/internal/Candidate_stage.h"
#include "algorithms/body_pair/internal/Live_set.h"
#include "algorithms/body_pair/internal/Pair_solver.h"

namespace extremal::internal {

class Pair_seeding {
 public:
  Pair_seeding(Pair_context& context, Pair_solver& solver, Live_set& live)
      : m_context(context), m_solver(solver), m_live(live) {}
  void attach(Candidate_stage& candidates) { m_candidates = &candidates; }
  // Trackers it seeded (Pair_statistics::seeds).
  long seeds() const { return m_seeds; }

  // Seeds pair (pa, pb) from the global solver restricted to it (or its closed form, or
  // sampled where the solver has no element for it: mesh edges). Returns that solve's
  // certified lower bound on the pair's distance (-infinity without one).
  double seed_pair(int pa, int pb, const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB);
  // Seeds a tracker on the pair of global result g when it beats `tracked` by more than its
  // tolerance. True if it seeded.
  bool seed_from(const Distance_result& g, const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB,
                 double tracked);
  // A tracker on pair (pa, pb) from `params`: the pair's live one moved there, or a new one
  // (the pair made a candidate). Returns its slot.
  int place(int pa, int pb, const Vec4& params, const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB);
  // A tracker on a penetration pair found by a solver, through contact (counted as a seed).
  void add_inside(int pa, int pb, const Vec4& params, const Rigid_pose_3& X_WA,
                  const Rigid_pose_3& X_WB);
  // Replaces a seed on a patch side by an interior pair at the same distance, if there is one.
  void prefer_central(int pa, int pb, const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB,
                      Vec4& params) const;

 private:
  Pair_context& m_context;
  Pair_solver& m_solver;
  Live_set& m_live;
  Candidate_stage* m_candidates = nullptr;
  long m_seeds = 0;
};

}  // namespace extremal::internal
