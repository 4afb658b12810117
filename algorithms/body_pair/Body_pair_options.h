// What a body-pair tracker (Body_pair_tracker.h) is asked for: the trackers' own options, the
// scene's threshold and contact tolerance, and the certified solver's requests for seeding,
// overlaps and audits.
#pragma once

#include "algorithms/distance/Global_distance.h"
#include "algorithms/distance/Penetration_depth.h"
#include "algorithms/pair/Extremal_tracker.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace extremal {

// The error a user allows an apart reading (as FCL's and Coal's abs_err and rel_err): every
// apart row carries a certified lower bound on the bodies' true distance d of at least
// d - max(absolute, relative |d|) (Pair_report::lower_bound), or the status Uncertified. The
// certification proves no more than that: a looser budget costs less.
struct Error_budget {
  double absolute = 1e-9;
  double relative = 1e-9;
  double at(double d) const { return std::max(absolute, relative * std::abs(d)); }
};

struct Body_pair_options {
  // What an apart row may miss the true distance by (see Error_budget).
  Error_budget tolerance;
  // Scenes correct the pair when one step's linearisation falls short (see
  // Tracker_options::corrections).
  Tracker_options tracker = [] {
    Tracker_options o;
    o.corrections = 10;
    return o;
  }();
  double threshold = 0.0;  // > 0: pairs whose boxes are farther apart are not tracked
  // Broad-phase margin added to the current distance (scene units); 0: 2% of the smaller
  // body's box diagonal.
  double broad_margin = 0.0;
  double contact_tolerance = 1e-9;  // |distance| at or below this is contact
  // Steps between audits by the certified global solver (0 = never): when the global minimum
  // has moved to another feature pair, a tracker is seeded there.
  int audit_every = 0;
  // A tracked primitive pair is watched for another basin of its own (a rod moved across a
  // ring leaves the ring's near side for its far side, both on one face pair): a basin that
  // comes closer than the tracked one by more than this fraction of its distance, or by more
  // than the error budget if that is less, gets the pair's tracker. Smaller costs deeper
  // restricted solves near the tracked minimum, which the watch must clear without settling
  // it; 0: not watched (the rows of two bodies not both convex then carry no certified bound
  // beyond the tracked pair's own: see Pair_report::lower_bound).
  double own_basin_gap = 1e-3;
  // The most memory, in bytes, one pair's candidate stage may hold: its candidate primitive
  // pairs (with their queues and the broad phase's scratch), their kept proofs and the trackers
  // on them. A step whose candidates would not fit keeps none: the pair is certified by the
  // global solver at that step instead (its memory bounded by `global.max_nodes`, as each
  // restricted solve's by its request's), and its row says so (Pair_report::memory_limited).
  // Kept proofs that would not fit are not kept (their pairs are solved again when due). The
  // default is far above what the bench scenes' and probe sets' pairs use (bench/RESULTS.md,
  // "Memory per pair"); 0: no limit.
  std::size_t memory_limit = std::size_t{1} << 30;
  // The certified solver's request on one candidate primitive pair (seeding a new pair, and
  // checking a pair whose tracker moved on for a closer basin): a start for the tracker, whose
  // corrections converge it, so a looser tolerance and a small node budget bound the cost of
  // pairs with a continuum of equal minima (parallel planar faces). The certification of
  // candidate pairs runs it at no more than a quarter of the error budget (k_seeding_slack).
  Distance_request seeding = [] {
    Distance_request r;
    r.absolute_tolerance = 1e-9;
    r.relative_tolerance = 1e-9;
    r.max_nodes = 3000;
    return r;
  }();
  // Bodies that overlap when a tracker starts or re-seeds (surfaces meet, or one inside the
  // other): the penetration pair of their convex hulls (hull_signed_distance) seeds a tracker
  // that reports the depth. The cells bound the cost where the depth has a continuum of
  // directions (coaxial bodies); the tracker's corrections converge the seed.
  Signed_distance_request overlap = [] {
    Signed_distance_request r;
    r.absolute_tolerance = 1e-9;
    r.relative_tolerance = 1e-9;
    r.max_cells = 4000;
    return r;
  }();
  // The certified solver's request for the start and the audits. Without the bounds about
  // centres and axes of symmetry: with them the start at a ball's pole above a cylinder's cap
  // centre (bench/stress_suite c0_cylinder) lands the tracker's first step 1.1e-6 off, a pole
  // start-up transient not yet mended. Its tolerances are capped by the error budget (its
  // answer is the row when no tracker holds).
  Distance_request global = [] {
    Distance_request r;
    r.absolute_tolerance = 1e-7;
    r.relative_tolerance = 1e-7;
    r.max_nodes = 50000;
    r.symmetry_bounds = false;
    return r;
  }();
  // A global solve that spends its node budget with its bound at or below contact_tolerance and
  // its witness above it has neither parted the surfaces nor found where they meet (a shallow
  // crossing), and one that spends it without finding a witness at all: each is solved again
  // with this many nodes, the one-shot distance's default. Shown by
  // ProbeScenes.TwoFacesOfAPartThatCrossReadPenetratingAtEveryStep and
  // ProbeScenes.ASheetFarFromATorusPassingByReadsAFiniteDistanceAtEveryStep.
  int undecided_max_nodes = Distance_request{}.max_nodes;
};

}  // namespace extremal
