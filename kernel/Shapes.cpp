#include "kernel/Shapes.h"

#include <cmath>
#include <sstream>

#include "kernel/Error.h"

namespace extremal {

namespace {

constexpr double k_pi = 3.14159265358979323846;
const double k_s = std::sqrt(0.5);  // weight of a quarter arc's middle pole

void require_positive(double x, const char* what) {
  if (!(std::isfinite(x) && x > 0.0)) {
    std::ostringstream os;
    os << what << " must be finite and > 0, got " << x;
    throw Invalid_input(os.str());
  }
}

// Unit full circle: 9 poles (x, y), weights, knots in [0, 2 pi].
struct Profile {
  std::vector<double> x, y, w, knots;
};

Profile unit_circle() {
  Profile c;
  c.x = {1, 1, 0, -1, -1, -1, 0, 1, 1};
  c.y = {0, 1, 1, 1, 0, -1, -1, -1, 0};
  c.w = {1, k_s, 1, k_s, 1, k_s, 1, k_s, 1};
  const double h = k_pi / 2;
  c.knots = {0, 0, 0, h, h, 2 * h, 2 * h, 3 * h, 3 * h, 4 * h, 4 * h, 4 * h};
  return c;
}

// Unit half circle from the south pole (0, -1) to the north pole (0, 1) through (1, 0), as
// (rho, z), latitude knots in [-pi/2, pi/2].
Profile unit_meridian() {
  Profile m;
  m.x = {0, 1, 1, 1, 0};
  m.y = {-1, -1, 0, 1, 1};
  m.w = {1, k_s, 1, k_s, 1};
  const double h = k_pi / 2;
  m.knots = {-h, -h, -h, 0, 0, h, h, h};
  return m;
}

// Surface of revolution about z of a profile given as (rho, z) with weights.
Nurbs_surface_3 revolve(const Profile& profile, int profile_degree) {
  const Profile c = unit_circle();
  const int nu = 9, nv = static_cast<int>(profile.x.size());
  std::vector<Point_3> poles;
  std::vector<double> weights;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      poles.emplace_back(profile.x[j] * c.x[i], profile.x[j] * c.y[i], profile.y[j]);
      weights.push_back(c.w[i] * profile.w[j]);
    }
  return Nurbs_surface_3(2, profile_degree, nu, nv, std::move(poles), c.knots, profile.knots,
                         std::move(weights));
}

std::vector<double> clamped_uniform(int n, int p) {
  std::vector<double> k;
  for (int i = 0; i <= p; ++i) k.push_back(0.0);
  for (int i = 1; i < n - p; ++i) k.push_back(static_cast<double>(i) / (n - p));
  for (int i = 0; i <= p; ++i) k.push_back(1.0);
  return k;
}

}  // namespace

Nurbs_curve_3 make_circle(double r) {
  require_positive(r, "circle radius");
  const Profile c = unit_circle();
  std::vector<Point_3> poles;
  for (int i = 0; i < 9; ++i) poles.emplace_back(r * c.x[i], r * c.y[i], 0.0);
  return Nurbs_curve_3(2, std::move(poles), c.knots, c.w);
}

Nurbs_surface_3 make_ellipsoid(double a, double b, double c) {
  require_positive(a, "ellipsoid semi-axis a");
  require_positive(b, "ellipsoid semi-axis b");
  require_positive(c, "ellipsoid semi-axis c");
  const Nurbs_surface_3 unit = revolve(unit_meridian(), 2);
  // An affine map of the control points maps the rational surface exactly.
  std::vector<Point_3> poles;
  for (const auto& p : unit.poles()) poles.emplace_back(a * p.x(), b * p.y(), c * p.z());
  Nurbs_surface_3 s(2, 2, unit.number_of_poles_u(), unit.number_of_poles_v(), std::move(poles),
                    unit.knots_u(), unit.knots_v(), unit.weights());
  s.set_outward_sign(+1);  // east x north points out
  return s;
}

Nurbs_surface_3 make_sphere(double r) {
  require_positive(r, "sphere radius");
  return make_ellipsoid(r, r, r);
}

Nurbs_surface_3 make_torus(double major, double minor) {
  require_positive(major, "torus major radius");
  require_positive(minor, "torus minor radius");
  Profile tube = unit_circle();
  for (int j = 0; j < 9; ++j) {
    tube.x[j] = major + minor * tube.x[j];
    tube.y[j] = minor * tube.y[j];
  }
  Nurbs_surface_3 s = revolve(tube, 2);
  s.set_outward_sign(+1);
  return s;
}

Nurbs_surface_3 make_cylinder_side(double r, double h) {
  require_positive(r, "cylinder radius");
  require_positive(h, "cylinder height");
  Profile side;
  side.x = {r, r};
  side.y = {0, h};
  side.w = {1, 1};
  side.knots = {0, 0, 1, 1};
  Nurbs_surface_3 s = revolve(side, 1);
  s.set_outward_sign(+1);
  return s;
}

Nurbs_surface_3 make_disk(double r, double z0, bool outward_up) {
  require_positive(r, "disk radius");
  Profile radial;
  radial.x = {0, r};
  radial.y = {z0, z0};
  radial.w = {1, 1};
  radial.knots = {0, 0, 1, 1};
  Nurbs_surface_3 s = revolve(radial, 1);
  // f_u (tangential) x f_v (radial) points down (-z).
  s.set_outward_sign(outward_up ? -1 : +1);
  return s;
}

Nurbs_surface_3 make_plane(double w, double h) {
  require_positive(w, "plane width");
  require_positive(h, "plane height");
  std::vector<Point_3> poles = {{-w / 2, -h / 2, 0}, {-w / 2, h / 2, 0},
                                {w / 2, -h / 2, 0},  {w / 2, h / 2, 0}};
  Nurbs_surface_3 s(1, 1, 2, 2, std::move(poles), {0, 0, 1, 1}, {0, 0, 1, 1});
  s.set_outward_sign(+1);
  return s;
}

Nurbs_surface_3 make_freeform(int degree_u, int degree_v, int n_u, int n_v,
                              std::vector<Point_3> poles, std::vector<double> weights) {
  if (n_u < degree_u + 1 || n_v < degree_v + 1) {
    std::ostringstream os;
    os << "freeform patch: a " << n_u << " x " << n_v << " grid is too small for degrees "
       << degree_u << " x " << degree_v;
    throw Invalid_input(os.str());
  }
  return Nurbs_surface_3(degree_u, degree_v, n_u, n_v, std::move(poles),
                         clamped_uniform(n_u, degree_u), clamped_uniform(n_v, degree_v),
                         std::move(weights));
}

Body make_point_body(const std::string& name) {
  Body b;
  b.name = name;
  b.is_point = true;
  return b;
}

Body make_sphere_body(double r, const std::string& name) {
  Body b;
  b.name = name;
  b.faces.push_back({make_sphere(r), "sphere"});
  return b;
}

Body make_ellipsoid_body(double a, double b, double c, const std::string& name) {
  Body body;
  body.name = name;
  body.faces.push_back({make_ellipsoid(a, b, c), "ellipsoid"});
  return body;
}

Body make_torus_body(double major, double minor, const std::string& name) {
  Body b;
  b.name = name;
  b.faces.push_back({make_torus(major, minor), "torus"});
  return b;
}

Body make_cylinder_body(double r, double h, const std::string& name) {
  Body b;
  b.name = name;
  b.faces.push_back({make_cylinder_side(r, h), "cylinder"});
  b.faces.push_back({make_disk(r, 0.0, false), "plane"});
  b.faces.push_back({make_disk(r, h, true), "plane"});
  return b;
}

Body make_plane_body(double w, double h, const std::string& name) {
  Body b;
  b.name = name;
  b.faces.push_back({make_plane(w, h), "plane"});
  return b;
}

}  // namespace extremal
