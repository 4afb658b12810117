#include "algorithms/body_pair/internal/Pair_answer.h"

#include <algorithm>
#include <cmath>

#include "algorithms/body_pair/internal/Body_pair_support.h"
#include "algorithms/body_pair/internal/Pair_engine.h"

namespace extremal::internal {

Pair_report report_of(const Pair_answer& a, double t, double contact_tolerance,
                      const Error_budget& budget) {
  Pair_report r;
  r.time = t;
  r.distance = a.distance;
  r.point_a = a.point_a;
  r.point_b = a.point_b;
  r.normal = a.normal;
  r.feature_a = a.feature_a;
  r.feature_b = a.feature_b;
  r.edge_a = a.edge_a;
  r.edge_b = a.edge_b;
  r.params = a.params;
  r.degeneracy = a.degeneracy;
  r.solved = a.source == Reading_source::Solved;
  r.rejected_by = r.solved ? a.rejected_by : Reading_rule::None;
  r.memory_limited = a.memory_limited;
  const double tol = contact_tolerance;
  r.status = a.distance < -tol                          ? Pair_status::Penetrating
             : a.distance <= tol                        ? Pair_status::Contact
             : a.shape == Reading_shape::Fallback       ? Pair_status::Fallback
             : a.shape == Reading_shape::Boundary       ? Pair_status::Boundary
                                                        : Pair_status::Tracking;
  // Apart: the bound certified at this step, never above the distance (a real pair's); a bound
  // short of the budget, or none, is no certificate.
  if (a.distance > tol) {
    const double lower = std::min(a.lower_bound.value_or(-HUGE_VAL), a.distance);
    if (lower > -HUGE_VAL) r.lower_bound = lower;
    if (!(lower >= certified_floor(a.distance, budget))) r.status = Pair_status::Uncertified;
  }
  return r;
}

Pair_report farther_report(double t, double box_bound) {
  Pair_report r;
  r.time = t;
  r.status = Pair_status::Farther;
  r.distance = box_bound;
  r.lower_bound = box_bound;  // (the boxes hold the bodies)
  return r;
}

double boxes_apart(const Tracking_model& a, const Rigid_pose_3& X_WA, const Tracking_model& b,
                   const Rigid_pose_3& X_WB) {
  return box_distance(transformed(a.box(), X_WA), transformed(b.box(), X_WB));
}

void add_counters(Pair_statistics& to, const Pair_statistics& from) {
  to.computed_steps += from.computed_steps;
  to.audits += from.audits;
  to.reseeds += from.reseeds;
  to.transitions += from.transitions;
  to.merges += from.merges;
  to.seeds += from.seeds;
  to.broad_phases += from.broad_phases;
  to.vacated_checks += from.vacated_checks;
  to.vacated_solves += from.vacated_solves;
  to.vacated_seeds += from.vacated_seeds;
  to.vacated_queued += from.vacated_queued;
  to.vacated_crease_solves += from.vacated_crease_solves;
  to.vacated_reach_solves += from.vacated_reach_solves;
  to.vacated_nodes += from.vacated_nodes;
  to.vacated_partial_solves += from.vacated_partial_solves;
  to.located += from.located;
  to.vacated_proof_checks += from.vacated_proof_checks;
  to.vacated_bound_checks += from.vacated_bound_checks;
  to.corrections += from.corrections;
  to.capped_corrections += from.capped_corrections;
  to.front_opened += from.front_opened;
  to.front_box_bounds += from.front_box_bounds;
  to.front_triangle_pairs += from.front_triangle_pairs;
  to.front_traversals += from.front_traversals;
  to.memory_limited_steps += from.memory_limited_steps;
  to.memory_bytes = std::max(to.memory_bytes, from.memory_bytes);
}

}  // namespace extremal::internal
