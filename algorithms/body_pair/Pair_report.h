// What a body-pair tracker reports at a step: the reading (the extremal pair and its status)
// and, apart from it, the statistics of the work done so far.
#pragma once

#include <cstddef>
#include <optional>

#include "algorithms/pair/Extremal_tracker.h"
#include "kernel/Types.h"

namespace extremal {

enum class Pair_status {
  Tracking,     // apart, tracked
  Contact,      // touching: |distance| within the contact tolerance
  Penetrating,  // distance below minus the contact tolerance
  Boundary,     // apart, the pair on a patch edge or corner
  Farther,      // beyond the threshold: not tracked
  Fallback,     // degenerate geometry: damped step (Pair_report::degeneracy says why)
  // Apart, but the certificate that nothing is closer by more than the error budget could not
  // be made within the step (a restricted solve ran out of its node budget): lower_bound says
  // what was certified.
  Uncertified,
};
const char* to_string(Pair_status s);

// The rules that decide whether a tracker's reading holds a pair of the bodies, in the order
// they are applied (docs/behaviour.md gives each one's situation and test). None: it holds.
enum class Reading_rule : unsigned char {
  None,
  Witness_off_face,                  // a witness outside its face's trim or triangle
  Normal_form_unsolved,              // the contact form's conditions do not hold
  Wandering_inside,                  // deep inside, the flow not converged on a pair
  Normals_alike_in_contact,          // two solids' faces touching from within
  Depth_normals_not_opposed,         // a depth whose outward normals do not oppose
  Apart_witness_inside,              // apart, but A's witness lies inside B
  Deeper_than_boxes,                 // deeper than the two solids' boxes overlap
  Edge_outside_wedge,                // an edge's depth direction outside its normals' wedge
  Depth_not_reached_through_contact, // a depth the tracker never came to through contact
};
// The rule's name as the report's detail column shows it (snake case, e.g. "witness_off_face").
const char* to_string(Reading_rule r);

struct Pair_report {
  double time = 0.0;
  double distance = 0.0;  // signed where the geometry has an outward side
  Vec3 point_a = Vec3::Zero(), point_b = Vec3::Zero(), normal = Vec3::Zero();
  // Face index (curves follow the faces, mesh triangles follow them as in the global solver);
  // a witness on a B-rep or mesh edge names a face along it, params mapped onto that face.
  int feature_a = -1, feature_b = -1;
  Vec4 params = Vec4::Zero();
  int edge_a = -1, edge_b = -1;  // B-rep edge (Body::edges) the witness lies on, else -1
  Pair_status status = Pair_status::Tracking;
  Degeneracy degeneracy = Degeneracy::None;
  // No tracker held a pair on the bodies at this step (all seeded this step, or wandering in a
  // deep overlap): the answer is the certified solver's of this step (0 at a common point
  // where the surfaces meet, the hulls' depth where a body lies inside the other).
  bool solved = false;
  // When solved: the rule that rejected the closest tracker's reading (None: no tracker read
  // a pair, or all were seeded this step and none had been judged).
  Reading_rule rejected_by = Reading_rule::None;
  // Apart (and farther): a certified lower bound on the bodies' true distance at this step, at
  // least distance - Error_budget::at(distance) unless the status is Uncertified. None where
  // the bodies touch or overlap (a depth is local: no bound on it is certified).
  std::optional<double> lower_bound;
  // The pair's candidates would not fit its memory limit (Body_pair_options::memory_limit) at
  // this step: the row was certified by the global solver alone (apart rows `uncertified`
  // where that solve fell short of the budget).
  bool memory_limited = false;
};

// Work done by a body-pair tracker since its start (Body_pair_tracker::statistics).
struct Pair_statistics {
  int trackers = 0;    // live feature-pair trackers at the last step
  int candidates = 0;  // live candidate primitive pairs of the broad phase at the last step
  // Steps the pair was computed at (not those whose report stood: nothing moved, or the bodies
  // moved as one).
  long computed_steps = 0;
  // Certified global solves so far (start, audits, re-seeds and the depth monitor's checks),
  // and the trackers audits and re-seeds seeded.
  int audits = 0, reseeds = 0;
  // Patch transitions (a tracker handed across an edge or side), merges (trackers that
  // reached the same pair), trackers seeded on candidate pairs (entering in contact, found
  // closer than the tracked minimum, or in contact when it began).
  long transitions = 0, merges = 0, seeds = 0;
  long broad_phases = 0;  // broad phases run
  // Candidate pairs without a tracker checked for a basin closer than the tracked minimum
  // (one per pair and step); the checks whose carried lower bound (decayed by the relative
  // motion since it was certified) could not clear them, which ran the restricted certified
  // solver; and the trackers those solves seeded on a closer basin.
  long vacated_checks = 0, vacated_solves = 0, vacated_seeds = 0;
  // Candidate pairs a step certified by their queued bound alone, without a check (their bound,
  // less the motion since, still clears the tracked minimum).
  long vacated_queued = 0;
  // Of those solves, the ones on a face sharing a patch side with a tracked face (a crease:
  // the side declared carried).
  long vacated_crease_solves = 0;
  // Of those solves, the ones whose carried bound still cleared the tracked minimum: the
  // neighbours across its carried sides were no longer tracked, or the reach of its set-aside
  // proofs had run out and checking them again at the current pose failed.
  long vacated_reach_solves = 0;
  // Sub-patch nodes those solves made in all (a repeatable measure of their work).
  long vacated_nodes = 0;
  // Of those solves, the ones that solved again only the sub-patch pairs whose kept proofs no
  // longer cleared it (the rest of the pair's domain kept its proofs).
  long vacated_partial_solves = 0;
  // Checks of pairs with one basin settled by Newton's method instead of a solve.
  long located = 0;
  // Checks past the reach whose set-aside proofs all still held at the current pose: no solve.
  long vacated_proof_checks = 0;
  // Checks whose carried bound ran out but whose last solve's bounded pairs, re-bounded at the
  // current pose, still cleared the tracked minimum: no solve.
  long vacated_bound_checks = 0;
  // Corrections run over the trackers' steps (Tracker_options), and the steps that ran all of
  // them without converging first.
  long corrections = 0, capped_corrections = 0;
  // Mesh pairs (two bodies each a mesh or a point): the certified front's work so far. Entries
  // opened (their decayed bound no longer cleared the minimum), box pairs bounded, triangle
  // pairs measured exactly, and traversals from the roots (the first step, growth, and steps
  // whose carried front cost more than a traversal). `candidates` is the front's size.
  long front_opened = 0, front_box_bounds = 0, front_triangle_pairs = 0, front_traversals = 0;
  // The most bytes the candidate stage held at once (Body_pair_options::memory_limit counts
  // them), and the steps whose candidates would not fit it.
  std::size_t memory_bytes = 0;
  long memory_limited_steps = 0;
};

}  // namespace extremal
