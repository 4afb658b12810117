// Geometric helpers the body-pair tracker's stages share: box sizes, keys of primitive pairs,
// the bound on how much closer a relative motion brings two boxes, parameters of a global
// result on a primitive, the error budget's floor. Not API.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include "algorithms/body_pair/Body_pair_options.h"
#include "algorithms/body_pair/Tracking_model.h"
#include "algorithms/body_pair/internal/Tuning.h"
#include "algorithms/distance/Penetration_depth.h"
#include "kernel/Rigid_pose_3.h"
#include "kernel/Types.h"

namespace extremal::internal {

using extremal::box_diagonal;

inline Bbox_3 inflate(const Bbox_3& b, double r) {
  return Bbox_3(b.xmin() - r, b.ymin() - r, b.zmin() - r, b.xmax() + r, b.ymax() + r, b.zmax() + r);
}

// How far parameters sit from the middle of their domain (0 at the centre, 1 at a corner).
inline double off_centre(const Feature& f, const double* p) {
  double s = 0.0;
  for (int i = 0; i < f.dimension(); ++i) {
    const double mid = 0.5 * (f.lower(i) + f.upper(i)), half = 0.5 * (f.upper(i) - f.lower(i));
    if (half > 0.0) s += ((p[i] - mid) / half) * ((p[i] - mid) / half);
  }
  return s;
}

// A candidate pair's key: primitive of A in the high half, of B in the low.
inline std::uint64_t pair_key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}
inline int key_a(std::uint64_t k) { return static_cast<int>(k >> 32); }
inline int key_b(std::uint64_t k) { return static_cast<int>(k & 0xffffffffu); }

// The relative motion from X0 to X1 (poses X_AB: B's frame in A's) for a primitive of A
// (body-frame box box_a) and one of B (box_b): the largest displacement of a point of B's box
// in A's frame (move_b) and of A's box in B's frame (move_a), and how much closer it can have
// brought the two, the smaller of those. Over the ball (c, r) that holds a box,
// |(R1 - R0) p + t1 - t0| <= |(R1 - R0) c + t1 - t0| + |R1 - R0|_F r. (Distances between
// rigid placements depend on the relative pose only, and change by at most the largest
// displacement of either side.)
struct Approach {
  double move_a = 0.0, move_b = 0.0, closer = 0.0;
  double most = 0.0;  // the larger of move_a and move_b (bounds either side's displacement)
};
inline Approach approach_bound(const Bbox_3& box_a, const Bbox_3& box_b, const Rigid_pose_3& X0,
                        const Rigid_pose_3& X1) {
  const Mat3 dR = X1.rotation() - X0.rotation();
  const double spin = dR.norm();  // Frobenius, >= the spectral norm
  const Vec3 ca(0.5 * (box_a.xmin() + box_a.xmax()), 0.5 * (box_a.ymin() + box_a.ymax()),
                0.5 * (box_a.zmin() + box_a.zmax()));
  const Vec3 cb(0.5 * (box_b.xmin() + box_b.xmax()), 0.5 * (box_b.ymin() + box_b.ymax()),
                0.5 * (box_b.zmin() + box_b.zmax()));
  const double ra = 0.5 * box_diagonal(box_a), rb = 0.5 * box_diagonal(box_b);
  const Vec3& t0 = X0.translation();
  const Vec3& t1 = X1.translation();
  const double move_b = (dR * cb + (t1 - t0)).norm() + spin * rb;
  // A in B's frame: X_BA = (R^T, -R^T t).
  const Vec3 dt_inverse = X0.rotation().transpose() * t0 - X1.rotation().transpose() * t1;
  const double move_a = (dR.transpose() * ca + dt_inverse).norm() + spin * ra;
  // Rounding of these products: a few ulps of the lengths involved.
  const double size = ca.norm() + ra + cb.norm() + rb + t0.norm() + t1.norm();
  const double rounding = 16.0 * std::numeric_limits<double>::epsilon() * size;
  Approach m;
  m.move_a = move_a + rounding;
  m.move_b = move_b + rounding;
  m.closer = std::min(m.move_a, m.move_b);
  m.most = std::max(m.move_a, m.move_b);
  return m;
}

// Whether two relative poses are equal to rounding (their difference no motion at all), for
// bodies of size `length`.
inline bool near_pose(const Rigid_pose_3& x, const Rigid_pose_3& y, double length) {
  return (x.rotation() - y.rotation()).cwiseAbs().maxCoeff() <= k_same_pose &&
         (x.translation() - y.translation()).cwiseAbs().maxCoeff() <= k_same_pose * length;
}

// Mesh triangles against triangles or the point: closed forms, no tracker.
// The least lower bound an apart row at distance d may carry and still be within the error
// budget (d - Error_budget::at(d), less the rounding of that difference).
inline double certified_floor(double d, const Error_budget& budget) {
  const double allowed = budget.at(d);
  return d - allowed - 4.0 * std::numeric_limits<double>::epsilon() * (std::abs(d) + allowed);
}

inline bool closed_form_pair(const Primitive& a, const Primitive& b) {
  const bool ta = a.kind == Primitive_kind::Triangle, tb = b.kind == Primitive_kind::Triangle;
  return (ta && (tb || b.kind == Primitive_kind::Point)) || (tb && a.kind == Primitive_kind::Point);
}

// A global result's parameters on a primitive (the global solver's triangles are degree 1 x 1
// patches with corners p0, p2 | p1, p2: (u, v) there is (u (1 - v), v) here).
inline void params_from_global(const Primitive& p, const std::array<double, 2>& q, double* out) {
  if (p.kind == Primitive_kind::Triangle) {
    out[0] = q[0] * (1.0 - q[1]);
    out[1] = q[1];
    return;
  }
  for (int k = 0; k < p.feature.dimension(); ++k) out[k] = q[k];
}

// A closed body through a sheet keeps the depth of the side it entered by: `side_A` is the
// normal, in A's frame, of the last reading apart (zero: none). Where the hulls' depth h is
// the other side's (the shallower, past half way), h becomes the depth along -h.normal when
// that is certified and a depth; true if it did (tests
// SheetDepth.ATurnedEllipsoidThroughAPlaneSpinningFastKeepsItsEntrySideWhenItsTrackerIsLost,
// Overlap.AClosedMeshThroughAnOpenMeshKeepsItsEntrySidesDepthWhileTheSurfacesMeet).
inline bool keep_entry_side(const Distance_hierarchy& HA, const Rigid_pose_3& X_WA,
                            const Distance_hierarchy& HB, const Rigid_pose_3& X_WB,
                            const Vec3& side_A, const Signed_distance_request& request,
                            Signed_distance_result& h) {
  if (!(side_A.norm() > 0.5) || !(h.normal.dot(X_WA.rotation() * side_A) < 0.0)) return false;
  const Signed_distance_result e = directional_signed_distance(HA, X_WA, HB, X_WB, -h.normal, request);
  if (!(e.is_certified() && e.distance <= 0.0 && e.element_a >= 0 && e.element_b >= 0)) return false;
  h = e;
  return true;
}

}  // namespace extremal::internal
