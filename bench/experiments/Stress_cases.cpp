#include "Stress_cases.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <stdexcept>

#include "algorithms/body_pair/Body_pair_tracker.h"
#include "algorithms/distance/Ellipsoid_distance.h"
#include "kernel/Nurbs_refinement.h"
#include "kernel/Shapes.h"

namespace extremal::experiments {

namespace {

constexpr double k_pi = 3.14159265358979323846;
constexpr double k_eps = std::numeric_limits<double>::epsilon();
constexpr double k_dt = 1e-3;  // 1 kHz throughout

struct Placement {
  Rigid_pose_3 pose;
  Twist_3 twist;
};

// A body whose centre follows `path` (velocity by central differences of the path, before the
// offset is added so that a large offset does not cancel it) while it spins at constant `spin`
// from the orientation R0.
struct Path_motion {
  std::function<Vec3(double)> path;
  Mat3 R0 = Mat3::Identity();
  Vec3 spin = Vec3::Zero();
  Vec3 offset = Vec3::Zero();

  Placement at(double t) const {
    Twist_3 w;
    w.angular = spin;
    const Mat3 R = advance(Rigid_pose_3(R0, Vec3::Zero()), w, t).rotation();
    const double h = 1e-5;
    w.linear = (path(t + h) - path(t - h)) / (2.0 * h);
    return {Rigid_pose_3(R, path(t) + offset), w};
  }
};

Path_motion still(const Vec3& at = Vec3::Zero(), const Mat3& R = Mat3::Identity()) {
  return {[at](double) -> Vec3 { return at; }, R, Vec3::Zero(), Vec3::Zero()};
}

using Reference = std::function<double(double, const Placement&, const Placement&)>;

std::size_t steps_for(Stress_length length, long short_steps) {
  return static_cast<std::size_t>(length == Stress_length::Long ? 100 * short_steps : short_steps);
}

// Runs the pair at 1 kHz from t = 0 and fills the counts of `r`.
void run_pair(Stress_result& r, const Body& a, const Body& b, const Path_motion& ma,
              const Path_motion& mb, const Reference& reference, std::size_t steps,
              const Body_pair_options& options = {}) {
  const auto t0 = std::chrono::steady_clock::now();
  Body_pair_tracker tracker(a, b, options);
  // EXTREMAL_STRESS_TRACE=1 prints the first steps whose error exceeds the tolerance.
  const bool trace = std::getenv("EXTREMAL_STRESS_TRACE") != nullptr;
  int traced = 0;
  for (std::size_t i = 0; i < steps; ++i) {
    const double t = static_cast<double>(i) * k_dt;
    const Placement pa = ma.at(t), pb = mb.at(t);
    const Pair_report& rep = tracker.step(t, pa.pose, pa.twist, pb.pose, pb.twist, k_dt);
    ++r.steps;
    if (!(std::isfinite(rep.distance) && rep.point_a.allFinite() && rep.point_b.allFinite() &&
          rep.normal.allFinite())) {
      ++r.nan_count;
      continue;
    }
    const double exact = reference(t, pa, pb);
    const double error = std::abs(rep.distance - exact);
    if (!(error <= r.lost_threshold)) ++r.lost_count;  // NaN reference counts as lost
    if (trace && !(error <= r.tolerance) && traced++ < 40)
      std::printf("  step %zu t %.3f: tracked %.6e exact %.6e status %s %s features %d %d "
                  "params %.6f %.6f %.6f %.6f trackers %d\n",
                  i, t, rep.distance, exact, to_string(rep.status), to_string(rep.degeneracy),
                  rep.feature_a, rep.feature_b, rep.params[0], rep.params[1], rep.params[2],
                  rep.params[3], tracker.statistics().trackers);
    if (std::isfinite(error)) r.max_error = std::max(r.max_error, error);
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Mat3 rotation(const Vec3& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

// ---- references ---------------------------------------------------------------------------

// Certified distance between two ellipsoids (support-function bounds; midpoint of a gap of
// about 1e-15 relative). Keeps the last normal as the next start.
struct Ellipsoid_reference {
  Vec3 axes_a, axes_b;
  double scale = 1.0;    // the reference geometry is the placed one divided by this
  Vec3 offset = Vec3::Zero();  // and moved back by this (its poses without the offset)
  mutable Vec3 normal = Vec3::Zero();
  double operator()(double, const Placement& pa, const Placement& pb) const {
    const Rigid_pose_3 A(pa.pose.rotation(), (pa.pose.translation() - offset) / scale);
    const Rigid_pose_3 B(pb.pose.rotation(), (pb.pose.translation() - offset) / scale);
    const Ellipsoid_distance_result e =
        ellipsoid_distance({A, axes_a / scale}, {B, axes_b / scale}, normal);
    normal = e.normal;
    if (!e.separated) return std::numeric_limits<double>::quiet_NaN();
    return scale * 0.5 * (e.lower_bound + e.upper_bound);
  }
};

// The seed's two ellipsoids on a bounded motion that can run for any time: A spins at the
// origin, B spins and circles A (centre 7.5 from A's, axes 3 and 2: never closer than 2.5).
void seed_orbit(double scale, const Vec3& offset, Path_motion& ma, Path_motion& mb) {
  ma = {[](double) -> Vec3 { return Vec3::Zero(); },
        Rigid_pose_3::from_quaternion(Vec3::Zero(), 0.9, 0.1, 0.3, 0.2).rotation(),
        Vec3(0.2, -0.1, 0.3), offset};
  mb = {[scale](double t) -> Vec3 {
          return scale * Vec3(7.5 * std::cos(0.3 * t), 7.5 * std::sin(0.3 * t) * 0.9,
                              0.5 + 7.5 * 0.43 * std::sin(0.3 * t) + 0.4 * std::sin(0.7 * t));
        },
        Rigid_pose_3::from_quaternion(Vec3::Zero(), 0.8, -0.2, 0.1, 0.4).rotation(),
        Vec3(-0.1, 0.3, 0.2), offset};
}

Stress_result seed_ellipsoids(const std::string& name, Stress_length length, double scale,
                              const Vec3& offset, long short_steps) {
  Stress_result r;
  r.name = name;
  r.reference = "Ellipsoid_distance certificate";
  const Vec3 axes_a(3.0, 2.0, 1.5), axes_b(2.0, 1.2, 1.0);
  const Body a = make_ellipsoid_body(scale * axes_a.x(), scale * axes_a.y(), scale * axes_a.z());
  const Body b = make_ellipsoid_body(scale * axes_b.x(), scale * axes_b.y(), scale * axes_b.z());
  Path_motion ma, mb;
  seed_orbit(scale, offset, ma, mb);
  const double size = 3.0 * scale;
  // Rounding of the world coordinates bounds what any method can resolve.
  r.tolerance = std::max(1e-9 * size, 64.0 * k_eps * offset.cwiseAbs().maxCoeff());
  r.lost_threshold = 1e-4 * size;
  run_pair(r, a, b, ma, mb, Ellipsoid_reference{scale * axes_a, scale * axes_b, scale, offset},
           steps_for(length, short_steps));
  return r;
}

// Distance from p to the finite cylinder rho <= r, 0 <= z <= h (p outside).
double point_to_cylinder(const Vec3& p, double r, double h) {
  const double dr = std::max(std::hypot(p.x(), p.y()) - r, 0.0);
  const double dz = std::max({p.z() - h, -p.z(), 0.0});
  return std::hypot(dr, dz);
}

// Distance from p to the segment from the origin to (0, 0, L).
double point_to_axis_segment(const Vec3& p, double L) {
  const double z = std::clamp(p.z(), 0.0, L);
  return (p - Vec3(0, 0, z)).norm();
}

// Distance from p to the paraboloid z = a (x^2 + y^2) where 1 - 2 a p_z > 0 (a unique
// nearest point, in the vertical plane through the axis and p): the root rho of
// 2 a^2 rho^3 + (1 - 2 a z) rho - rho0 = 0, by Newton's method in long double from rho0.
double point_to_paraboloid(const Vec3& p, double a) {
  const long double rho0 = std::hypot(p.x(), p.y()), z0 = p.z(), A = a;
  long double rho = rho0;
  for (int k = 0; k < 60; ++k) {
    const long double f = 2 * A * A * rho * rho * rho + (1 - 2 * A * z0) * rho - rho0;
    const long double df = 6 * A * A * rho * rho + (1 - 2 * A * z0);
    const long double step = f / df;
    rho -= step;
    if (std::abs(step) < 1e-19L) break;
  }
  const long double dz = A * rho * rho - z0, dr = rho - rho0;
  return static_cast<double>(std::sqrt(dz * dz + dr * dr));
}

Body body_of(std::vector<Nurbs_surface_3> faces, const std::string& name) {
  Body b;
  b.name = name;
  for (auto& s : faces) b.faces.emplace_back(std::move(s), "bspline");
  return b;
}

// Sets the outward sign of `s` so that outward_normal points away from `inside`, judged at the
// middle of the domain.
void orient_away_from(Nurbs_surface_3& s, const Vec3& inside) {
  Surface_point sp;
  s.evaluate(0.5 * (s.u_min() + s.u_max()), 0.5 * (s.v_min() + s.v_max()), sp, 1);
  s.set_outward_sign(sp.du.cross(sp.dv).dot(sp.p - inside) >= 0.0 ? 1 : -1);
}

// ---- the cases ----------------------------------------------------------------------------

Stress_result near_parallel_big_sphere(Stress_length length) {
  // A sphere of radius 1000 over a plane 2 x 2: the tangent planes at the pair are parallel
  // and the sphere's curvature terms in M are 1e-3 of the metric terms.
  Stress_result r;
  r.name = "near-parallel: sphere R 1e3 over a plane";
  r.reference = "closed form c_z - R";
  const double R = 1e3;
  const Body plane = make_plane_body(2.0, 2.0), sphere = make_sphere_body(R);
  // A quarter turn about x puts the sphere's equator, not its pole, at the bottom.
  Path_motion mb{[R](double t) -> Vec3 {
                   return Vec3(0.5 * std::sin(0.7 * t), 0.4 * std::cos(0.9 * t),
                               R + 0.05 + 0.03 * std::sin(1.1 * t));
                 },
                 rotation(Vec3::UnitX(), 0.5 * k_pi), Vec3(0, 0, 0.2), Vec3::Zero()};
  r.tolerance = 1e-9;
  r.lost_threshold = 1e-4;
  run_pair(r, plane, sphere, still(), mb,
           [R](double, const Placement&, const Placement& pb) {
             return pb.pose.translation().z() - R;
           },
           steps_for(length, 3000));
  return r;
}

Stress_result near_parallel_tilted_planes(Stress_length length) {
  // A 1 x 1 plane facing a 2 x 2 plane, tilted by 1e-6 and spinning about the vertical: the
  // nearest point is the lowest corner of the small plane, 1e-6 below its other points, and
  // changes corner four times a turn (a continuum in between).
  Stress_result r;
  r.name = "near-parallel: planes tilted by 1e-6";
  r.reference = "closed form: lowest corner";
  const double tilt = 1e-6;
  const Body big = make_plane_body(2.0, 2.0), small = make_plane_body(1.0, 1.0);
  const Mat3 R0 = rotation(Vec3(1.0, 0.3, 0.0), tilt) * rotation(Vec3::UnitX(), k_pi);
  Path_motion mb{[](double t) -> Vec3 { return Vec3(0, 0, 0.02 + 0.01 * std::sin(t)); }, R0,
                 Vec3(0, 0, 0.8), Vec3::Zero()};
  // Over the small plane the distance varies by at most the tilt times its diagonal: the
  // tracker may sit anywhere on that near-continuum (damped steps), so the error is bounded by
  // it, not by rounding.
  r.tolerance = tilt * std::sqrt(2.0);
  r.lost_threshold = 1e-4;
  run_pair(r, big, small, still(), mb,
           [](double, const Placement&, const Placement& pb) {
             double z = std::numeric_limits<double>::infinity();
             for (double x : {-0.5, 0.5})
               for (double y : {-0.5, 0.5}) z = std::min(z, pb.pose.apply_point(Vec3(x, y, 0)).z());
             return z;
           },
           steps_for(length, 3000));
  return r;
}

// A sphere sliding and spinning on a plane, its distance oscillating by +-1e-9 around contact,
// from the orientation R0.
Stress_result grazing_sphere(Stress_length length, const Mat3& R0, const std::string& name) {
  Stress_result r;
  r.name = name;
  r.reference = "closed form c_z - r";
  const Body plane = make_plane_body(4.0, 4.0), sphere = make_sphere_body(0.5);
  Path_motion mb{[](double t) -> Vec3 {
                   return Vec3(0.8 * std::sin(0.6 * t), 0.8 * std::cos(0.5 * t),
                               0.5 + 1e-9 * std::sin(3.0 * t));
                 },
                 R0, Vec3(0.4, -0.9, 0.3), Vec3::Zero()};
  r.tolerance = 1e-11;
  r.lost_threshold = 1e-6;
  run_pair(r, plane, sphere, still(), mb,
           [](double, const Placement&, const Placement& pb) {
             return pb.pose.translation().z() - 0.5;
           },
           steps_for(length, 3000));
  return r;
}

Stress_result grazing_ellipsoid(Stress_length length) {
  // An ellipsoid tumbling on a plane with its lowest point held in contact (distance 1e-10
  // sin(2t)): every step is at or within 1e-10 of tangential contact.
  Stress_result r;
  r.name = "grazing: ellipsoid tumbling in contact";
  r.reference = "closed form c_z - sqrt(P_zz)";
  const Vec3 axes(3.0, 2.0, 1.5);
  const Body plane = make_plane_body(40.0, 40.0), ell = make_ellipsoid_body(3.0, 2.0, 1.5);
  const Vec3 spin(0.3, 0.5, 0.2);
  const Mat3 R0 = rotation(Vec3(1, 2, 3), 0.4);
  auto lowest = [axes](const Mat3& R) {
    const Mat3 P = R * axes.cwiseAbs2().asDiagonal() * R.transpose();
    return std::sqrt(P(2, 2));
  };
  Path_motion mb{[=](double t) -> Vec3 {
                   Twist_3 w;
                   w.angular = spin;
                   const Mat3 R = advance(Rigid_pose_3(R0, Vec3::Zero()), w, t).rotation();
                   return Vec3(0.3 * std::sin(t), 0.2 * t / (1.0 + 0.01 * t),
                               lowest(R) + 1e-10 * std::sin(2.0 * t));
                 },
                 R0, spin, Vec3::Zero()};
  r.tolerance = 1e-11;
  r.lost_threshold = 1e-6;
  run_pair(r, plane, ell, still(), mb,
           [=](double, const Placement&, const Placement& pb) {
             return pb.pose.translation().z() - lowest(pb.pose.rotation());
           },
           steps_for(length, 3000));
  return r;
}

Stress_result poles_point_over_sphere(Stress_length length) {
  // A point circling a sphere through both poles of its parametrisation.
  Stress_result r;
  r.name = "poles: point through sphere poles";
  r.reference = "closed form |c| - r";
  const Body sphere = make_sphere_body(1.0), point = make_point_body();
  Path_motion mb{[](double t) -> Vec3 { return 1.5 * Vec3(std::sin(2.0 * t), 0.0, std::cos(2.0 * t)); },
                 Mat3::Identity(), Vec3::Zero(), Vec3::Zero()};
  r.tolerance = 1e-9;
  r.lost_threshold = 1e-4;
  run_pair(r, sphere, point, still(), mb,
           [](double, const Placement&, const Placement& pb) {
             return pb.pose.translation().norm() - 1.0;
           },
           steps_for(length, 4000));
  return r;
}

Stress_result poles_ellipsoids(Stress_length length) {
  // Two ellipsoids spinning so that the poles of both sweep through the extremal pair (centres
  // 4.7 apart, longest semi-axes 2.5 and 2: always apart).
  Stress_result r;
  r.name = "poles: ellipsoid poles through the pair";
  r.reference = "Ellipsoid_distance certificate";
  const Vec3 axes_a(2.0, 1.5, 2.5), axes_b(2.0, 1.2, 1.0);
  const Body a = make_ellipsoid_body(2.0, 1.5, 2.5), b = make_ellipsoid_body(2.0, 1.2, 1.0);
  const Path_motion ma{[](double) -> Vec3 { return Vec3::Zero(); }, Mat3::Identity(), Vec3(1.3, 0, 0),
                       Vec3::Zero()};
  const Path_motion mb{[](double t) -> Vec3 { return Vec3(0.1 * std::sin(t), 0.0, -4.7); },
                       Mat3::Identity(), Vec3(0, 0.9, 0), Vec3::Zero()};
  r.tolerance = 1e-9 * 2.5;
  r.lost_threshold = 1e-4 * 2.5;
  run_pair(r, a, b, ma, mb, Ellipsoid_reference{axes_a, axes_b}, steps_for(length, 4000));
  return r;
}

Stress_result c0_cylinder(Stress_length length) {
  // A small sphere circling a closed cylinder (side and two caps, C0 rims) through the cap
  // centres (the collapsed edge of each disk), across both rims and along the side.
  Stress_result r;
  r.name = "C0 joins: sphere around a cylinder";
  r.reference = "closed form (point to finite cylinder) - r_s";
  const double rs = 0.2;
  const Body cyl = make_cylinder_body(1.0, 2.0), ball = make_sphere_body(rs);
  Path_motion mb{[](double t) -> Vec3 {
                   return Vec3(1.8 * std::sin(1.5 * t), 0.0, 1.0 + 1.8 * std::cos(1.5 * t));
                 },
                 Mat3::Identity(), Vec3(0.3, 0.2, -0.5), Vec3::Zero()};
  r.tolerance = 1e-9;
  r.lost_threshold = 1e-4;
  // Once failed: the far cap's tracker reported a pair through the body as penetration
  // (-2.30 against +0.30 at t = 1.702); penetration now counts only when reached through contact.
  run_pair(r, cyl, ball, still(), mb,
           [rs](double, const Placement&, const Placement& pb) {
             return point_to_cylinder(pb.pose.translation(), 1.0, 2.0) - rs;
           },
           steps_for(length, 4200));
  return r;
}

Stress_result c0_disk_rim(Stress_length length) {
  // A small sphere circling a disk beside its rim, above and below its plane: the pair lies on
  // the rim (a patch edge at v = 1, while v = 0 is the disk's collapsed centre) all the time,
  // and crosses the seam of the closed u direction.
  Stress_result r;
  r.name = "C0 edge: sphere around a disk rim";
  r.reference = "closed form (point to circle) - r_s";
  const double rs = 0.1;
  const Body disk = body_of({make_disk(1.0, 0.0, true)}, "disk"), ball = make_sphere_body(rs);
  Path_motion mb{[](double t) -> Vec3 {
                   const double rho = 1.4 + 0.1 * std::sin(1.3 * t);
                   return Vec3(rho * std::cos(0.8 * t), rho * std::sin(0.8 * t), 0.4 * std::sin(t));
                 },
                 Mat3::Identity(), Vec3(0.5, 0.1, -0.3), Vec3::Zero()};
  r.tolerance = 1e-9;
  r.lost_threshold = 1e-4;
  run_pair(r, disk, ball, still(), mb,
           [rs](double, const Placement&, const Placement& pb) {
             const Vec3 c = pb.pose.translation();
             return std::hypot(std::hypot(c.x(), c.y()) - 1.0, c.z()) - rs;
           },
           steps_for(length, 8000));
  return r;
}

Body capsule(double radius, double length) {
  const Nurbs_surface_3 sphere = make_sphere(radius);
  auto [lower, upper] = split(sphere, Parameter_direction::V, 0.0);
  upper = transformed(upper, Rigid_pose_3(Mat3::Identity(), Vec3(0, 0, length)));
  Nurbs_surface_3 side = make_cylinder_side(radius, length);
  for (Nurbs_surface_3* s : {&lower, &upper, &side}) s->set_closed(true, false);
  orient_away_from(lower, Vec3::Zero());
  orient_away_from(upper, Vec3(0, 0, length));
  orient_away_from(side, Vec3(0, 0, 0.5 * length));
  return body_of({lower, side, upper}, "capsule");
}

Stress_result g1_capsule(Stress_length length) {
  // A small sphere circling a capsule (two hemispheres on a cylinder: G1 joins at the rims)
  // through the poles of both hemispheres.
  Stress_result r;
  r.name = "G1 joins: sphere around a capsule";
  r.reference = "closed form (point to segment) - r - r_s";
  const double rs = 0.25;
  const Body cap = capsule(1.0, 2.0), ball = make_sphere_body(rs);
  Path_motion mb{[](double t) -> Vec3 {
                   return Vec3(2.6 * std::sin(1.2 * t), 0.1 * std::sin(0.5 * t),
                               1.0 + 2.6 * std::cos(1.2 * t));
                 },
                 Mat3::Identity(), Vec3(-0.4, 0.2, 0.6), Vec3::Zero()};
  // The long run's error is 8.8e-10 (1.1e-14 before d493282): check_vacated certifies pairs
  // against the seeding tolerance (1e-9), so the neighbour across the join, closer than the
  // minimum held on it by less than that, is not seeded. A thousandth of that margin made it
  // exact, but left exact ties on the usual solve path re-solved every step (bench/RESULTS.md).
  r.tolerance = 1e-9;
  r.lost_threshold = 1e-4;
  // Once failed: with no patch transitions the tracker stayed on the G1 join while the nearest
  // point moved onto the cylinder side (from t = 0.981).
  run_pair(r, cap, ball, still(), mb,
           [rs](double, const Placement&, const Placement& pb) {
             return point_to_axis_segment(pb.pose.translation(), 2.0) - 1.0 - rs;
           },
           steps_for(length, 5300));
  return r;
}

// The paraboloid z = a (x^2 + y^2) over [-1, 1]^2 as one polynomial Bezier patch of degree n
// in both directions (exact: x = -1 + 2u has Bezier ordinates -1 + 2i/n, and x^2 has
// 1 - 4i/n + 4i(i-1)/(n(n-1))).
Nurbs_surface_3 paraboloid_patch(int n, double a) {
  std::vector<Point_3> poles;
  auto sq = [n](int i) { return 1.0 - 4.0 * i / n + 4.0 * i * (i - 1.0) / (n * (n - 1.0)); };
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j)
      poles.emplace_back(-1.0 + 2.0 * i / n, -1.0 + 2.0 * j / n, a * (sq(i) + sq(j)));
  return make_freeform(n, n, n + 1, n + 1, std::move(poles));
}

Stress_result degree12_paraboloid(Stress_length length) {
  Stress_result r;
  r.name = "degree 12: point over a paraboloid";
  r.reference = "closed form (cubic root, long double)";
  const double a = 0.3;
  Nurbs_surface_3 s = paraboloid_patch(12, a);
  orient_away_from(s, Vec3(0, 0, -1.0));  // the solid is below: outward is up, towards the point
  const Body para = body_of({s}, "paraboloid"), point = make_point_body();
  Path_motion mb{[](double t) -> Vec3 {
                   return Vec3(0.4 * std::cos(1.1 * t), 0.35 * std::sin(0.8 * t),
                               0.45 + 0.25 * std::sin(0.6 * t));
                 },
                 Mat3::Identity(), Vec3::Zero(), Vec3::Zero()};
  r.tolerance = 1e-9;
  r.lost_threshold = 1e-4;
  run_pair(r, para, point, still(), mb,
           [a](double, const Placement&, const Placement& pb) {
             return point_to_paraboloid(pb.pose.translation(), a);
           },
           steps_for(length, 3000));
  return r;
}

// One rational biquadratic Bezier patch covering the sphere octant x, y, z >= 0 (a pole at
// one edge), its weights spread over [1e-3, 1e3] by the Moebius reparametrisation
// w_ij -> w_ij a^i b^j, which keeps the point set.
Nurbs_surface_3 octant_wide_weights(double r) {
  const double s = std::sqrt(0.5);
  const double lx[3] = {1, 1, 0}, ly[3] = {0, 1, 1}, lw[3] = {1, s, 1};
  const double mr[3] = {1, 1, 0}, mz[3] = {0, 1, 1}, mw[3] = {1, s, 1};
  const double a = std::sqrt(1e3), b = 1.0 / std::sqrt(1e3);
  std::vector<Point_3> poles;
  std::vector<double> weights;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      poles.emplace_back(r * lx[i] * mr[j], r * ly[i] * mr[j], r * mz[j]);
      weights.push_back(lw[i] * mw[j] * std::pow(a, i) * std::pow(b, j));
    }
  Nurbs_surface_3 patch = make_freeform(2, 2, 3, 3, std::move(poles), std::move(weights));
  orient_away_from(patch, Vec3::Zero());
  return patch;
}

Stress_result wide_weights(Stress_length length) {
  Stress_result r;
  r.name = "weights 1e-3 to 1e3: point over a sphere octant";
  r.reference = "closed form |c| - r";
  const Body octant = body_of({octant_wide_weights(1.0)}, "octant"), point = make_point_body();
  Path_motion mb{[](double t) -> Vec3 {
                   const Vec3 dir(1.0 + 0.6 * std::sin(t), 1.0 + 0.6 * std::cos(0.7 * t),
                                  1.0 + 0.5 * std::sin(1.3 * t));
                   return (1.5 + 0.3 * std::sin(0.4 * t)) * dir.normalized();
                 },
                 Mat3::Identity(), Vec3::Zero(), Vec3::Zero()};
  r.tolerance = 1e-9;
  r.lost_threshold = 1e-4;
  run_pair(r, octant, point, still(), mb,
           [](double, const Placement&, const Placement& pb) {
             return pb.pose.translation().norm() - 1.0;
           },
           steps_for(length, 3000));
  return r;
}

Stress_result random_placements(Stress_length length, std::uint64_t seed) {
  // Random ellipsoid pairs (axes in [0.3, 3]), random orientations and spins; B circles A on a
  // random plane at a random clearance.
  Stress_result r;
  r.name = "random placements: 8 ellipsoid pairs";
  r.reference = "Ellipsoid_distance certificate";
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> axis(0.3, 3.0), gap(0.05, 2.0), rate(0.1, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  auto random_rotation = [&] {
    Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
    return Mat3(q.normalized().toRotationMatrix());
  };
  double worst_size = 0.0;
  r.tolerance = 1e-9 * 3.0;
  r.lost_threshold = 1e-4 * 3.0;
  for (int k = 0; k < 8; ++k) {
    const Vec3 axes_a(axis(rng), axis(rng), axis(rng)), axes_b(axis(rng), axis(rng), axis(rng));
    worst_size = std::max({worst_size, axes_a.maxCoeff(), axes_b.maxCoeff()});
    const double radius = axes_a.maxCoeff() + axes_b.maxCoeff() + gap(rng);
    const Mat3 plane = random_rotation();
    const double w = rate(rng);
    const Body a = make_ellipsoid_body(axes_a.x(), axes_a.y(), axes_a.z());
    const Body b = make_ellipsoid_body(axes_b.x(), axes_b.y(), axes_b.z());
    const Path_motion ma{[](double) -> Vec3 { return Vec3::Zero(); }, random_rotation(),
                         Vec3(g(rng), g(rng), g(rng)), Vec3::Zero()};
    const Path_motion mb{[=](double t) -> Vec3 {
                           return plane * Vec3(radius * std::cos(w * t), radius * std::sin(w * t), 0.0);
                         },
                         random_rotation(), Vec3(g(rng), g(rng), g(rng)), Vec3::Zero()};
    Stress_result one = r;
    one.steps = 0;
    one.max_error = 0.0;
    one.nan_count = one.lost_count = 0;
    one.seconds = 0.0;
    run_pair(one, a, b, ma, mb, Ellipsoid_reference{axes_a, axes_b}, steps_for(length, 600));
    r.steps += one.steps;
    r.max_error = std::max(r.max_error, one.max_error);
    r.nan_count += one.nan_count;
    r.lost_count += one.lost_count;
    r.seconds += one.seconds;
  }
  return r;
}

}  // namespace

std::vector<std::string> stress_case_names() {
  return {"near_parallel_sphere", "near_parallel_planes", "grazing_sphere", "grazing_ellipsoid",
          "poles_point", "poles_ellipsoids", "pole_at_contact",
          "c0_disk_rim", "c0_cylinder", "g1_capsule", "degree12",
          "wide_weights", "offset_1e6", "scale_1e-6", "drift", "random"};
}

Stress_result run_stress_case(const std::string& name, Stress_length length, std::uint64_t seed) {
  if (name == "near_parallel_sphere") return near_parallel_big_sphere(length);
  if (name == "near_parallel_planes") return near_parallel_tilted_planes(length);
  if (name == "grazing_sphere")
    return grazing_sphere(length, rotation(Vec3(1, 1, 0), 0.7), "grazing: sphere sliding at +-1e-9");
  if (name == "pole_at_contact") {
    // The same with the sphere's south pole (a collapsed edge) at the contact point at t = 0:
    // the contact point has to leave the pole in the normal form.
    return grazing_sphere(length, Mat3::Identity(), "poles: sphere pole at contact");
  }
  if (name == "grazing_ellipsoid") return grazing_ellipsoid(length);
  if (name == "poles_point") return poles_point_over_sphere(length);
  if (name == "poles_ellipsoids") return poles_ellipsoids(length);
  if (name == "c0_disk_rim") return c0_disk_rim(length);
  if (name == "c0_cylinder") return c0_cylinder(length);
  if (name == "g1_capsule") return g1_capsule(length);
  if (name == "degree12") return degree12_paraboloid(length);
  if (name == "wide_weights") return wide_weights(length);
  if (name == "offset_1e6")
    return seed_ellipsoids("coordinates offset by 1e6: seed ellipsoids", length, 1.0,
                           Vec3(1e6, -1e6, 1e6), 3000);
  if (name == "scale_1e-6")
    return seed_ellipsoids("models at 1e-6 scale: seed ellipsoids", length, 1e-6, Vec3::Zero(),
                           3000);
  if (name == "drift") {
    // 10^4 steps short, 10^6 long: no error may accumulate over the run.
    return seed_ellipsoids("drift: seed ellipsoids on an orbit", length, 1.0, Vec3::Zero(), 10000);
  }
  if (name == "random") return random_placements(length, seed);
  throw std::invalid_argument("unknown stress case '" + name + "'");
}

}  // namespace extremal::experiments
