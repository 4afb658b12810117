#include "algorithms/body_pair/internal/Reading_rules.h"

#include <algorithm>
#include <cmath>

#include "algorithms/body_pair/internal/Body_pair_support.h"
#include "algorithms/body_pair/internal/Tuning.h"

namespace extremal::internal {

namespace {

// Whether a surface primitive's parameters q lie on its trim's boundary band (a B-rep edge).
bool on_trim_boundary(const Primitive& P, const double* q) {
  return P.is_surface() && P.trim != nullptr &&
         P.trim->locate(q[0], q[1]) == Trim_location::On_boundary;
}

// An edge of a face that a witness sits on: its direction and one leaving the face across it
// (tangent vectors at the witness); `chord`: a trim's, read off its flattened polyline.
struct Face_edge {
  Vec3 along, leaving;
  bool chord = false;
};

// The edges of surface primitive P at q: the patch edges its parameters are held on (bits of
// `held`), then its trim's boundary. Evaluates P there into f (first derivatives) only when it
// finds one. Returns how many.
int face_edges_at(const Primitive& P, const Rigid_pose_3& X, const double* q, unsigned held,
                  Feature_point& f, Face_edge out[3]) {
  double along[2], leaving[2];
  const bool on_trim = P.trim != nullptr && P.trim->boundary_directions(q[0], q[1], along, leaving);
  if (!held && !on_trim) return 0;
  evaluate_feature(P.feature, X, q, f, 1);
  int n = 0;
  for (int k = 0; k < 2; ++k) {
    if (!(held & (1u << k))) continue;
    const bool upper = P.feature.upper(k) - q[k] < q[k] - P.feature.lower(k);
    out[n++] = {f.d[1 - k], upper ? f.d[k] : Vec3(-f.d[k]), false};
  }
  if (on_trim)
    out[n++] = {along[0] * f.d[0] + along[1] * f.d[1], leaving[0] * f.d[0] + leaving[1] * f.d[1], true};
  return n;
}

// Whether `n_other` (the other body's outward normal at its witness) points across an edge
// of P's face at q (face_edges_at). A solid's outward normals at a convex edge all lie on the
// side the face leaves by (the face's and its neighbour's), and a penetration pair's normals
// oppose: -n_other must be among them. A point of one surface crossing the other body's edge,
// outside it, and the edge point inside the first body are no depth: a peg 4 deep in a box's
// top, slid past its side, read the box's top edge against the peg's side, 4.6 growing to 9.4
// (normals perpendicular, so the face-normal test keeps it).
bool normal_across_edge(const Primitive& P, const Rigid_pose_3& X, const double* q, unsigned held,
                        const Vec3& n_other) {
  if (!P.is_surface()) return false;
  Feature_point f;
  Face_edge edges[3];
  const int count = face_edges_at(P, X, q, held, f, edges);
  if (count == 0) return false;
  const Vec3 n = P.feature.outward_sign() * f.d[0].cross(f.d[1]);
  if (!(n.norm() * n_other.norm() > 0.0)) return false;
  // Past the margin only: a pair beside an edge, its normals opposed, is a depth to rounding.
  for (int i = 0; i < count; ++i) {
    Vec3 side = n.cross(edges[i].along);
    if (side.dot(edges[i].leaving) < 0.0) side = -side;
    const double len = side.norm();
    if (len > 0.0 && n_other.dot(side) > k_wandering_error * len * n_other.norm()) return true;
  }
  return false;
}

// Whether direction v lies outside the wedge of outward normals at parameter t of B-rep edge
// primitive e (between its two faces' normals, where they differ): a penetration pair's
// direction from the edge, minus the other surface's normal, lies among them. A peg's side
// past a box's top edge, outside the box, read against that edge as 2.8 deep (its normal
// along the side face's, which the edge's top face is perpendicular to).
bool outside_edge_wedge(const Tracking_model& M, int e, const Rigid_pose_3& X, double t,
                        const Vec3& v) {
  int count = 0;
  const Edge_on_face* faces = M.faces_of(e, count);
  if (count != 2) return false;
  Vec3 n[2];
  for (int i = 0; i < 2; ++i) {
    const Primitive& F = M.primitives()[faces[i].face];
    if (!F.is_surface()) return false;
    double q[2];
    faces[i].map(t, q);
    for (int c = 0; c < 2; ++c)  // (a trim curve may leave the patch by rounding)
      q[c] = std::clamp(q[c], F.feature.lower(c), F.feature.upper(c));
    Feature_point f;
    evaluate_feature(F.feature, X, q, f, 1);
    n[i] = F.feature.outward_sign() * f.d[0].cross(f.d[1]);
    const double len = n[i].norm();
    if (!(len > 0.0)) return false;
    n[i] /= len;
  }
  const double c = n[0].dot(n[1]), det = 1.0 - c * c;
  const double len = v.norm();
  if (!(det > k_smooth_join) || !(len > 0.0)) return false;  // a smooth join: one normal
  // v's coordinates along the two normals (least squares in their plane).
  const double a = v.dot(n[0]) / len, b = v.dot(n[1]) / len;
  const double alpha = (a - c * b) / det, beta = (b - c * a) / det;
  return alpha < -k_wandering_error || beta < -k_wandering_error;
}

// At d = 0, whether a witness on an edge (a curve, a patch edge it is held on, its face's trim
// boundary) crosses the other side's surface rather than touching it: the edge's tangent not
// in the surface's tangent plane. A box's top edge through a peg's side read 0 'contact' with
// the peg 4 deep in the box, and so did a tilted peg's rim through the box's side.
bool edge_crosses_surface(const Primitive& A, const Rigid_pose_3& XA, const Primitive& B,
                          const Rigid_pose_3& XB, const double* q, unsigned on_edge) {
  const int na = A.feature.dimension();
  const double* qs[2] = {q, q + na};
  const Primitive* P[2] = {&A, &B};
  const Rigid_pose_3* X[2] = {&XA, &XB};
  const unsigned held[2] = {on_edge & ((1u << na) - 1u), on_edge >> na};
  Vec3 tangent[2];
  bool on[2] = {false, false}, chord[2] = {false, false};
  Feature_point f[2];
  for (int s = 0; s < 2; ++s) {
    Face_edge edges[3];
    const int count =
        P[s]->is_surface() ? face_edges_at(*P[s], *X[s], qs[s], held[s], f[s], edges) : 0;
    if (count == 0) evaluate_feature(P[s]->feature, *X[s], qs[s], f[s], 1);
    if (P[s]->feature.dimension() == 1) {
      tangent[s] = f[s].d[0];
      on[s] = true;
    } else if (count > 0 && held[s] != 3u) {
      // One edge (a corner, two held parameters, is a point): the held one, or the trim's.
      tangent[s] = edges[0].along;
      on[s] = true;
      chord[s] = edges[0].chord;
    }
  }
  if (on[0] == on[1]) return false;  // edge on edge (or neither): a point contact
  const int e = on[0] ? 0 : 1;
  if (!P[1 - e]->is_surface()) return false;
  const Vec3 n = f[1 - e].d[0].cross(f[1 - e].d[1]);
  // A trim's tangent is its flattened polyline's chord, a degree or two off the curve (as1's
  // bolt shank in the plate's hole, its rim's chord 1.1 degrees off): a crossing is read there
  // only past a tenth.
  const double limit = chord[e] ? k_trim_chord_crossing : k_wandering_error;
  return std::abs(tangent[e].dot(n)) > limit * tangent[e].norm() * n.norm();
}


// The side (0 A, 1 B) whose outward normal gives a tracker's reading its sign, as
// Extremal_tracker::signed_distance takes it: a surface side not held on a patch edge, B's
// first with sign_from_b; -1: neither (the reading is |d|).
int sign_side(const Primitive& A, const Primitive& B, unsigned on_edge, bool sign_from_b) {
  const int na = A.feature.dimension();
  const bool b_free = B.is_surface() && !((on_edge >> na) & 3u);
  if (sign_from_b && b_free) return 1;
  if (A.is_surface() && !(on_edge & 3u)) return 0;
  return b_free ? 1 : -1;
}

// ---- The rules -------------------------------------------------------------------------------
// Each states what a reading that holds satisfies; docs/behaviour.md names the situations and
// tests (tests/test_reading_rules.cpp applies each to a synthetic reading).

double contact_tolerance(const Reading& r) { return r.context.options.contact_tolerance; }
bool inside(const Reading& r) { return is_inside(r.slot.regime); }
const double* params_of(const Reading& r) { return r.slot.result.params.data(); }

// A witness on a face lies inside its trim (or triangle): a point of the patch beyond the trim
// is not on the body.
bool witness_off_face(const Reading& r) {
  const Tracking_model& MA = *r.context.model_a;
  const Tracking_model& MB = *r.context.model_b;
  const double* q = params_of(r);
  return (r.a.is_surface() && !MA.contains(r.slot.pa, q)) ||
         (r.b.is_surface() && !MB.contains(r.slot.pb, q + r.a.feature.dimension()));
}

// A normal-form reading whose normals are not yet parallel holds only where the contact form's
// conditions do: apart from d = 0, d along the reference normal and the other witness its foot;
// at d = 0 (no direction), a singular system at an edge, a trim boundary or a curve that lies in
// the other surface's tangent plane. (Seeded where surfaces cross, the normal form's residual
// has a local minimum that is no solution.)
bool normal_form_unsolved(const Reading& r) {
  const Track_result& t = r.slot.result;
  if (!(t.normal_form && t.alignment_error > k_wandering_error)) return false;
  const Pair_context& c = r.context;
  const double* q = params_of(r);
  const bool holds =
      r.slot.regime != Regime::Contact_band
          ? t.reference_error <= k_wandering_error && t.other_error <= k_wandering_error
          : t.degeneracy != Degeneracy::None && t.degeneracy != Degeneracy::Pole &&
                (t.on_edge != 0u || !r.a.is_surface() || !r.b.is_surface() ||
                 on_trim_boundary(r.a, q) || on_trim_boundary(r.b, q + 2)) &&
                !edge_crosses_surface(r.a, *c.now.X_WA, r.b, *c.now.X_WB, q, t.on_edge);
  return !holds;
}

// Inside, past the normal form's band, a reading holds only once the flow has converged on a
// penetration pair (Newton's basin about one can be small).
bool wandering_inside(const Reading& r) {
  return inside(r) && !r.slot.result.normal_form &&
         !is_converged_along_free(r.context, r.slot, k_wandering_error);
}

// The outward normal of a solid's face at parameters q (at a pole, its limit); false where it
// is not defined (below a relative size, Tuning.h).
bool outward(const Primitive& P, const Rigid_pose_3& X, const double* q, Vec3& n) {
  Feature_point f;
  const bool pole = P.feature.collapsed_edges() != 0u;
  evaluate_feature(P.feature, X, q, f, pole ? 2 : 1);
  const Vec3 cross = P.feature.outward_sign() * f.d[0].cross(f.d[1]);
  n = pole ? outward_direction(P.feature, f, q, cross) : cross;
  // (The limit's factors at a pole: the mixed derivative and the tangent that remains.)
  const double scale = f.d[0].norm() * f.d[1].norm() +
                       f.dd[0][1].norm() * std::max(f.d[0].norm(), f.d[1].norm());
  return n.norm() > k_normal_defined * scale;
}

// Two solids' faces, both witnesses interior points of them.
bool solid_faces(const Reading& r) {
  return r.a.is_surface() && r.b.is_surface() && r.context.kind.both_closed();
}

// Two solids whose faces' interior points touch (in the contact band or just apart) have their
// outward normals opposed; alike, one body touches the other from within.
bool normals_alike_in_contact(const Reading& r) {
  if (!solid_faces(r)) return false;
  const Track_result& t = r.slot.result;
  const double* q = params_of(r);
  const double d = t.distance, tol = contact_tolerance(r);
  const bool near = d >= -tol && d <= k_near_contact * tol && t.on_edge == 0u &&
                    !on_trim_boundary(r.a, q) && !on_trim_boundary(r.b, q + 2);
  Vec3 na, nb;
  return near && outward(r.a, *r.context.now.X_WA, q, na) && outward(r.b, *r.context.now.X_WB, q + 2, nb) &&
         na.dot(nb) > k_normals_alike * na.norm() * nb.norm();
}

// Two solids' penetration pair has its outward normals opposed, and neither points across an
// edge of the other's face at its witness.
bool depth_normals_not_opposed(const Reading& r) {
  if (!solid_faces(r) || !inside(r)) return false;
  const Track_result& t = r.slot.result;
  const double* q = params_of(r);
  Vec3 na, nb;
  return outward(r.b, *r.context.now.X_WB, q + 2, nb) && outward(r.a, *r.context.now.X_WA, q, na) &&
         (na.dot(nb) > k_normals_opposed * na.norm() * nb.norm() ||
          normal_across_edge(r.a, *r.context.now.X_WA, q, t.on_edge & 3u, nb) ||
          normal_across_edge(r.b, *r.context.now.X_WB, q + 2, t.on_edge >> 2, na));
}

// Two solids apart: d goes against B's outward normal at its witness (along it, A's witness
// lies inside B: the bodies are nested, not apart).
bool apart_witness_inside(const Reading& r) {
  if (!solid_faces(r) || r.slot.regime != Regime::Apart) return false;
  const Track_result& t = r.slot.result;
  Vec3 nb;
  if (!outward(r.b, *r.context.now.X_WB, params_of(r) + 2, nb)) return false;
  const Vec3 gap = t.point_b - t.point_a;
  return nb.dot(gap) > k_normals_opposed * nb.norm() * gap.norm();
}

// Two solids are no deeper than their boxes overlap along either frame's axes (a translation
// that parts the boxes parts them).
bool deeper_than_boxes(const Reading& r) {
  return inside(r) && r.context.kind.both_closed() &&
         r.slot.result.distance < -r.context.boxes_bound();
}

// A B-rep edge of a solid against the other solid's face, inside: minus the face's normal lies
// in the wedge of the edge's two faces' outward normals.
bool edge_outside_wedge(const Reading& r) {
  const Pair_context& c = r.context;
  if (!inside(r) || !c.kind.both_closed()) return false;
  const bool edge_a = r.a.kind == Primitive_kind::Edge && r.b.is_surface();
  const bool edge_b = r.b.kind == Primitive_kind::Edge && r.a.is_surface();
  if (!edge_a && !edge_b) return false;
  const Primitive& S = edge_a ? r.b : r.a;
  const double* q = params_of(r);
  Feature_point f;
  evaluate_feature(S.feature, edge_a ? *c.now.X_WB : *c.now.X_WA, edge_a ? q + 1 : q, f, 1);
  const Vec3 n = S.feature.outward_sign() * f.d[0].cross(f.d[1]);
  return outside_edge_wedge(c.model(edge_a ? 0 : 1), edge_a ? r.slot.pa : r.slot.pb,
                            edge_a ? *c.now.X_WA : *c.now.X_WB, edge_a ? q[0] : q[2], -n);
}

// A depth counts only for a pair that went inside through contact (a face turned away from the
// other body also reads d against its outward normal with the bodies apart).
bool depth_not_reached_through_contact(const Reading& r) {
  return inside(r) && r.slot.provenance != Provenance::Through_contact;
}

}  // namespace

const std::array<Rule_entry, 9> k_reading_rules = {{
    {Reading_rule::Witness_off_face, witness_off_face},
    {Reading_rule::Normal_form_unsolved, normal_form_unsolved},
    {Reading_rule::Wandering_inside, wandering_inside},
    {Reading_rule::Normals_alike_in_contact, normals_alike_in_contact},
    {Reading_rule::Depth_normals_not_opposed, depth_normals_not_opposed},
    {Reading_rule::Apart_witness_inside, apart_witness_inside},
    {Reading_rule::Deeper_than_boxes, deeper_than_boxes},
    {Reading_rule::Edge_outside_wedge, edge_outside_wedge},
    {Reading_rule::Depth_not_reached_through_contact, depth_not_reached_through_contact},
}};

namespace {
// The rules that run before the reading's passage through contact is recorded, and the last.
constexpr std::size_t k_before_contact_rules = 2;
constexpr std::size_t k_last_rule = 8;
}  // namespace

void judge(Live& L, bool first, Pair_context& context) {
  const Primitive& A = context.primitive(0, L.pa);
  const Primitive& B = context.primitive(1, L.pb);
  const Reading reading{L, A, B, context};
  // Behind an open sheet: a tracker seeded apart whose first reading is inside (the sheet's
  // normal points away from the other body) did not come through contact, and stays so until
  // it reads the pair in front (test Contact.AnEllipsoidUnderAPlaneIsApart). Where its sign is
  // an open body's normal, which has no inside, the pair is apart and reads its distance,
  // positive (tests Contact.TwoOpenSheetsPassedThroughEachOtherAreApartOnceOut,
  // ProbeScenes.ASolidThroughASheetAndOutPastItsBorderIsApart).
  Provenance& p = L.provenance;
  if (L.result.distance > 0.0 && p == Provenance::Behind_sheet)
    p = Provenance::Unreached;
  else if (first && p == Provenance::Seeded_apart && is_inside(L.regime) &&
           !context.kind.both_closed())
    p = Provenance::Behind_sheet;
  if (p == Provenance::Seeded_apart) p = Provenance::Unreached;  // (read now)
  const int signed_by = sign_side(A, B, L.result.on_edge, context.options.tracker.sign_from_b);
  if (p == Provenance::Behind_sheet && L.result.distance < 0.0 && signed_by >= 0 &&
      !context.kind.closed(signed_by)) {
    L.result.distance = -L.result.distance;
    L.result.normal = -L.result.normal;
    L.regime = Regime::Apart;
  }
  const double d = L.result.distance;
  Reading_rule rejected = Reading_rule::None;
  std::size_t next = 0;
  for (; next < k_before_contact_rules && rejected == Reading_rule::None; ++next)
    if (k_reading_rules[next].rejects(reading)) rejected = k_reading_rules[next].rule;
  // Through contact: a normal-form reading that holds, in front of any sheet; apart, no longer.
  if (L.result.normal_form && p != Provenance::Behind_sheet && rejected == Reading_rule::None)
    p = Provenance::Through_contact;
  else if (d > 0.0 && p == Provenance::Through_contact)
    p = Provenance::Unreached;
  for (next = k_before_contact_rules; next < k_last_rule && rejected == Reading_rule::None; ++next)
    if (k_reading_rules[next].rejects(reading)) rejected = k_reading_rules[next].rule;
  // Would hold but for not having come through contact: rejected by the last rule alone
  // (holds_unreached, read by the depth monitor).
  if (rejected == Reading_rule::None && k_reading_rules[k_last_rule].rejects(reading))
    rejected = k_reading_rules[k_last_rule].rule;
  L.rejected_by = rejected;
  L.valid = rejected == Reading_rule::None;
}

bool rule_rejects(Reading_rule r, const Live& L, Pair_context& context) {
  const Reading reading{L, context.primitive(0, L.pa), context.primitive(1, L.pb), context};
  for (const Rule_entry& e : k_reading_rules)
    if (e.rule == r) return e.rejects(reading);
  return false;
}

}  // namespace extremal::internal
