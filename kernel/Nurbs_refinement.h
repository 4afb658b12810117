// Knot insertion, Bezier extraction and subdivision. All exact in homogeneous coordinates:
// the refined curve or surface is the same point set with the same parametrisation.
#pragma once

#include <utility>
#include <vector>

#include "kernel/Nurbs_curve_3.h"
#include "kernel/Nurbs_surface_3.h"

namespace extremal {

// Inserts knot t (inside the domain, ends included) `times` times (Boehm's algorithm). Throws
// Precondition_violation if t is outside the domain or the multiplicity would exceed the degree.
Nurbs_curve_3 insert_knot(const Nurbs_curve_3& c, double t, int times = 1);
Nurbs_surface_3 insert_knot(const Nurbs_surface_3& s, Parameter_direction dir, double t,
                            int times = 1);

// Bezier pieces of a curve, in parameter order; each keeps its own parameter interval as its
// (clamped) knot vector.
std::vector<Nurbs_curve_3> extract_bezier(const Nurbs_curve_3& c);

// Bezier pieces of a surface: count_u x count_v patches, patch (i, j) at patches[i*count_v + j].
struct Bezier_patches {
  int count_u = 0, count_v = 0;
  std::vector<Nurbs_surface_3> patches;
};
Bezier_patches extract_bezier(const Nurbs_surface_3& s);

// Splits at t strictly inside the domain into the parts before and after t.
std::pair<Nurbs_curve_3, Nurbs_curve_3> split(const Nurbs_curve_3& c, double t);
std::pair<Nurbs_surface_3, Nurbs_surface_3> split(const Nurbs_surface_3& s,
                                                  Parameter_direction dir, double t);

}  // namespace extremal
