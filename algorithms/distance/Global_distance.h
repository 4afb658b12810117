// Certified global extremal distance between two posed bodies (branch and bound over Bezier
// sub-patches, docs/design.md, "The certified solvers").
//
// The distance is the minimum distance between the bodies' geometry (faces, curves, a point body's
// origin), with a certificate: lower_bound <= true minimum <= upper_bound, where upper_bound is the
// distance of a witness pair of points that lie on the bodies, and the gap upper - lower is within
// the requested tolerance (status Converged) or the result says why not.
//
// Trimmed faces (imported CAD): a face's pieces cover its whole underlying patch, so a witness on
// a face counts only where Face::contains holds (Trim_region, with its On_boundary band), and the
// B-rep edges' 3D curves (Body::edges, over [t_min, t_max]) are curve elements, which carry the
// minima on trim boundaries. Hull bounds of a piece of a trimmed face stay valid lower bounds
// for its trimmed part; a piece whose parameter box lies wholly outside the trim is dropped.
//
// Method. Every face and curve is cut into its Bezier pieces once, in the body frame, and the
// pieces are put in a bounding-volume tree (Distance_hierarchy). A query places both trees in the
// world and runs a best-first branch and bound over pairs of nodes:
//   - lower bounds: the distance between the nodes' world boxes, and for two Bezier sub-patches
//     the gap between the projections of their control points on a few axes (the witness normal,
//     the line through their centroids, and where those gain nothing on the parent pair, each
//     sub-patch's own normal: nearly parallel sheets that bend). A rational patch with positive
//     weights lies in the convex hull of its Cartesian control points, so both are certified;
//     and where one element's centre or axis of symmetry is (nearly) the other's, or the other
//     is a point, the gap between the sub-patches' ranges of distances to it (Symmetry.h):
//     exact on concentric spheres and coaxial cylinders, whose continuum of minima the hull
//     bounds close only quadratically in the sub-patch size (a kept proof of it records the
//     ranges, which a turn about the shared axis leaves whole: Bound_proof);
//   - upper bounds: on-surface corner points of the sub-patches, then a Newton polish of the pair
//     (solve_pair_at_rest) on the whole face or curve whenever a pair beats the best so far;
//   - near a Newton solution that may be the minimum: a parameter box on which |f_A - f_B|^2 is
//     proven convex (interval Hessian from the sub-nets' hodographs) bounds every pair inside it
//     by the solution's distance up to its residual, so tight tolerances cost no more nodes;
//   - trimmed faces whose edges are curve elements: a pair on which the gradient along the
//     face's parameters provably does not vanish holds no minimum (it would lie on an edge) and
//     is dropped, which certifies minima on trim boundaries;
//   - the pair with the smallest lower bound is split (the larger node, in two, by de Casteljau
//     in homogeneous coordinates), pairs whose bound cannot beat the best witness are pruned.
// Intersections: when the bounds of a pair reach zero, a Gauss-Newton solve of f = h looks for a
// common point; a found one ends the query with distance exactly 0 (status Intersecting, or
// Touching when the surfaces are tangent there). A small positive number is never reported for
// bodies that meet.
//
// Sub-nets made during a query live in a Distance_workspace whose buffers are kept between
// queries, so repeated queries (an audit every N steps) do not allocate once warm.
#pragma once

#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/distance/Distance_hierarchy.h"
#include "algorithms/pair/Feature.h"
#include "algorithms/pair/Pair_geometry.h"
#include "kernel/Body.h"
#include "kernel/Rigid_pose_3.h"
#include "kernel/Types.h"

namespace extremal {

struct Distance_request {
  // Certificate: stop when upper - lower <= max(absolute_tolerance, relative_tolerance * upper).
  // Tolerances below the floating-point resolution of the scene (about 1e-15 of the coordinates'
  // size) are raised to it.
  double absolute_tolerance = 1e-9;  // body units (mm for CAD files)
  double relative_tolerance = 1e-9;
  // Budget: live sub-patch nodes made in one query (memory grows with it, about 0.6 kB each)
  // and wall time in seconds (0 = no time limit). Exhausting either returns the best bounds so
  // far with status Budget_exhausted.
  int max_nodes = 200000;
  double max_seconds = 0.0;
  // Polish witness candidates with Newton's method (off: corner points only; the bounds stay
  // certified but converge slowly). For tests and benchmarks.
  bool newton_polish = true;
  // Only witnesses closer than this are sought: pairs whose bound cannot beat it are pruned
  // from the start, and when none does the result has no elements (element_a = -1) and
  // upper_bound = cutoff. Infinity: no cutoff. (Checking whether a primitive pair holds
  // anything closer than a tracked distance costs little when it does not.)
  double cutoff = HUGE_VAL;
  // Bounds about a centre or axis of symmetry two elements share (Symmetry.h): they close on
  // the continuum of minima of concentric and coaxial bodies. Off: the witness is the one the
  // other bounds lead to (Body_pair_options::global: see there).
  bool symmetry_bounds = true;
};

enum class Distance_status {
  Converged,         // upper - lower within the tolerance
  Intersecting,      // the bodies cross: distance 0, point_a = point_b is a common point
  Touching,          // a common point where the surfaces are tangent (or curves meet): distance 0
  Budget_exhausted,  // node or time budget spent: best bounds so far
  Resolution_limit,  // sub-patches reached floating-point size before the bounds met
};
const char* to_string(Distance_status s);

struct Distance_result {
  Distance_status status = Distance_status::Converged;
  double distance = 0.0;     // the witness distance (= upper_bound), 0 when the bodies meet
  double lower_bound = 0.0;  // certified: lower_bound <= true distance <= upper_bound
  double upper_bound = 0.0;
  Vec3 point_a = Vec3::Zero();  // witness on A, world
  Vec3 point_b = Vec3::Zero();  // witness on B, world
  // Unit normal from A to B: point_b - point_a = distance * normal. When the bodies meet:
  // A's outward normal at the common point if A is a surface there, else minus B's, else zero.
  // (Also apart at rounding distance, and closer than a millionth of the smaller body where a
  // surface normal agrees with d within 5 degrees, turned along d.)
  Vec3 normal = Vec3::Zero();
  Element_kind kind_a = Element_kind::Face, kind_b = Element_kind::Face;
  int element_a = -1, element_b = -1;  // index into Body::faces / Body::curves (0 for a point)
  int face_a = -1, face_b = -1;        // element index when the witness is on a face, else -1
  std::array<double, 2> params_a{{0.0, 0.0}}, params_b{{0.0, 0.0}};  // witness parameters
  // Work done: node pairs taken from the queue, sub-patch nodes made, Newton polishes run,
  // intersection solves tried.
  long pairs_processed = 0;
  long nodes_created = 0;
  int newton_runs = 0;
  int intersection_attempts = 0;
  double tolerance_used = 0.0;  // the effective max(absolute, relative * upper) at the end
  // Lower bound over the sub-patch pairs not set aside for a carried boundary (trim edges held
  // by curve elements, Distance_request::carried_sides): the minimum is at least
  // min(uncarried_lower_bound, the minimum on the carried boundaries). It may exceed
  // upper_bound (the witness lies where a set-aside pair holds it); infinity when every pair
  // was set aside or pruned without a bound.
  double uncarried_lower_bound = 0.0;
  // How far the other element's points may move, in the frame of the element whose gradient
  // set pairs aside ([0]: A's, B's points moving; [1]: B's, A's points moving), before that
  // gradient can vanish on one of them: until then their minima still lie on the carried
  // boundaries. Infinity when nothing was set aside.
  std::array<double, 2> carried_reach{{HUGE_VAL, HUGE_VAL}};

  bool is_certified() const { return status != Distance_status::Budget_exhausted &&
                                     status != Distance_status::Resolution_limit; }
};

namespace internal {
struct Distance_scratch;
}

// A sub-patch pair that a query set aside for a carried boundary (see
// Distance_request::carried_sides): over it, one component of the gradient of |f_A - f_B|^2
// along one element's parameters does not vanish. The gradient is (p_side - p_other) . d, so
// the proof is the two sub-patch boxes and an enclosure of d, all in the world frame of the
// query: a caller can re-check it after the bodies moved (move the other box rigidly, take the
// interval product again) rather than solve again, e.g. Body_pair_tracker.
struct Gradient_proof {
  int side = 0;  // 0: the derivative is along A's parameters (A's box is `own`), 1: along B's
  int component = 0;  // the parameter it is along
  Vec3 own_min = Vec3::Zero(), own_max = Vec3::Zero();      // box of the side's sub-patch
  Vec3 other_min = Vec3::Zero(), other_max = Vec3::Zero();  // box of the other side's
  Vec3 derivative_min = Vec3::Zero(), derivative_max = Vec3::Zero();  // the derivative's box
  // The two sub-patches' parameter boxes (a curve's second parameter: 0 to 0).
  std::array<double, 2> own_lo{{0, 0}}, own_hi{{0, 0}}, other_lo{{0, 0}}, other_hi{{0, 0}};
};
// Whether proof p still holds once the other side's points have moved by `motion` (a rigid map
// of the query's world frame, the proof's side held still). `length` bounds the translations
// `motion` was composed from (the rounding of that product). If it holds, `reach` is how much
// farther the other side's points may then move, in any direction, before it can fail.
bool gradient_proof_holds(const Gradient_proof& p, const Rigid_pose_3& motion, double length,
                          double& reach);

// A sub-patch pair a query bounded (pruned, settled, or left open when it stopped), with what
// re-bounding it after the bodies moved needs: its bound and both sub-patches' boxes and balls,
// in the world frame of the query. With the set-aside pairs (Gradient_proof) and the pieces
// outside the trims, they cover the two elements' parameter domains.
struct Bound_proof {
  double lower = 0.0;  // lower bound on the distance over the pair at the query's poses
  Vec3 a_min = Vec3::Zero(), a_max = Vec3::Zero(), b_min = Vec3::Zero(), b_max = Vec3::Zero();
  Vec3 a_centre = Vec3::Zero(), b_centre = Vec3::Zero();
  double a_radius = 0.0, b_radius = 0.0;  // balls about the centres that hold the sub-patches
  // A unit axis along which B's control net lies `gap` beyond A's (-infinity: none), whose
  // bound decays only by the motion along it.
  Vec3 axis = Vec3::Zero();
  double gap = -HUGE_VAL;
  // The sub-patches' ranges of distances to a centre or axis of symmetry (Symmetry.h; world at
  // the query) that moves with A (symmetry_side 0) or with B (1); -1: none. Where the motion
  // turns B about the axis (a shaft spinning in its bore) this bound does not decay at all.
  int symmetry_side = -1;
  Symmetry symmetry;
  std::array<double, 2> a_range{{0, 0}}, b_range{{0, 0}};
  // The sub-patches' parameter boxes (a curve's second parameter: 0 to 0; a group of the
  // hierarchy above the elements: element -1).
  int a_element = -1, b_element = -1;
  std::array<double, 2> a_lo{{0, 0}}, a_hi{{0, 0}}, b_lo{{0, 0}}, b_hi{{0, 0}};
};
// A lower bound on the distance over proof p's pair once B's points have moved by `motion` (a
// rigid map of the query's world frame, A held still); `length` as for gradient_proof_holds.
double bound_after_motion(const Bound_proof& p, const Rigid_pose_3& motion, double length);

// Buffers of the branch and bound, kept between queries (one per thread).
class Distance_workspace {
 public:
  Distance_workspace();
  ~Distance_workspace();
  Distance_workspace(Distance_workspace&&) noexcept;
  Distance_workspace& operator=(Distance_workspace&&) noexcept;
  internal::Distance_scratch& scratch() { return *m_scratch; }
  const internal::Distance_scratch& scratch() const { return *m_scratch; }
  // With Distance_request::keep_proofs: the pairs the last query set aside, and the pairs it
  // bounded.
  const std::vector<Gradient_proof>& gradient_proofs() const;
  const std::vector<Bound_proof>& bound_proofs() const;

 private:
  std::unique_ptr<internal::Distance_scratch> m_scratch;
};

// The certified global distance between A placed by X_WA and B placed by X_WB. Throws
// Precondition_violation on a non-positive tolerance or budget; numerical trouble is a status.
[[nodiscard]] Distance_result extremal_distance(const Distance_hierarchy& A,
                                                const Rigid_pose_3& X_WA,
                                                const Distance_hierarchy& B,
                                                const Rigid_pose_3& X_WB,
                                                const Distance_request& request,
                                                Distance_workspace& workspace);
// One-shot conveniences (build a workspace, or the hierarchies too).
[[nodiscard]] Distance_result extremal_distance(const Distance_hierarchy& A,
                                                const Rigid_pose_3& X_WA,
                                                const Distance_hierarchy& B,
                                                const Rigid_pose_3& X_WB,
                                                const Distance_request& request = {});
[[nodiscard]] Distance_result extremal_distance(const Body& A, const Rigid_pose_3& X_WA,
                                                const Body& B, const Rigid_pose_3& X_WB,
                                                const Distance_request& request = {});

// The certified distance between one element of A and one element of B (element ids as in
// Distance_hierarchy::elements(), e.g. from element_of): the same branch and bound started from
// the pairs of those elements' pieces only, so its cost follows the two elements, not the
// bodies. A tracker for a new candidate face pair starts from it.
[[nodiscard]] Distance_result extremal_distance_between(const Distance_hierarchy& A,
                                                        const Rigid_pose_3& X_WA, int element_a,
                                                        const Distance_hierarchy& B,
                                                        const Rigid_pose_3& X_WB, int element_b,
                                                        const Distance_request& request,
                                                        Distance_workspace& workspace);

// ---- Starting and auditing trackers --------------------------------------------------------

// What an Extremal_tracker needs to start on the global pair: the two features (referring to
// the geometry of the Body objects passed in, which must outlive them) and the parameters
// [A's..., B's...].
struct Tracker_seed {
  Feature feature_a = Feature::point(Vec3::Zero());
  Feature feature_b = Feature::point(Vec3::Zero());
  Vec4 params = Vec4::Zero();
  Element_kind kind_a = Element_kind::Point, kind_b = Element_kind::Point;
  int element_a = -1, element_b = -1;
};
// Throws Precondition_violation if `result` does not refer to elements of A and B.
Tracker_seed tracker_seed(const Body& A, const Body& B, const Distance_result& result);

// Audit of a tracked pair against a global result at the same poses: re-seed when the global
// minimum is on another element pair and beats the tracked distance by more than the global
// certificate's tolerance (`margin` more, to avoid flip-flopping between near-equal minima).
struct Audit_decision {
  bool reseed = false;
  bool same_elements = false;
  double improvement = 0.0;  // tracked_distance - global upper bound
};
Audit_decision audit_tracked_pair(const Distance_result& global, double tracked_distance,
                                  Element_kind kind_a, int element_a, Element_kind kind_b,
                                  int element_b, double margin = 0.0);

}  // namespace extremal
