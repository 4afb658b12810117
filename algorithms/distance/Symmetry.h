// Centres and axes of rotational symmetry of faces and curves, and the bounds they give the
// global distance solver where two bodies are concentric or coaxial (a shaft in its bore, a
// sphere in a spherical socket, a probe on a hole's axis).
//
// There the distance is reached along a whole circle, band or sphere of equal minima, and the
// hull bounds of sub-patches close on it only quadratically in their size, in every direction
// along the continuum: certifying 1e-9 would take about 1e9 sub-patch pairs. The distance of a
// point to a centre or an axis is 1-Lipschitz, so
//   |x - y| >= |rho(x) - rho(y)|,
// and rho's range over a rational Bezier sub-patch is tight: rho^2 = N / W with N = |w (P - c)|^2
// (its part across the axis) and W = w^2, both polynomials whose Bernstein coefficients bound
// the ratio (N - t W >= 0 wherever every coefficient of it is). On a sphere about the centre, or
// a cylinder about its axis, N = r^2 W exactly, so the bound is exact on every sub-patch.
#pragma once

#include <Eigen/Core>

#include "kernel/Nurbs_curve_3.h"
#include "kernel/Nurbs_surface_3.h"
#include "kernel/Rigid_pose_3.h"
#include "kernel/Types.h"

namespace extremal {

// A point (a sphere's centre) or a line (the axis of a cylinder, cone, torus, revolved surface,
// disc or circle) about which a face or curve is symmetric.
struct Symmetry {
  enum class Kind { None, Centre, Axis };
  Kind kind = Kind::None;
  Vec3 point = Vec3::Zero();      // the centre, or a point of the axis
  Vec3 direction = Vec3::Zero();  // the axis' unit direction
  bool any() const { return kind != Kind::None; }
  // x less the centre, or less its foot on the axis: its norm is x's distance to the symmetry.
  Vec3 offset(const Vec3& x) const {
    const Vec3 d = x - point;
    return kind == Kind::Axis ? Vec3(d - d.dot(direction) * direction) : d;
  }
  // The same symmetry of the element placed by X.
  Symmetry placed(const Rigid_pose_3& X) const;
};

// Found by sampling: iso-curves across one parameter direction that are circles about one axis
// (then a sphere when their points are equidistant from one point of it), or a curve that is a
// circle (arc). Within 1e-9 of the element's size; None otherwise. Only decides where the
// bounds are worth trying: radial_range is sound about any point or line.
Symmetry find_symmetry(const Nurbs_surface_3& s);
Symmetry find_symmetry(const Nurbs_curve_3& c);
// How far apart two centres or axes found within `box` may be and still be one: 1e-9 of its
// size, and the rounding of its coordinates.
double symmetry_tolerance(const Bbox_3& box);

// Bounds [lo, hi] on the distance to s's centre or axis of the points of the rational Bezier
// piece with homogeneous poles `net` (nu x nv, row-major along u, positive weights), widened by
// the rounding. False (nothing set) for a net above degree k_max_radial_degree in a direction.
constexpr int k_max_radial_degree = 12;
bool radial_range(const Eigen::Vector4d* net, int nu, int nv, const Symmetry& s, double& lo,
                  double& hi);

}  // namespace extremal
