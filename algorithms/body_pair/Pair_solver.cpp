#include "algorithms/body_pair/internal/Pair_solver.h"

#include <algorithm>
#include <cmath>

namespace extremal::internal {

Distance_result Pair_solver::global(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) {
  ++m_solves;
  const Pair_context& c = m_context;
  Distance_request request = c.options.global;
  request.absolute_tolerance = std::min(request.absolute_tolerance, c.now.budget.absolute);
  request.relative_tolerance = std::min(request.relative_tolerance, c.now.budget.relative);
  Distance_result g = extremal_distance(c.model_a->hierarchy(), X_WA, c.model_b->hierarchy(), X_WB,
                                       request, m_workspace);
  const double tol = c.options.contact_tolerance;
  // Undecided (the bound at contact, the witness apart) or without a witness at all: solved
  // again at the one-shot budget (tests
  // ProbeScenes.TwoFacesOfAPartThatCrossReadPenetratingAtEveryStep,
  // ProbeScenes.ASheetFarFromATorusPassingByReadsAFiniteDistanceAtEveryStep).
  const bool undecided = g.lower_bound <= tol && g.distance > tol;
  if (g.status == Distance_status::Budget_exhausted && (undecided || !std::isfinite(g.distance)) &&
      request.max_nodes < c.options.undecided_max_nodes) {
    request.max_nodes = c.options.undecided_max_nodes;
    g = extremal_distance(c.model_a->hierarchy(), X_WA, c.model_b->hierarchy(), X_WB, request,
                          m_workspace);
  }
  return g;
}

}  // namespace extremal::internal
