#include "algorithms/distance/Ellipsoid_distance.h"

#include <cmath>

#include <Eigen/Dense>

namespace extremal {

namespace {

Mat3 shape_matrix(const Ellipsoid& e) {
  const Mat3& R = e.pose.rotation();
  return R * e.semi_axes.cwiseAbs2().asDiagonal() * R.transpose();
}

}  // namespace

Ellipsoid_distance_result ellipsoid_distance(const Ellipsoid& A, const Ellipsoid& B,
                                             const Vec3& start_normal) {
  const Mat3 PA = shape_matrix(A), PB = shape_matrix(B);
  const Vec3 c = B.pose.translation() - A.pose.translation();
  Vec3 n = start_normal.norm() > 0.0 ? start_normal.normalized() : c.normalized();
  Ellipsoid_distance_result r;
  auto g = [&](const Vec3& m) {
    return m.dot(c) - std::sqrt(m.dot(PA * m)) - std::sqrt(m.dot(PB * m));
  };
  double best = g(n);
  for (r.iterations = 0; r.iterations < 100; ++r.iterations) {
    const double sa = std::sqrt(n.dot(PA * n)), sb = std::sqrt(n.dot(PB * n));
    const Vec3 grad = c - PA * n / sa - PB * n / sb;
    const Mat3 H = -(PA / sa - (PA * n) * (PA * n).transpose() / (sa * sa * sa)) -
                   (PB / sb - (PB * n) * (PB * n).transpose() / (sb * sb * sb));
    // Riemannian Newton step on the sphere, in an orthonormal basis of the tangent plane.
    Vec3 e1 = n.unitOrthogonal();
    Vec3 e2 = n.cross(e1);
    Eigen::Matrix<double, 3, 2> T;
    T << e1, e2;
    const Eigen::Vector2d gt = T.transpose() * grad;
    const Eigen::Matrix2d Ht = T.transpose() * H * T - n.dot(grad) * Eigen::Matrix2d::Identity();
    Eigen::Vector2d step = -Ht.ldlt().solve(gt);
    if (!step.allFinite() || step.dot(gt) < 0.0) step = 0.1 * gt;  // not ascending: gradient
    // Backtrack until g does not decrease.
    double alpha = 1.0;
    Vec3 next = n;
    double value = best;
    for (int ls = 0; ls < 40; ++ls) {
      next = (n + alpha * (T * step)).normalized();
      value = g(next);
      if (value >= best) break;
      alpha *= 0.5;
    }
    const double moved = (next - n).norm();
    if (value >= best) {
      n = next;
      best = value;
    }
    if (moved < 1e-16 || gt.norm() < 1e-15 * (c.norm() + 1.0)) break;
  }
  const double sa = std::sqrt(n.dot(PA * n)), sb = std::sqrt(n.dot(PB * n));
  r.normal = n;
  r.point_a = A.pose.translation() + PA * n / sa;
  r.point_b = B.pose.translation() - PB * n / sb;
  r.lower_bound = best;
  r.upper_bound = (r.point_b - r.point_a).norm();
  r.separated = best > 0.0;
  return r;
}

}  // namespace extremal
