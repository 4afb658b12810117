// Signed extremal distance between two posed bodies with a certificate: the certified distance
// while they are apart, and a certified penetration depth while they overlap
// (docs/design.md: positive apart, 0 at contact, negative inside).
//
// Definition.
//   - Bodies whose surfaces do not meet and neither of which lies inside the other: s is the
//     certified minimum distance of extremal_distance (Global_distance.h), positive.
//   - Overlapping bodies (their surfaces meet, or one lies inside the other, closed, body):
//         s = -min over unit n of overlap(n),   overlap(n) = h_A(n) + h_B(-n),
//     with h_X(n) = max over x in X of n.x the support function. The minimising n and the
//     support points p of A along n and q of B along -n are an extremal pair: at a smooth
//     minimum p - q = overlap * n, the outward normal of A at p is +n and that of B at q is -n
//     (the pair a tracker follows through penetration). point_b - point_a = s * normal holds
//     there, and where a support set is flat (a plane face, a cylinder's generator) the
//     witness on it is taken across from the other one when the face reaches there; in
//     general (support points on edges or vertices) n.(point_b - point_a) = s.
//   - For two convex bodies -s is the minimum translation distance (the shortest translation
//     of B that separates them). For non-convex bodies it is the penetration depth of their
//     convex hulls, an upper bound on the minimum translation distance, and it jumps where the
//     bodies start to overlap (a ball that touches the inside of a U-shaped part's cavity goes
//     from 0 to minus the depth of the part's hull). `depth_is_translation_distance` says which
//     one holds: it is set only when both bodies are certified convex (a point, or a single
//     untrimmed sphere or ellipsoid face).
//   - A point inside a closed body: s = minus its certified distance to the body's surface,
//     the minimum translation distance (depth_is_translation_distance), whatever the body's
//     shape; the witnesses and bounds are that distance's.
//   - A ball (certified_ball) overlapping a closed body that is not certified convex: its
//     centre's signed distance (as a point's) less its radius; the ball's witness is the
//     centre moved along the normal by the radius. Not a translation distance in general.
//   - Bodies with no inside to be deep in, whose surfaces meet: a point on any body, or a
//     curve, a point or an open mesh meeting a body that is not closed: the distance, 0
//     (status Touching); these pairs are never negative (docs/behaviour.md, "Overlap").
//
// Certificate of the depth. For any unit n, certified upper bounds on h come from the control
// points of the Bezier pieces (a rational piece with positive weights lies in the convex hull
// of its Cartesian control points): the max of n.P over a piece's control net bounds the
// piece, and a best-first search over halved sub-nets (support_bound) closes the gap to a real
// surface point (net corners lie on the surface; the best is polished by Newton's method). So
// overlap_up(n) >= overlap(n) >= min overlap. Real surface points p on A and q on B give, for
// every n, overlap(n) >= n.(p - q); over a cone of directions of axis c and half-angle a,
//     min overlap over the cone >= |p - q| cos(angle(c, p - q) + a),
// which is second order in a when p - q is (nearly) parallel to the optimum; more generally
// every point y of conv{p_i - q_i} (inside conv(A - B), whose support function is overlap)
// gives |y| cos(angle(c, y) + a), maximised over y by Frank-Wolfe iterations, which keeps the
// bound second order at kinks of overlap (a hull edge or face: the support points jump, and a
// combination of the differences on both sides is parallel to the optimum). A best-first
// branch and bound over cells of the direction sphere (the 6 faces of a cube, turned by a
// fixed generic rotation so that kinks along coordinate planes do not run along cell
// boundaries, subdivided in quadtrees) with these bounds gives
//     lower_bound = -min overlap_up <= s <= upper_bound = -(smallest cell lower bound).
// Before it, the best sampled direction is polished: Newton's method on the sphere (gradient of
// overlap: the tangential part of p - q; Hessian by differences of gradients) for smooth
// minima, then an expanding polytope (as EPA: the face of conv(differences) nearest the origin
// gives the next direction) for kinks, and the differences on either side of the result are
// kept for every cell's bound. It stops at the tolerance (status Penetrating), or when the cell
// or time budget is spent (Budget_exhausted) or the cells reach floating-point size
// (Resolution_limit), with the bounds so far. A continuum of minimising directions (concentric
// balls) exhausts the budget. Trimmed CAD faces: a piece covers its whole patch, so its net
// bounds the trimmed face conservatively; sub-nets wholly outside the trim are dropped, and so
// are sub-nets on which the gradient of n.f provably does not vanish (a maximiser there would
// lie on a trim boundary, which a B-rep edge curve element carries), and real points count
// only inside the trim (with its On_boundary band).
//
// Containment (one body inside the other while their surfaces are apart). A body contains
// something only when it is closed (body_closedness: every B-rep edge shared by two faces;
// without a B-rep, every side of every patch wraps, collapses to a pole or lies on another
// patch's side; a mesh whose every edge has two triangles; never a point, curves or an open
// surface). For a closed body, a point x at a known clearance from its surface is inside when
// the winding number of the surface about x, (1/4 pi) * integral of (f - x).n / |f - x|^3, is
// 1 (or -1 for an inward-oriented mesh): an adaptive Gauss quadrature over halved sub-patches
// whose size stays below half their distance to x, so its error is far below the 1/2 that
// rounding needs; a value not within 0.25 of an integer is reported, not guessed. One point
// of each face (up to 32 faces spread over the body), each curve and the point body is
// tested: every connected part of a surface that does not meet the other body lies wholly
// inside or outside it.
#pragma once

#include <cmath>
#include <string>

#include "algorithms/distance/Global_distance.h"
#include "algorithms/distance/Solid_classification.h"
#include "kernel/Body.h"
#include "kernel/Rigid_pose_3.h"
#include "kernel/Types.h"

namespace extremal {

// ---- Support function ------------------------------------------------------------------------

struct Support_request {
  double tolerance = 1e-12;  // absolute: stop when upper - lower <= tolerance
  int max_nets = 200000;     // sub-nets made; beyond it the bounds so far are returned
  bool newton_polish = true;  // polish the best real point by local maximisation of n.x
};

struct Support_bound {
  double lower = -HUGE_VAL;  // n.point: point is a real point of the body (inside its trims)
  double upper = HUGE_VAL;   // certified: h(n) <= upper
  Vec3 point = Vec3::Zero();  // world
  Element_kind kind = Element_kind::Face;
  int element = -1;  // hierarchy element (Distance_hierarchy::elements()), -1 if none found
  std::array<double, 2> params{{0.0, 0.0}};
  int nets = 0;  // sub-nets made
  bool converged = false;  // upper - lower within the tolerance
};

// Bounds on the support function h(n) = max over the placed body of n.x, n a unit world vector.
[[nodiscard]] Support_bound support_bound(const Distance_hierarchy& H, const Rigid_pose_3& X_W,
                                          const Vec3& n_W, const Support_request& request = {});

// ---- Signed distance --------------------------------------------------------------------------

struct Signed_distance_request {
  // Stop when upper - lower <= max(absolute_tolerance, relative_tolerance * |s|).
  double absolute_tolerance = 1e-9;
  double relative_tolerance = 1e-9;
  int max_cells = 200000;    // direction cells evaluated
  double max_seconds = 0.0;  // 0: no time limit (the apart query has its own in `apart`)
  // The whole query's wall time (apart query, containment test, depth search), 0: no limit.
  // The apart query and the depth search each get what is left of it, within their own limits.
  double total_seconds = 0.0;
  // The query that decides whether the bodies are apart (and gives s when they are); its
  // tolerances are set from the ones above.
  Distance_request apart;
};

enum class Signed_distance_status {
  Converged,            // apart: the certified distance (as Distance_status::Converged)
  Touching,             // surfaces meet tangentially and the depth is within the tolerance of 0
  Penetrating,          // overlapping: the depth within the tolerance
  Budget_exhausted,     // cell, node or time budget spent: the bounds so far
  Resolution_limit,     // cells or sub-patches reached floating-point size first
  Containment_unknown,  // apart, but whether one lies inside the other could not be decided
};
const char* to_string(Signed_distance_status s);

enum class Overlap_kind { None, Surfaces_meet, A_inside_B, B_inside_A };
const char* to_string(Overlap_kind k);

struct Signed_distance_result {
  Signed_distance_status status = Signed_distance_status::Converged;
  Overlap_kind overlap = Overlap_kind::None;
  double distance = 0.0;  // s, within the tolerance of the truth
  double lower_bound = 0.0, upper_bound = 0.0;  // certified: lower <= s <= upper
  // Witnesses (world): apart, the closest pair; overlapping, the support points p of A along
  // `normal` and q of B along -normal. normal: unit, from A to B (B moved by -s along it
  // separates the hulls).
  Vec3 point_a = Vec3::Zero(), point_b = Vec3::Zero(), normal = Vec3::Zero();
  Element_kind kind_a = Element_kind::Face, kind_b = Element_kind::Face;
  int element_a = -1, element_b = -1;  // index into Body::faces / Body::curves (0: point)
  int face_a = -1, face_b = -1;        // element index when on a face, else -1
  std::array<double, 2> params_a{{0.0, 0.0}}, params_b{{0.0, 0.0}};
  // Overlapping only: whether -s is the minimum translation distance (both bodies certified
  // convex) or the convex hulls' depth (an upper bound on it).
  bool depth_is_translation_distance = false;
  Closedness closed_a, closed_b;
  Distance_result apart;  // the certified distance query that ran first
  // Work: direction cells evaluated, support evaluations, quadrature cells.
  long cells = 0, supports = 0, winding_cells = 0;
  double tolerance_used = 0.0;

  bool is_certified() const {
    return status == Signed_distance_status::Converged ||
           status == Signed_distance_status::Touching ||
           status == Signed_distance_status::Penetrating;
  }
};

// The signed distance between A placed by X_WA and B placed by X_WB (HA, HB: their prepared
// hierarchies). Throws Precondition_violation on a non-positive tolerance or budget.
[[nodiscard]] Signed_distance_result signed_distance(const Body& A, const Distance_hierarchy& HA,
                                                     const Rigid_pose_3& X_WA, const Body& B,
                                                     const Distance_hierarchy& HB,
                                                     const Rigid_pose_3& X_WB,
                                                     const Signed_distance_request& request = {});
[[nodiscard]] Signed_distance_result signed_distance(const Body& A, const Rigid_pose_3& X_WA,
                                                     const Body& B, const Rigid_pose_3& X_WB,
                                                     const Signed_distance_request& request = {});

// The penetration-depth part alone: -min over n of overlap(n) with its bounds, whatever the
// bodies' relation (for separated bodies it is the distance between their convex hulls).
// Fills distance, bounds, witnesses, status (Penetrating, Budget_exhausted, Resolution_limit)
// and the work counts.
[[nodiscard]] Signed_distance_result hull_signed_distance(const Distance_hierarchy& HA,
                                                          const Rigid_pose_3& X_WA,
                                                          const Distance_hierarchy& HB,
                                                          const Rigid_pose_3& X_WB,
                                                          const Signed_distance_request& request = {});

// The depth along one direction: s(n) = -overlap(n) = -(h_A(n) + h_B(-n)) for the unit world
// n (from A to B; normalised here), at most the hulls' depth (hull_signed_distance), equal to
// it where n minimises overlap. Bounds from the two support searches (lower_bound <= s(n) <=
// upper_bound, within the request's tolerance, status Penetrating; Budget_exhausted when a
// search ran out), witnesses as hull_signed_distance gives them (a flat support face's across
// from the other witness). The depth of the side a solid entered an open sheet by: n the
// sheet's normal on that side (keep_entry_side in algorithms/body_pair).
[[nodiscard]] Signed_distance_result directional_signed_distance(
    const Distance_hierarchy& HA, const Rigid_pose_3& X_WA, const Distance_hierarchy& HB,
    const Rigid_pose_3& X_WB, const Vec3& n_W, const Signed_distance_request& request = {});

// Whether two bodies overlap, given the certified apart query `apart` between them: their
// surfaces meet, or (surfaces apart) a sample point of one lies inside the other, closed, body
// by its winding number (see "Containment" above). `unknown`: some winding number was not
// decided (kind stays None for it).
struct Overlap_test {
  Overlap_kind kind = Overlap_kind::None;
  bool unknown = false;
  long winding_cells = 0;
};
[[nodiscard]] Overlap_test overlap_of(const Distance_result& apart, const Distance_hierarchy& HA,
                                      const Rigid_pose_3& X_WA, bool closed_a,
                                      const Distance_hierarchy& HB, const Rigid_pose_3& X_WB,
                                      bool closed_b);

// Whether the world point x lies inside the closed body of H placed by X_W, certified: its
// distance from the surface bounded away from 0 and the winding number decided. False when
// outside, on the surface or undecided; the caller checks that the body is closed.
// Within `surface_tolerance` of the surface (certified), x is on it: false, and `on_surface`
// (if given) is set (the winding number there would need cells as small as the distance).
[[nodiscard]] bool inside_body(const Distance_hierarchy& H, const Rigid_pose_3& X_W, const Vec3& x_W,
                               double surface_tolerance = 0.0, bool* on_surface = nullptr);

// A lower bound on the signed distance of two bodies inside these world boxes: their distance
// when apart, else minus the smallest overlap along a coordinate axis (overlap(n) of the hulls
// is at most that of the boxes along it, so the depth is at most it).
[[nodiscard]] double signed_box_bound(const Bbox_3& a, const Bbox_3& b);

}  // namespace extremal
