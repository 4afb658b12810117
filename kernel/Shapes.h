// Exact rational NURBS forms of the analytic shapes of the command-line shape specs
// (docs/cli.md). Every surface's outward_sign is set so that outward_normal points out of
// the solid. Parametrisations:
//   sphere, ellipsoid: u = longitude in [0, 2 pi] (closed), v = latitude in [-pi/2, pi/2]
//                      (poles at the v ends); biquadratic, 9 x 5 control points.
//   torus:     u = angle about z in [0, 2 pi], v = angle about the tube in [0, 2 pi]; 9 x 9.
//   cylinder:  side u = angle in [0, 2 pi], v = height in [0, 1] (z = v h); caps are disks with
//              v = radius fraction in [0, 1] (collapsed edge at the centre).
//   plane:     bilinear, u along x, v along y, both in [0, 1]; normal +z.
// Angle knots sit at multiples of pi/2 but the rational parametrisation is not the angle.
#pragma once

#include <vector>

#include "kernel/Body.h"
#include "kernel/Nurbs_curve_3.h"
#include "kernel/Nurbs_surface_3.h"

namespace extremal {

// Full circle of radius r in the xy-plane centred at the origin, rational quadratic, 9 poles.
Nurbs_curve_3 make_circle(double r);

Nurbs_surface_3 make_ellipsoid(double a, double b, double c);
Nurbs_surface_3 make_sphere(double r);
Nurbs_surface_3 make_torus(double major, double minor);
Nurbs_surface_3 make_cylinder_side(double r, double h);
// Disk of radius r in the plane z = z0; `outward_up` chooses whether +z is outward.
Nurbs_surface_3 make_disk(double r, double z0, bool outward_up);
Nurbs_surface_3 make_plane(double w, double h);
// Freeform patch through a grid of control points (n_u x n_v, row-major as in
// Nurbs_surface_3), clamped uniform knots in [0, 1].
Nurbs_surface_3 make_freeform(int degree_u, int degree_v, int n_u, int n_v,
                              std::vector<Point_3> poles, std::vector<double> weights = {});

// Bodies for the shape specs. Sizes must be finite and > 0 (Invalid_input otherwise).
Body make_point_body(const std::string& name = "point");
Body make_sphere_body(double r, const std::string& name = "sphere");
Body make_ellipsoid_body(double a, double b, double c, const std::string& name = "ellipsoid");
Body make_torus_body(double major, double minor, const std::string& name = "torus");
Body make_cylinder_body(double r, double h, const std::string& name = "cylinder");  // side + caps
Body make_plane_body(double w, double h, const std::string& name = "plane");

}  // namespace extremal
