// The numerical stress ladder: each degeneracy swept over decades down to double precision's
// limit, shared by bench/stress_ladder (every rung, plots) and tests/test_stress_ladder.cpp (a
// few rungs of each sweep).
//
// A sweep is one scene whose degeneracy parameter sets each rung: the angle between two axes,
// the gap to tangency, a point's distance to an axis of revolution or a pole, the difference
// between two minima, the spread of rational weights, the distance of the scene from the
// origin, the distance from a minimum to a trim. At every rung two answers are measured
// against a reference computed in quadruple precision (Boost.Multiprecision) from the rung's
// double-precision input, each from a closed form of the exact shapes (bench/RESULTS.md,
// "Stress ladder", names each):
//   - one-shot: extremal_distance (Global_distance.h) with the request given, timed over
//     repeated solves;
//   - tracked: Body_pair_tracker over a short motion about the rung's pose that keeps the
//     degeneracy (a turn about the common normal, a slide along a trim...), every row read.
// Each rung is then checked: no NaN, no lower bound above the reference, and the error within
// the budget unless the row's status says it was not certified (rung_violations).
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "algorithms/body_pair/Body_pair_options.h"
#include "algorithms/distance/Global_distance.h"

namespace extremal::experiments {

struct Ladder_sweep {
  std::string key;         // e.g. "angle_shaft_in_bore"
  std::string family;      // the degeneracy, e.g. "angle between axes" (one plot per family)
  std::string family_key;  // e.g. "angle" (the plot's file name)
  std::string title;       // the scene, e.g. "shaft tilted in a bore"
  std::string parameter;   // what the rung value is, e.g. "tilt (rad)"
  std::string reference;   // how the reference is computed
  std::vector<double> values;  // the full ladder (0 is the limit itself, not plotted)
  std::vector<double> quick;   // the rungs the ctest run takes
  // A defect not fixed yet that some rungs show: what goes wrong, and the start of the
  // violation it causes (rung_violations). The ctest run skips a sweep whose only violations
  // are that one, with this text.
  std::string known_issue;
  std::string known_violation;
};

// Every sweep, in the order of the issue's list.
const std::vector<Ladder_sweep>& ladder_sweeps();

struct Ladder_options {
  Distance_request one_shot;  // the library defaults: 1e-9 absolute and relative, 200,000 nodes
  Body_pair_options tracked;  // the library defaults: error budget 1e-9 absolute and relative
  int tracked_steps = 20;     // at 1 kHz
  // One-shot solves per rung for the median time, after an untimed one that warms the
  // workspace: up to max_repeats (0: none timed), fewer once repeat_seconds have been spent.
  int max_repeats = 7;
  double repeat_seconds = 1.0;
};

struct Rung_result {
  std::string sweep;
  double parameter = 0.0;
  double reference = 0.0;  // the reference at the rung's pose (t = 0), rounded to double
  // What rounding the input allows the answer to differ from the exact shapes' reference by:
  // the NURBS control data and the placed world coordinates are doubles (see rung_slack).
  double slack = 0.0;

  // One-shot.
  Distance_status status = Distance_status::Converged;
  double distance = 0.0, lower = 0.0, upper = 0.0, tolerance_used = 0.0;
  double budget = 0.0;     // the request's tolerance at the reference
  double error = 0.0;      // |distance - reference|
  double lower_gap = 0.0;  // reference - lower (negative: the lower bound is above it)
  long nodes = 0;
  double seconds = 0.0;  // median over `repeats` solves
  int repeats = 0;

  // Tracked: every row of the short motion.
  int steps = 0;
  int nan_rows = 0;
  int uncertified_rows = 0;  // status Uncertified
  int bound_rows = 0;        // rows with a lower bound
  double tracked_budget = 0.0;  // the error budget at the reference
  double tracked_max_error = 0.0;  // over every row
  // Over the rows that claim the budget (all but Uncertified ones).
  double tracked_max_claimed_error = 0.0;
  // Smallest and largest reference - lower_bound over the rows with a bound (infinity and 0:
  // none had one): the first is checked, the second is how loose the certificate got.
  double tracked_min_lower_gap = std::numeric_limits<double>::infinity();
  double tracked_max_lower_gap = 0.0;
  double step_seconds = 0.0;  // median step time, the first (start) excluded
  std::string tracked_statuses;  // e.g. "tracking 19, uncertified 1"

  // What failed the rung's checks (empty: it passed); see rung_violations.
  std::vector<std::string> violations;
  bool certified() const {
    return status != Distance_status::Budget_exhausted &&
           status != Distance_status::Resolution_limit;
  }
};

// Runs one rung. Throws std::invalid_argument for a value the sweep's reference does not hold
// at (a motion that leaves the closed form's domain).
Rung_result run_rung(const Ladder_sweep& sweep, double value, const Ladder_options& options);

// The rung's checks, as sentences (empty: it passes):
//   - no NaN in the one-shot answer or in any tracked row;
//   - never a lower bound above the reference by more than the slack (one-shot, every row);
//   - the one-shot witness distance not below the reference by more than the slack;
//   - a certified one-shot answer within max(tolerance used, budget) + slack of the
//     reference; a tracked row within the budget + slack unless it reads Uncertified.
std::vector<std::string> rung_violations(const Rung_result& r);

}  // namespace extremal::experiments
