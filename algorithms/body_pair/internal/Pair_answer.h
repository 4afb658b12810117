// What an engine of a body-pair tracker found at a step (the NURBS stages, the mesh front, a
// ball as its centre), and the one mapping from it to the pair's report row and status. Not
// API.
#pragma once

#include <optional>

#include "algorithms/body_pair/Body_pair_options.h"
#include "algorithms/body_pair/Pair_report.h"

namespace extremal::internal {

// Where a reading came from: a tracker (or a mesh front's exact closed form) that holds a pair
// of the bodies, or the certified solver at this step because no tracker held one.
enum class Reading_source : unsigned char { Tracked, Solved };

// The kind of pair a tracked reading holds, as far as its status goes.
enum class Reading_shape : unsigned char {
  Interior,  // both witnesses free: an interior stationary pair
  Boundary,  // a witness held on a patch edge or corner
  Fallback,  // degenerate geometry: the damped step (Pair_answer::degeneracy says why)
};

struct Pair_answer {
  double distance = 0.0;  // signed where the geometry has an outward side
  Vec3 point_a = Vec3::Zero(), point_b = Vec3::Zero(), normal = Vec3::Zero();
  // The report's elements: face index (curves, then mesh triangles, after the faces), B-rep
  // edge (-1: none), and the parameters on those faces (A's, then B's).
  int feature_a = -1, feature_b = -1, edge_a = -1, edge_b = -1;
  Vec4 params = Vec4::Zero();
  Degeneracy degeneracy = Degeneracy::None;
  Reading_shape shape = Reading_shape::Interior;
  Reading_source source = Reading_source::Tracked;
  // When solved: the rule that rejected the closest tracker's reading (None: no tracker read).
  Reading_rule rejected_by = Reading_rule::None;
  // The certified lower bound on the bodies' true distance made at this step (none: nothing
  // certified). Only read apart.
  std::optional<double> lower_bound;
  // The candidates would not fit the memory limit at this step (Pair_report::memory_limited).
  bool memory_limited = false;
};

// The report row of an answer at time t: its status from the distance (penetrating below
// minus the contact tolerance, contact within it, else by the reading's shape), and apart its
// lower bound (never above the distance), `uncertified` where that bound is short of the error
// budget. Test Certificate.EveryApartRowsLowerBoundHoldsAgainstTheOneShotSolver.
Pair_report report_of(const Pair_answer& answer, double t, double contact_tolerance,
                      const Error_budget& budget);

// The row of a pair beyond the threshold: `farther`, its distance `box_bound` (a lower bound on
// the bodies' distance, and its lower_bound), no witnesses.
Pair_report farther_report(double t, double box_bound);

}  // namespace extremal::internal
