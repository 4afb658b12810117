// What the two bodies of a pair are (fixed at construction), whose normal gives the sign of
// a reading, and the regime of a reading (computed once per step). Not API.
#pragma once

#include "algorithms/body_pair/Tracking_model.h"

namespace extremal::internal {

// A body's kind: closed B-rep faces enclose a solid; open ones are a sheet; a body of curves
// only, a point, or a triangle mesh (closed when every edge has two triangles).
enum class Body_kind { Solid, Open_sheet, Curve, Point, Closed_mesh, Open_mesh };
const char* to_string(Body_kind k);

// Whose outward normal gives a reading's sign: A's (where A is a surface at its witness, else
// B's), or, for an A that is not closed (a sheet, a curve, a point, an open mesh) against a
// closed B, B's wherever B's witness is inside one of its faces (a sheet's normal does not tell
// a solid's inside; Tracker_options::sign_from_b; test ProbeScenes.ASolidLeftBehindASheetIsApart).
enum class Sign_policy { Normal_of_a, Normal_of_closed_b };

struct Pair_kind {
  Body_kind a = Body_kind::Solid, b = Body_kind::Solid;
  Sign_policy sign = Sign_policy::Normal_of_a;

  static Pair_kind of(const Tracking_model& A, const Tracking_model& B);
  Body_kind side(int s) const { return s == 0 ? a : b; }
  // Encloses a volume (a solid or a closed mesh): it has an inside a depth can be read in.
  bool closed(int s) const { return side(s) == Body_kind::Solid || side(s) == Body_kind::Closed_mesh; }
  bool point(int s) const { return side(s) == Body_kind::Point; }
  // Closed, or a point: a depth against it is a depth (a point inside a body is at its depth).
  bool solid_or_point(int s) const { return closed(s) || point(s); }
  bool both_closed() const { return closed(0) && closed(1); }
  bool any_point() const { return point(0) || point(1); }
  // Has two sides a solid can enter it by: open B-rep faces or an open mesh.
  bool sheet(int s) const { return side(s) == Body_kind::Open_sheet || side(s) == Body_kind::Open_mesh; }
  // One side closed and the other a sheet: the solid keeps the side it entered by.
  bool closed_against_sheet() const { return (closed(0) && sheet(1)) || (closed(1) && sheet(0)); }
  // One side closed and the other a curve: no side to enter by, a depth like a solid's.
  bool curve_against_closed() const {
    return (closed(0) && side(1) == Body_kind::Curve) || (closed(1) && side(0) == Body_kind::Curve);
  }
  // An inside to read a depth in: a closed body on either side, or two B-rep sheets (which
  // cross). Without one (a curve, a point or an open mesh against a body that is not closed)
  // a pair reads its distance unsigned: 0 where they meet (docs/behaviour.md, "Overlap").
  bool has_inside() const {
    return closed(0) || closed(1) || (side(0) == Body_kind::Open_sheet && side(1) == Body_kind::Open_sheet);
  }
};

// Where a reading lies: apart (d above the contact tolerance), in the contact band (|d| within
// it), inside the normal form's band about contact, or deep (past it: Extremal_tracker's
// normal form off).
enum class Regime { Apart, Contact_band, Inside_band, Deep };
inline Regime regime_of(double distance, double contact_tolerance, bool normal_form) {
  if (distance > contact_tolerance) return Regime::Apart;
  if (distance >= -contact_tolerance) return Regime::Contact_band;
  return normal_form ? Regime::Inside_band : Regime::Deep;
}
inline bool is_inside(Regime r) { return r == Regime::Inside_band || r == Regime::Deep; }

}  // namespace extremal::internal
