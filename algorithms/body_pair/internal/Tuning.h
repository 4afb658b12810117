// Every tuning number of the body-pair tracker, named once: what it bounds, and the bench scene
// whose measurement set it ("Set by", bench/RESULTS.md and git history) or the test that
// exercises it ("Shown by"). Lengths are fractions of the stated size; errors are normalised
// (sines of angles).
// The options a user sets are in Body_pair_options.h. Not API.
#pragma once

#include <cstddef>

namespace extremal::internal {

// ---- Readings (Reading_rules, Live_set) --------------------------------------------------
// Normalised projection errors within this along the free parameters: converged on its pair,
// about d e^2 / 2 above its minimum, far below the seeding tolerance (a tracked pair carries a
// crease only then). Shown by BodyScenes.CreaseTieStillCatchesTheNeighboursDeeperBump.
constexpr double k_converged_error = 1e-6;
// Beyond this, inside the bodies, a flow is wandering outside the basin of any penetration
// pair (a lagging tracker stays orders of magnitude below); also the margin of the normal
// form's conditions and of the normals' tests. Shown by
// Contact.BodiesThatStartOverlappingReportTheirDepthFromTheFirstStep.
constexpr double k_wandering_error = 1e-2;
// A trim boundary's tangent is its flattened polyline's chord, a degree or two off the curve:
// a crossing is read at a trim edge only past this cosine. Shown by
// RimContact.PartsSeatedFlushInAnAssemblyTouchWithoutInterference (as1's bolt shank: 1.1 deg).
constexpr double k_trim_chord_crossing = 0.1;
// An outward normal is defined where its length exceeds this fraction of its factors' (a pole's
// limit below it is no direction). Shown by Contact.ABallRisingInACylinderLeavesThroughItsCap.
constexpr double k_normal_defined = 1e-8;
// Readings up to this many contact tolerances apart count as near contact for the normals'
// test between two solids' faces. Shown by Contact.ABallTouchingACylindersCapFromWithinReadsItsDepth.
constexpr double k_near_contact = 1e3;
// Two outward normals are alike past this cosine (60 degrees). Shown by
// Contact.ABallTouchingACylindersCapFromWithinReadsItsDepth.
constexpr double k_normals_alike = 0.5;
// Normals perpendicular are no sign of a depth or a distance: opposed unless past this cosine.
// Shown by BodyScenes.ABallShotIntoABoxReportsItsDepth and
// BodyScenes.ABallInsideANonConvexPartIsNeverApart.
constexpr double k_normals_opposed = 1e-6;
// An edge's two faces join smoothly (one normal, no wedge) where 1 - cos^2 of their normals'
// angle is below this. Shown by EdgeSlide.APegSlidOntoABoxsTopFromItsSideReadsTheShallowerDepth.
constexpr double k_smooth_join = 1e-6;
// An open body's witness counts as inside a solid's box (Depth_monitor's trigger) within this
// fraction of the box's diagonal (plus the contact tolerance). Shown by
// ProbeScenes.ABoxLeavingPastASheetsBorderIsApart.
constexpr double k_box_margin = 1e-9;

// ---- Hand-overs and merges (Live_set) ----------------------------------------------------
// A descent leaves a patch side (or enters a neighbour) past this fraction of its scale.
// Shown by BodyScenes.AFacePointLeavingAtACornerGoesToTheEdgeItSlidesOn.
constexpr double k_descent = 1e-10;
// An edge's direction in a face's parameter plane by central differences of this fraction of
// the edge's domain; an untrimmed face's edge band, this fraction of its larger domain side;
// the face's side is probed this many bands off the edge. Shown by
// Contact.PointSlidesOffAnEdgeRoundACornerAndBack.
constexpr double k_edge_difference = 1e-6;
constexpr double k_untrimmed_band = 1e-6;
constexpr double k_side_probe_bands = 4.0;
// A handed-over point starts this fraction of its domain inside it (a parameter held on a
// patch edge is left out of the corrections). Shown by
// BodyScenes.AFacePointLeavingAtACornerGoesToTheEdgeItSlidesOn.
constexpr double k_handover_inset = 1e-9;
// Trackers of one primitive pair whose witnesses are within this fraction of the larger body's
// diagonal are one. Shown by BodyScenes.MultiPatchTorusWithASphereThroughItsHole.
constexpr double k_merge_distance = 1e-7;

// ---- Seeding (Pair_seeding, Depth_monitor) -----------------------------------------------
// Samples per parameter of a sampled seed (pairs the solver has no element for: mesh edges),
// and of the interior points a seed on a patch side is moved towards. Shown by
// BodyScenes.MeshAgainstNurbsAndMeshAgainstMesh and Contact.ParallelPlanesThroughContact.
constexpr int k_sampled_seed_grid = 8;
constexpr int k_central_seed_grid = 4;
// Two distances tie within this fraction (of 1 + the distance) when a seed is moved to a more
// central pair. Shown by Contact.ParallelPlanesThroughContact.
constexpr double k_distance_tie = 1e-12;
// A seed of a depth is matched to faces and pairs to this fraction of the largest of 1, the
// depth and the bodies' diagonals (a depth whose budget ran out is a little off; this is a
// seed), with normals aligned to within 1 - k_depth_seed_aligned, over a grid of this many
// samples per parameter. Shown by Contact.CrossingRodsReportTheDepthOnTheSidesTheyLeaveBy and
// bench/scenes/shaft_in_bore.json.
constexpr double k_depth_seed_tolerance = 1e-4;
constexpr double k_depth_seed_aligned = 1e-6;
constexpr int k_depth_seed_grid = 8;
// The hulls' witnesses face each other (they are the depth's pair) within this fraction of the
// shift that parts them. Shown by Contact.SphereThroughSphereExactSignedDistance.
constexpr double k_facing_pair = 1e-2;
// Relative tolerance of the coarse hull depth taken against a tracked depth, and of the solve
// that finds the depth's pair once the hulls are moved apart. Shown by
// RimContact.APegTumblingOnABoxReadsItsFarRimOnceItIsTheDeeper.
constexpr double k_coarse_depth_tolerance = 1e-3;
constexpr double k_depth_pair_tolerance = 1e-6;

// ---- Balls tracked as their centres (Ball_pair) ------------------------------------------
// The witness's parameters on a ball's face: Newton's method from the last step's, at most this
// many corrections, to this normalised projection error. Shown by
// BodyScenes.ABallIsTrackedAsItsCentre.
constexpr int k_witness_corrections = 10;
// Its first start: the nearest of a grid of this many intervals per parameter over the face.
constexpr int k_witness_start_grid = 16;
constexpr double k_witness_tolerance = 1e-12;
// ---- Broad phase (Kept_proof_stage) ------------------------------------------------------
// Default broad-phase margin: this fraction of the smaller body's diagonal. Set by bench
// compare (b), (c).
constexpr double k_default_broad_margin = 0.02;
// The broad phase reaches this fraction of the margin farther than it must, so that it runs
// again only once the relative motion since has used that up. Set by bench compare (c).
constexpr double k_broad_extra = 0.5;
// Two relative poses are one within this (rotation entries; translations as a fraction of the
// larger body's diagonal). Shown by BodyScenes.SteadyTrackingAllocatesNothing.
constexpr double k_same_pose = 1e-14;

// ---- Certification of candidates (Kept_proof_certification) ------------------------------
// The candidates' queues are made anew once the motion summed in their keys exceeds this many
// times the larger body's size (a key's rounding, subtracted from its bound, stays about 1e-14
// of that motion). Shown by BodyScenes.CarriedBoundsSkipMostRechecksAndStillCatchAnOvertakingBump.
constexpr double k_requeue_motion = 1e2;
// A candidates' queue drops its stale entries once it holds this many per candidate. Shown by
// BodyScenes.SteadyTrackingAllocatesNothing.
constexpr std::size_t k_queue_slack = 4;
// A primitive is flat (a plane, a line: Primitive::flatness) when its control points lie within
// this fraction of its size from one (imported planes and lines: to rounding). Shown by
// BodyScenes.FlatAgainstConvexPairsNeedNoWatch.
constexpr double k_flat_fraction = 1e-9;
// A flat pair's tracked reading is its minimum when the primitives' flatness adds up to at most
// this fraction of the error budget (a second basin lies at most twice their flatness below).
constexpr double k_flat_budget = 0.25;
// Newton's method on a pair with one basin (Kept_proof_stage::locate_single_basin): at most this
// many steps, stopping once the normalised projection errors are within k_locate_tolerance; the
// point counts as the stationary point within k_locate_converged. Shown by
// BodyScenes.FlatAgainstConvexPairsNeedNoWatch.
constexpr int k_locate_corrections = 30;
constexpr double k_locate_tolerance = 1e-13;
constexpr double k_locate_converged = 1e-10;
// A candidate keeps the proofs of at most this many solves (a partial solve adds one); past
// it, the pair is solved anew. Set by bench compare (c) at 1 kHz.
constexpr int k_kept_solves = 8;
// A watch's convex region about the tracked point is doubled at most this many times after
// its solve (Kept_proof_stage::grow_region). Set by bench compare (b) at 10 kHz.
constexpr int k_region_doublings = 4;
// The least slack of a restricted solve's cutoff, and the least gap of the own-basin watch,
// in seeding tolerances. Shown by BodyScenes.AuditsOrTheWatchMoveATrackerToALowerBasinOfItsOwnPair.
constexpr double k_seeding_slack = 4.0;
// The watch's cutoffs stay this fraction of the gap below the tracked basin, so that its
// solves settle it rather than converge on it. Shown by BodyScenes.ARodMovedAcrossARingFollowsTheRingsNearSide.
constexpr double k_watch_ceiling = 0.5;
// A pair's restricted solve is cut off at least this many steps' worth of the pair's relative
// motion above the tracked minimum, so that its bound clears the next steps' checks without a
// solve; the next solve of a pair that found nothing reaches this many times higher. Shown by
// BodyScenes.CarriedBoundsSkipMostRechecksAndStillCatchAnOvertakingBump and bench compare (c).
constexpr double k_slack_steps = 8.0;
constexpr double k_slack_growth = 4.0;
// Trim-edge set-asides of a usual restricted solve must outlast this many steps' motion.
// Set by bench compare (c).
constexpr double k_reach_steps = 2.0;
// A proving solve is cut off this many steps' motion above the tracked minimum (higher, the
// pairs near a trim edge need deeper splits). Set by bench compare (c) at 1 kHz (sub-patch
// nodes: 2 steps 442k, 1 step 468k, 4 steps 523k, 8 steps 794k, none 486k).
constexpr double k_proving_steps = 2.0;
// A crease solve is cut off this fraction of the broad margin above the tracked minimum, and
// sets sub-patch pairs aside only when their gradient proof lasts as much motion, within this
// node budget. Set by bench compare (b) (an eighth: 179k / 43.9k / 18.1k nodes at 10 kHz /
// 1 kHz / 100 Hz; a quarter 243k / 49.4k / 17.3k) and
// BodyScenes.CreaseTieStillCatchesTheNeighboursDeeperBump.
constexpr double k_crease_fraction = 0.125;
constexpr int k_crease_nodes = 200;
// A patch side is a crease shared with a tracked neighbour when its certified gap to the
// neighbour's side is within this fraction of the seeding tolerance. Shown by
// BodyScenes.CreaseTieStillCatchesTheNeighboursDeeperBump.
constexpr double k_crease_gap = 0.25;
// A partial solve restarts at most this many times the node budget's sub-patch pairs (more:
// solved anew). Set by bench compare (c) at 1 kHz (twice: 293k nodes; once 307k; half 374k)
// and BodyScenes.TwoBodiesOfTheAs1AssemblyInRelativeMotion.
constexpr int k_partial_restarts = 2;
// The kept proofs' pools are compacted once their stale entries outnumber the live ones by
// this factor plus these counts. Set by bench compare (c).
constexpr int k_compact_factor = 2;
constexpr int k_compact_proofs = 1024;
constexpr int k_compact_bounds = 4096;
// They are compacted, rather than grown, when a solve's entries would pass their capacity and
// at least this share of it is stale: a pool grows only when its live entries outgrow it, so a
// periodic motion stops allocating once one period has passed. Shown by
// BodyScenes.SteadyTrackingAllocatesNothing.
constexpr double k_compact_stale_share = 0.25;

// ---- Depth monitor -------------------------------------------------------------------------
// Within the normal form's band (depths up to this fraction of the smaller body) the tracked
// pair is the one the bodies met at, and is not checked. Shown by
// Contact.DeepPassagesReportTheDepthAndLeaveApart.
constexpr double k_deep_band = 0.1;
// The check runs again once the depth grew by this fraction of the smaller body since the
// last (between checks a stale pair is off by at most twice that). Set by
// bench/scenes/ball_through_ball.json and Contact.DeepPassagesReportTheDepthAndLeaveApart.
constexpr double k_deep_growth = 1e-2;
// Two solids are checked again once either's box centre moved this many growth steps relative
// to the other (a shaft turning in place is not). Shown by Contact.ABallRisingInACylinderLeavesThroughItsCap
// and bench/scenes/shaft_in_bore.json.
constexpr double k_deep_motion_steps = 10.0;
// A solid against a sheet, as deep as it is wide along the pair's normal, is checked once the
// bodies moved this fraction of the size since the last check. Shown by
// Contact.ABallThroughAnOpenPlaneIsApartOnceOut.
constexpr double k_sheet_motion = 1e-3;
// Gauss-Newton steps of the search for the surfaces' common point again from the last one
// (bodies not both closed, penetrating): past them, the certified solve decides. Shown by
// Contact.TwoOpenSheetsPassedThroughEachOtherAreApartOnceOut.
constexpr int k_common_point_steps = 8;
// Sub-nets of each support query bounding a solid's width against a sheet: its lower bound is
// a real point's, so a small budget can only make the check early. Shown by
// SheetDepth.ATurnedEllipsoidThroughAPlaneSpinningKeepsItsEntrySideUntilOut.
constexpr int k_width_nets = 200;

}  // namespace extremal::internal
