// Certified distance between two sets of posed bodies (an assembly, a multi-solid file): the
// smallest distance over all body pairs, with one certificate for the sets,
//     lower_bound <= min over pairs (a, b) of d(a, b) <= upper_bound,
// and the pair that holds it.
//
// The body pairs are taken nearest box first. Each query is cut off at the best distance found
// so far (Distance_request::cutoff), and a pair whose boxes lie at least that far apart is not
// queried at all: the distance between its boxes is its lower bound. The time budget is the
// whole set's: each query gets what is left of it, and pairs left unqueried when it runs out
// count with their box bound. So a set of many bodies costs about as much as its nearest pairs.
//
// Ties: of pairs at exactly the same distance the one queried first is reported (the cutoff
// prunes the others); for bodies that meet (box distance 0, a stable order) that is the first
// in the sets' order, A's bodies outermost.
#pragma once

#include <vector>

#include "algorithms/Global_distance.h"
#include "algorithms/Penetration_depth.h"
#include "kernel/Body.h"
#include "kernel/Rigid_pose_3.h"

namespace extremal {

// A body of a set with its prepared hierarchy and world pose. Both must outlive the query; the
// body is read by signed queries only (closedness, convexity).
struct Placed_body {
  const Body* body = nullptr;
  const Distance_hierarchy* hierarchy = nullptr;
  Rigid_pose_3 pose;
};

struct Set_distance_result {
  // The best pair's result, with the sets' certificate: lower_bound is the smallest lower
  // bound over all pairs (queried or not), and status the best pair's when the sets' gap
  // upper - lower is within its tolerance, else that of the pair holding the smallest lower
  // bound (Budget_exhausted for a pair the time budget left unqueried). Work counters are
  // summed over the queries. No witness at all (no pair could be queried): element_a = -1 and
  // distance = upper_bound = infinity, status Budget_exhausted.
  Distance_result result;
  int body_a = -1, body_b = -1;  // indices in the sets of the pair that holds the witness
  int pairs_queried = 0;         // body pairs given to the certified solver
  int pairs_skipped = 0;         // pairs bounded by their boxes alone
};

// The certified distance between sets A and B. `request`'s tolerances and node budget apply
// to each query, its cutoff to the sets (nothing farther is sought); `max_seconds` (0: no
// limit) is the wall time of the whole set. Throws Precondition_violation on an empty set or
// a body without a hierarchy.
[[nodiscard]] Set_distance_result set_distance(const std::vector<Placed_body>& A,
                                               const std::vector<Placed_body>& B,
                                               const Distance_request& request,
                                               Distance_workspace& workspace,
                                               double max_seconds = 0.0);

struct Signed_set_distance_result {
  // As Set_distance_result, for signed distances: lower_bound the smallest over all pairs
  // (unqueried or undecided pairs by their boxes: the distance between them, or minus the
  // smallest overlap of the boxes along the coordinate axes, which bounds the hulls' depth),
  // work counts of the best pair's query summed over all queries.
  Signed_distance_result result;
  int body_a = -1, body_b = -1;
  int pairs_queried = 0;
  int pairs_skipped = 0;
};

// The smallest signed distance between a body of A and a body of B (the deepest overlap, else
// the closest pair; Penetration_depth.h). Pairs are taken by their boxes' signed bound, and
// while the best so far is positive each pair's apart query is cut off at it (a pair farther
// apart than that can only win by containment, which is still tested). `max_seconds` (0: no
// limit) is the whole set's wall time, shared out as in set_distance, within the request's own
// limits for each pair. Throws Precondition_violation on an empty set or a missing body.
[[nodiscard]] Signed_set_distance_result signed_set_distance(const std::vector<Placed_body>& A,
                                                             const std::vector<Placed_body>& B,
                                                             const Signed_distance_request& request,
                                                             double max_seconds = 0.0);

}  // namespace extremal
