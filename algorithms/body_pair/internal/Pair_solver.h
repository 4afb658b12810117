// The certified solver as the stages of one body pair use it: its workspace (scratch of every
// solve, read by the caller right after its own solve), the global solve on the whole pair at
// this step's budget, and the count of those solves. Not API.
#pragma once

#include "algorithms/body_pair/internal/Pair_context.h"
#include "algorithms/distance/Global_distance.h"

namespace extremal::internal {

class Pair_solver {
 public:
  explicit Pair_solver(const Pair_context& context) : m_context(context) {}

  // The global solver on the whole pair (Body_pair_options::global, at most this step's
  // budget; solved again with undecided_max_nodes where it could neither part the surfaces nor
  // find where they meet), counted.
  Distance_result global(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB);
  Distance_workspace& workspace() { return m_workspace; }
  // Global solves so far (Pair_statistics::audits).
  int solves() const { return m_solves; }
  // Another solve of the whole pair the caller made (a hulls' depth search).
  void count() { ++m_solves; }

 private:
  const Pair_context& m_context;
  Distance_workspace m_workspace;
  int m_solves = 0;
};

}  // namespace extremal::internal
