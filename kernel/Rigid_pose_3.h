// Rigid placements and velocities. X_WA is the pose of body A in the world: p_W = R p_A + t.
#pragma once

#include <Eigen/Geometry>

#include "kernel/Nurbs_curve_3.h"
#include "kernel/Nurbs_surface_3.h"
#include "kernel/Types.h"

namespace extremal {

class Rigid_pose_3 {
 public:
  Rigid_pose_3() : m_rotation(Mat3::Identity()), m_translation(Vec3::Zero()) {}
  // Throws Invalid_input if the rotation is not orthonormal (1e-9) or anything is not finite.
  Rigid_pose_3(const Mat3& rotation, const Vec3& translation);
  // Unit quaternion, w first (normalised here; a zero or non-finite one throws Invalid_input).
  static Rigid_pose_3 from_quaternion(const Vec3& translation, double qw, double qx, double qy,
                                      double qz);

  const Mat3& rotation() const { return m_rotation; }
  const Vec3& translation() const { return m_translation; }
  Eigen::Quaterniond quaternion() const { return Eigen::Quaterniond(m_rotation); }

  Vec3 apply_point(const Vec3& p) const { return m_rotation * p + m_translation; }
  Vec3 apply_vector(const Vec3& v) const { return m_rotation * v; }
  Point_3 operator()(const Point_3& p) const { return to_point(apply_point(to_vec3(p))); }
  Vector_3 operator()(const Vector_3& v) const { return to_vector(apply_vector(to_vec3(v))); }

  Rigid_pose_3 inverse() const;
  // (X_WA * X_AB) maps B's frame to the world.
  Rigid_pose_3 operator*(const Rigid_pose_3& other) const;

 private:
  Mat3 m_rotation;
  Vec3 m_translation;
};

// Velocity of a rigid body: v is the world velocity of the body origin, w the world angular
// velocity. A material point at world position x moves at v + w x (x - origin).
struct Twist_3 {
  Vec3 linear = Vec3::Zero();
  Vec3 angular = Vec3::Zero();

  Vec3 velocity_at(const Vec3& p_W, const Rigid_pose_3& X_WA) const {
    return linear + angular.cross(p_W - X_WA.translation());
  }
  bool is_zero() const { return linear.isZero(0.0) && angular.isZero(0.0); }
};

// The pose after moving with a constant twist for time dt:
// R(dt) = exp([w]x dt) R, t(dt) = t + v dt.
Rigid_pose_3 advance(const Rigid_pose_3& X_WA, const Twist_3& twist, double dt);

// The patch, curve or box placed by a pose. Weights are unchanged: a rigid map of the control
// points maps the NURBS exactly.
Nurbs_surface_3 transformed(const Nurbs_surface_3& s, const Rigid_pose_3& X);
Nurbs_curve_3 transformed(const Nurbs_curve_3& c, const Rigid_pose_3& X);
Bbox_3 transformed(const Bbox_3& box, const Rigid_pose_3& X);

}  // namespace extremal
