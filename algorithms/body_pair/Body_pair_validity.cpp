// Which tracker readings hold a pair of the bodies (Body_pair_tracker::judge): the witnesses on
// the faces, a depth reached through contact, the contact form's conditions, the normals'
// opposition between solids (at faces, edges and poles), and the boxes' bound on a depth.
#include "algorithms/body_pair/Body_pair_tracker.h"

#include <algorithm>
#include <cmath>

#include "algorithms/body_pair/internal/Body_pair_support.h"
#include "algorithms/distance/internal/Restricted_solve.h"

namespace extremal {

using internal::k_wandering_error;

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
  if (!(det > 1e-6) || !(len > 0.0)) return false;  // a smooth join: one normal
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
  const double limit = chord[e] ? 0.1 : k_wandering_error;
  return std::abs(tangent[e].dot(n)) > limit * tangent[e].norm() * n.norm();
}

}  // namespace

void Body_pair_tracker::judge(int k, bool first) {
  Live& L = m_live[k];
  const Tracking_model& MA = *m_model_a;
  const Tracking_model& MB = *m_model_b;
  const Primitive& A = MA.primitives()[L.pa];
  const Primitive& B = MB.primitives()[L.pb];
  const int na = A.feature.dimension();
  L.valid = (!A.is_surface() || MA.contains(L.pa, L.result.params.data())) &&
            (!B.is_surface() || MB.contains(L.pb, L.result.params.data() + na));
  // A penetration depth counts only for a pair that went inside through contact (the normal
  // form's band around it): a face turned away from the other body (the far side of a torus
  // seen from its hole) also has d against its outward normal, with the bodies apart.
  // A tracker seeded apart whose first step reads it behind an open sheet (the sheet's normal
  // points away from the other body: an ellipsoid under a plane) did not come through contact:
  // an open sheet has no inside, and the solver's answer is reported instead. (A sheet A
  // against a solid B reads its sign from the solid where it can, Tracker_options::sign_from_b:
  // there a first negative reading is the sheet's witness inside the solid.)
  // It stays so until it reads the pair in front.
  if (L.result.distance > 0.0)
    L.behind_sheet = false;
  else if (first && L.seeded_apart && L.result.distance < -m_options.contact_tolerance &&
           (!closed(0) || !closed(1)))
    L.behind_sheet = true;
  // A normal-form reading holds a pair only where its conditions do: the normals parallel, or
  // (the other side held on an edge) d along the reference normal with the other witness the
  // foot of d along its free parameters, the conditions of a pair on an edge. Seeded at a
  // common point of surfaces that cross (a ball cutting a sheet), the normal form's residual
  // has a local minimum there that is no solution, and the tracker sits on it (read -0.011 and
  // +0.041 for a ball 0.7 deep in a plane). Through contact the corrections keep both to
  // rounding. With d along the reference normal but across the other's face, no foot there,
  // the reading is no pair: as1's bolt head seated flush on a bracket's flange, its rim at the
  // flange's edge, read as a 0.475 interference, and a tilted peg's cap and side pressed into
  // a plate read along their own normals (-4.8 for a rim 8 deep). At d = 0, where d has no
  // direction, a regular system decides (surfaces crossing there, no contact); a singular one
  // is a rim or an edge touching the other surface, in contact (as1's rod on a plate's edge),
  // where a witness is on an edge (of its patch or its trim) or a curve: two faces' interior
  // points are a crossing (a tilted peg's cap through a sheet's border read 0 'contact' 1.6
  // deep).
  if (L.result.normal_form && L.result.alignment_error > k_wandering_error) {
    const bool holds =
        std::abs(L.result.distance) > m_options.contact_tolerance
            ? L.result.reference_error <= k_wandering_error &&
                  L.result.other_error <= k_wandering_error
            : L.result.degeneracy != Degeneracy::None && L.result.degeneracy != Degeneracy::Pole &&
                  (L.result.on_edge != 0u || !A.is_surface() || !B.is_surface() ||
                   on_trim_boundary(A, L.result.params.data()) ||
                   on_trim_boundary(B, L.result.params.data() + 2)) &&
                  !edge_crosses_surface(A, *m_XA, B, *m_XB, L.result.params.data(), L.result.on_edge);
    if (!holds) L.valid = false;
  }
  if (L.result.normal_form && !L.behind_sheet && L.valid) L.through_contact = true;
  else if (L.result.distance > 0.0) L.through_contact = false;
  // Invalidated at the end: the other rules still run, so that holds_unreached records whether
  // the reading would hold but for this one (read by step()). Not behind an open sheet, whose
  // solid-only rules do not run.
  const bool unreached = L.result.distance < -m_options.contact_tolerance && !L.through_contact;
  // Deep inside (past the normal form's band), Newton's basin about a penetration pair can be
  // small: a tracker seeded at a common point of a deep overlap, or carried there, whose
  // conditions are far from holding wanders and reports nothing.
  if (L.result.distance < -m_options.contact_tolerance && !L.result.normal_form &&
      !is_converged(L, k_wandering_error))
    L.valid = false;
  // Between solids the outward normals at the witnesses tell a depth or a distance from a
  // point of one body inside the other (where they are defined; at a pole, their limit; normals
  // perpendicular are no sign of either, hence the margins):
  // - a penetration pair's normals oppose each other. With them alike, the pair is no depth: a
  //   point of one surface inside the other body and its foot on the face it entered by (a ball
  //   that jumped deep into a box in one step). Open sheets keep it: a plane passed through its
  //   copy is behind it. (A tilted peg's side held on its rim, pressed into a plate: normals
  //   nearly perpendicular.)
  // - apart, d goes along A's normal (where A's sign is read) and against B's. With B's along
  //   it too, A's witness lies inside B: the bodies are nested, not apart (a ball inside a
  //   part's plate, its tracker gone over its pole onto the pair below it, read +17.8; found by
  //   a helper's probe). No distance: the row is the solver's depth until a tracker holds one.
  // - in contact or just apart, two faces' interior points have their normals opposed; alike,
  //   one body lies inside the other there, touching it from within (a ball inside a cylinder
  //   against its cap read 0 'contact' 2 deep, or 2e-8 apart, its tracker lagging).
  if (L.valid && A.is_surface() && B.is_surface() && closed(0) && closed(1)) {
    // At a pole, the limit of the normal (a ball inside a cylinder, its top pole under the
    // cap's centre, read apart by the gap to the cap).
    const auto outward = [](const Primitive& P, const Rigid_pose_3& X, const double* q, Vec3& n) {
      Feature_point f;
      const bool pole = P.feature.collapsed_edges() != 0u;
      evaluate_feature(P.feature, X, q, f, pole ? 2 : 1);
      const Vec3 cross = P.feature.outward_sign() * f.d[0].cross(f.d[1]);
      n = pole ? outward_direction(P.feature, f, q, cross) : cross;
      // (The limit's factors at a pole: the mixed derivative and the tangent that remains.)
      const double scale = f.d[0].norm() * f.d[1].norm() +
                           f.dd[0][1].norm() * std::max(f.d[0].norm(), f.d[1].norm());
      return n.norm() > 1e-8 * scale;
    };
    const double* q = L.result.params.data();
    Vec3 na, nb;
    // (Near contact only: apart, the rule below reads the same from d.)
    const double d = L.result.distance, tol = m_options.contact_tolerance;
    const bool near = d >= -tol && d <= 1e3 * tol && L.result.on_edge == 0u &&
                      !on_trim_boundary(A, q) && !on_trim_boundary(B, q + 2);
    if (near && outward(A, *m_XA, q, na) && outward(B, *m_XB, q + 2, nb) &&
        na.dot(nb) > 0.5 * na.norm() * nb.norm()) {
      L.valid = false;
    } else if (std::abs(d) > tol && outward(B, *m_XB, q + 2, nb)) {
      if (d < 0.0) {
        if (outward(A, *m_XA, q, na) &&
            (na.dot(nb) > 1e-6 * na.norm() * nb.norm() ||
             normal_across_edge(A, *m_XA, q, L.result.on_edge & 3u, nb) ||
             normal_across_edge(B, *m_XB, q + 2, L.result.on_edge >> 2, na)))
          L.valid = false;
      } else {
        const Vec3 gap = L.result.point_b - L.result.point_a;
        if (nb.dot(gap) > 1e-6 * nb.norm() * gap.norm()) L.valid = false;
      }
    }
  }
  // Two solids: deeper than their boxes overlap along either frame's axes (a translation that
  // parts the boxes parts them) a reading is no depth (a peg 1 deep in a box's top, slid past
  // its side: the cap's pair read 1 with the side's 0.8).
  if (L.valid && L.result.distance < -m_options.contact_tolerance && closed(0) && closed(1) &&
      L.result.distance < -boxes_bound())
    L.valid = false;
  // A solid against an open body (a sheet, a curve, an open mesh): a depth puts the open
  // body's witness inside the solid, so inside the solid's box. Outside it, the reading is a
  // stale pair (a box that clipped a plane's border and left past it read -10 to -28 while 2 to
  // 18 apart, its tracker in the normal form's band).
  if (L.valid && L.result.distance < -m_options.contact_tolerance && closed(0) != closed(1) &&
      !MA.body().is_point && !MB.body().is_point) {
    const bool solid_a = closed(0);
    const Bbox_3& box = (solid_a ? MA : MB).box();
    const Vec3 x = (solid_a ? *m_XA : *m_XB)
                       .inverse()
                       .apply_point(solid_a ? L.result.point_b : L.result.point_a);
    const double margin = m_options.contact_tolerance + 1e-9 * internal::box_diagonal(box);
    for (int c = 0; c < 3; ++c)
      if (x[c] < box.min(c) - margin || x[c] > box.max(c) + margin) L.valid = false;
  }
  // A B-rep edge against a face, inside: the same opposition, against the edge's wedge.
  if (L.valid && L.result.distance < -m_options.contact_tolerance && closed(0) && closed(1)) {
    const bool edge_a = A.kind == Primitive_kind::Edge && B.is_surface();
    const bool edge_b = B.kind == Primitive_kind::Edge && A.is_surface();
    if (edge_a || edge_b) {
      const Primitive& S = edge_a ? B : A;
      const double* q = L.result.params.data();
      Feature_point f;
      evaluate_feature(S.feature, edge_a ? *m_XB : *m_XA, edge_a ? q + 1 : q, f, 1);
      const Vec3 n = S.feature.outward_sign() * f.d[0].cross(f.d[1]);
      if (outside_edge_wedge(edge_a ? MA : MB, edge_a ? L.pa : L.pb, edge_a ? *m_XA : *m_XB,
                             edge_a ? q[0] : q[2], -n))
        L.valid = false;
    }
  }
  L.holds_unreached = unreached && L.valid && !L.behind_sheet;
  if (unreached) L.valid = false;
}

}  // namespace extremal
