// Certified distance between two disjoint ellipsoids, used as ground truth. Ellipsoid E with
// centre c, rotation R and semi-axes s has support function h(n) = n.c + sqrt(n^T P n),
// P = R diag(s^2) R^T. For every unit n,
//   g(n) = n.(c_B - c_A) - sqrt(n^T P_A n) - sqrt(n^T P_B n)
// is a lower bound on the distance, and the support points x_A(n), x_B(-n) give an upper bound
// |x_B - x_A|; at the maximiser of g they meet (to about 1e-15 relative).
#pragma once

#include "kernel/Rigid_pose_3.h"
#include "kernel/Types.h"

namespace extremal {

struct Ellipsoid {
  Rigid_pose_3 pose;  // centre and axes in the world
  Vec3 semi_axes = Vec3::Ones();
};

struct Ellipsoid_distance_result {
  double lower_bound = 0.0;
  double upper_bound = 0.0;
  Vec3 point_a = Vec3::Zero();
  Vec3 point_b = Vec3::Zero();
  Vec3 normal = Vec3::Zero();  // unit, from A to B
  int iterations = 0;
  bool separated = false;  // false: the ellipsoids touch or overlap (bounds not certified)
};

// Maximises g by Newton's method on the unit sphere, from `start_normal` if non-zero.
Ellipsoid_distance_result ellipsoid_distance(const Ellipsoid& A, const Ellipsoid& B,
                                             const Vec3& start_normal = Vec3::Zero());

}  // namespace extremal
