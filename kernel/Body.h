// A rigid body: the patches (faces) and curves that bound it, in its own frame.
#pragma once

#include <string>
#include <vector>

#include "kernel/Nurbs_curve_3.h"
#include "kernel/Nurbs_surface_3.h"
#include "kernel/Types.h"

namespace extremal {

// One face of a body: its surface and the kind of surface it came from ("sphere", "plane",
// "bspline", ...), which `extremal info` reports.
struct Face {
  Nurbs_surface_3 surface;
  std::string kind;
};

struct Body {
  std::string name;
  // A point body is just its origin (a probe, a tool tip): no faces, no curves.
  bool is_point = false;
  std::vector<Face> faces;
  std::vector<Nurbs_curve_3> curves;

  // Box of every face's and curve's control points, in the body frame.
  Bbox_3 hull_bbox() const;
  bool is_empty() const { return !is_point && faces.empty() && curves.empty(); }
};

}  // namespace extremal
