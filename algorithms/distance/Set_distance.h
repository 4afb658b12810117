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

#include "algorithms/distance/Global_distance.h"
#include "algorithms/distance/Penetration_depth.h"
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

// The work of a set query, summed over the body pairs queried.
struct Set_work {
  // The certified distance queries (Distance_result's counters; for signed queries, the apart
  // queries').
  long pairs_processed = 0, nodes_created = 0;
  long newton_runs = 0, intersection_attempts = 0;
  // Signed queries only (Signed_distance_result's counters).
  long cells = 0, supports = 0, winding_cells = 0;
  int body_pairs_queried = 0;  // body pairs given to the solver
  int body_pairs_bounded = 0;  // body pairs bounded by their boxes alone (beyond the best so
                               // far, or left when the time budget ran out)

  // Adds a certified distance query's counters.
  void add(const Distance_result& r) {
    pairs_processed += r.pairs_processed;
    nodes_created += r.nodes_created;
    newton_runs += r.newton_runs;
    intersection_attempts += r.intersection_attempts;
  }
};

struct Set_distance_result {
  // The best pair's result (its own work counters), with the sets' certificate: lower_bound is
  // the smallest lower bound over all pairs, queried or not, and status the best pair's while
  // the sets' gap upper - lower is within its tolerance, else Resolution_limit if the pair
  // holding the smallest lower bound stopped there, else Budget_exhausted. No pair with a
  // witness below the request's cutoff (or none queried): element_a = -1, distance =
  // upper_bound = the cutoff (infinity without one), status by that gap as above.
  Distance_result result;
  int body_a = -1, body_b = -1;  // indices in the sets of the pair that holds the witness
  Set_work work;
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
  // (pairs not queried by their boxes' signed bound, signed_box_bound), status the best pair's
  // while the gap is within its tolerance, else Resolution_limit or Containment_unknown if the
  // pair holding the smallest lower bound stopped so, else Budget_exhausted. No witness (no
  // pair queried): element_a = -1, distance = upper_bound = infinity, Budget_exhausted.
  Signed_distance_result result;
  int body_a = -1, body_b = -1;
  Set_work work;
};

// The smallest signed distance between a body of A and a body of B (the deepest overlap, else
// the closest pair; Penetration_depth.h). Pairs are taken by their boxes' signed bound, most
// overlapping first (ties: A-major order), and while the best so far is positive (above its
// tolerance) each pair's apart query is cut off at it: a pair farther apart than that can only
// win by containment, which is still tested (its certified clearance is then positive).
// `max_seconds` (0: no limit) is the whole set's wall time, each pair's query getting what is
// left (Signed_distance_request::total_seconds). Throws Precondition_violation on an empty set
// or a missing body.
[[nodiscard]] Signed_set_distance_result signed_set_distance(const std::vector<Placed_body>& A,
                                                             const std::vector<Placed_body>& B,
                                                             const Signed_distance_request& request,
                                                             double max_seconds = 0.0);

}  // namespace extremal
