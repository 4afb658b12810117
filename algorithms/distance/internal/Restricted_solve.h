// The certified solver restricted to one element pair, with what only a caller that keeps its
// proofs across motion asks of it (the body-pair tracker's candidate certification): sides whose
// minima other pairs carry, a floor that turns the query into a proof against a cutoff, a known
// stationary point, the proofs kept, and the relative motion's axis. Not API.
#pragma once

#include <array>
#include <cmath>
#include <optional>
#include <vector>

#include "algorithms/distance/Global_distance.h"

namespace extremal::internal {

struct Proof_request {
  // Sides of element_a ([0]) and of element_b ([1]) whose minima another pair carries (bits as
  // Element::open_sides: 1 and 2 the lower and upper end of the first parameter, 4 and 8 of the
  // second), e.g. a patch side shared with a face whose pair with the other element is
  // tracked. Sub-patch pairs touching no other open side of the element, over which the
  // gradient of the squared distance along its parameters provably does not vanish, are set
  // aside: their minimum lies on a carried side (see Distance_result::uncarried_lower_bound and
  // carried_reach).
  std::array<unsigned, 2> carried_sides{{0u, 0u}};
  // A pair is set aside for a carried boundary (trim edges, carried_sides) only when its
  // gradient keeps its sign while the other element moves by at least this much
  // (Distance_result::carried_reach); others are split.
  double carried_min_reach = 0.0;
  // With a finite cutoff: while no witness lies below this floor, pairs are pruned against the
  // cutoff rather than the best witness, so a query that finds nothing below the floor settles
  // every pair it does not set aside at the cutoff (uncarried_lower_bound >= the cutoff, up to
  // the tolerance) instead of stopping at a witness between floor and cutoff (a tie held on a
  // carried side). A witness below the floor brings the usual pruning back (the closer basin is
  // found). -infinity: the usual pruning.
  double cutoff_floor = -HUGE_VAL;
  // A stationary point of the two elements' distance the caller knows (a converged tracker's
  // parameters, A's then B's, as Distance_result::params_a/_b). A convex region about it is
  // certified as the pairs that hold it are split, even while proving a cutoff below it: the
  // region's bound (the distance there, less the point's residual) settles those pairs, where
  // hull bounds would need sub-patches as small as the square root of the cutoff's distance
  // below it (the body-pair tracker's watch of a tracked pair).
  std::optional<std::array<double, 4>> stationary;
  // Keep the proofs behind the result in the workspace (Distance_workspace::gradient_proofs,
  // bound_proofs), for a caller that checks them again after motion instead of solving again.
  bool keep_proofs = false;
  // The line (world, kind Axis) the bodies' relative motion turns about, when the caller knows
  // it (from the twists): bounds about a symmetry of either element along it are taken against
  // every other element too, since that turn leaves them whole (kept, they outlast it;
  // elsewhere only shared symmetries are worth their cost).
  Symmetry motion_axis;
};

// A pair of sub-patches of a restricted query's two elements, by their parameter boxes (as
// Bound_proof and Gradient_proof keep them; a curve's second parameter: 0 to 0), each inside
// one Bezier piece of its element.
struct Sub_patch_pair {
  std::array<double, 2> a_lo{{0, 0}}, a_hi{{0, 0}}, b_lo{{0, 0}}, b_hi{{0, 0}};
};

// A box of parameters of one element pair: element_a's, then element_b's right after them (a
// face has two, a curve one, a point none), as Proof_request::stationary.
struct Parameter_box {
  int element_a = -1, element_b = -1;
  std::array<double, 4> lo{{0, 0, 0, 0}}, hi{{0, 0, 0, 0}};
};

// The region about Proof_request::stationary that the last query on `workspace` certified
// convex (every sub-patch pair inside it settled by that region's bound), if it did.
std::optional<Parameter_box> stationary_region(const Distance_workspace& workspace);

// Whether the squared distance of the box's element pair is certified convex over the whole
// box at these poses (the interval Hessian positive definite there), and if so the lower bound
// on the distance over the box that convexity about x (inside the box) gives: the distance at
// x less its gradient's reach across the box. A tracked minimum's region, certified by a
// solve, checked again after motion without solving (the own-basin watch's carried region).
std::optional<double> convex_region_lower(const Distance_hierarchy& A, const Rigid_pose_3& X_WA,
                                          const Distance_hierarchy& B, const Rigid_pose_3& X_WB,
                                          const Parameter_box& box, const std::array<double, 4>& x,
                                          Distance_workspace& workspace);

// extremal_distance (Global_distance.h) with the proof request (of its fields, keep_proofs and
// motion_axis apply to the whole bodies' query).
[[nodiscard]] Distance_result extremal_distance(const Distance_hierarchy& A,
                                                const Rigid_pose_3& X_WA,
                                                const Distance_hierarchy& B,
                                                const Rigid_pose_3& X_WB,
                                                const Distance_request& request,
                                                const Proof_request& proof,
                                                Distance_workspace& workspace);

// extremal_distance_between (Global_distance.h) with the proof request.
[[nodiscard]] Distance_result extremal_distance_between(const Distance_hierarchy& A,
                                                        const Rigid_pose_3& X_WA, int element_a,
                                                        const Distance_hierarchy& B,
                                                        const Rigid_pose_3& X_WB, int element_b,
                                                        const Distance_request& request,
                                                        const Proof_request& proof,
                                                        Distance_workspace& workspace);

// The same restricted query over the given sub-patch pairs only: its bounds, witness and kept
// proofs cover their union, not the whole elements. A caller whose earlier proofs still hold
// over the rest of the domain re-solves only where they fail. Throws Precondition_violation on
// a box outside every piece of its element.
[[nodiscard]] Distance_result extremal_distance_between(const Distance_hierarchy& A,
                                                        const Rigid_pose_3& X_WA, int element_a,
                                                        const Distance_hierarchy& B,
                                                        const Rigid_pose_3& X_WB, int element_b,
                                                        const std::vector<Sub_patch_pair>& starts,
                                                        const Distance_request& request,
                                                        const Proof_request& proof,
                                                        Distance_workspace& workspace);

}  // namespace extremal::internal
