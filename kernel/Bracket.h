// A generated non-convex CAD part with a full B-rep: a U-shaped channel bracket, the part of the
// bundled demo (the build writes this body as data/demo/bracket.step through io/Step_writer).
//
// The profile in the xz-plane is a block [-w/2, w/2] x [0, h] with a slot of width s cut down to
// the floor at z = f; the slot's bottom corners are filleted (radius r, concave quarter
// cylinders) and the block's bottom edges rounded (radius R, convex quarter cylinders). The
// profile is extruded along y over [-l/2, l/2]. Faces (all NURBS, exact):
//   0..11  the sides, one ruled patch per profile segment (bilinear planes, rational
//          biquadratic-by-linear quarter cylinders), u = the segment's parameter, v from the
//          y = +l/2 end (v = 0) to y = -l/2 (v = 1), outward_sign +1;
//   12, 13 the end caps y = -l/2 and y = +l/2: bilinear planes over the profile's box, trimmed
//          by the profile (u along x, v along z), outward_sign +1 and -1.
// Edges: the 12 profile segments at y = +l/2 (0..11) and at y = -l/2 (12..23), and the 12 straight
// rulings at the profile's corners (24..35), each used by two faces in opposite directions.
// Every trim curve is the exact image of its edge in the face's parameters (same_parameter).
// Body frame: origin at the middle of the bottom face, z up, the slot open towards +z.
#pragma once

#include <string>

#include "kernel/Body.h"

namespace extremal {

struct Bracket_size {
  double width = 8.0;       // w, along x
  double height = 4.0;      // h, along z
  double length = 10.0;     // l, along y
  double floor = 1.0;       // f, the slot floor's height
  double slot_width = 5.0;  // s
  double fillet = 1.0;      // r, slot bottom corners (concave)
  double round = 1.0;       // R, the block's bottom edges (convex)
};

// Throws Invalid_input when the sizes do not make a valid profile (non-positive or non-finite
// values, a slot wider than the block, fillets that do not fit).
Body make_bracket_body(const Bracket_size& size = {}, const std::string& name = "bracket");

// The bracket's exact volume: profile area times length (for tests of orientation and closure).
double bracket_volume(const Bracket_size& size = {});

}  // namespace extremal
