#include "kernel/Rigid_pose_3.h"

#include <cmath>
#include <sstream>

#include "kernel/Error.h"

namespace extremal {

Rigid_pose_3::Rigid_pose_3(const Mat3& rotation, const Vec3& translation)
    : m_rotation(rotation), m_translation(translation) {
  if (!m_rotation.allFinite() || !m_translation.allFinite())
    throw Invalid_input("pose: rotation or translation is not finite");
  const double err = (m_rotation * m_rotation.transpose() - Mat3::Identity()).norm();
  if (err > 1e-9 || m_rotation.determinant() < 0.0) {
    std::ostringstream os;
    os << "pose: rotation is not a proper orthonormal matrix (|R R^T - I| = " << err << ")";
    throw Invalid_input(os.str());
  }
}

Rigid_pose_3 Rigid_pose_3::from_quaternion(const Vec3& translation, double qw, double qx,
                                           double qy, double qz) {
  Eigen::Quaterniond q(qw, qx, qy, qz);
  const double n = q.norm();
  if (!std::isfinite(n) || n < 1e-12)
    throw Invalid_input("pose: quaternion must be finite and non-zero");
  q.coeffs() /= n;
  return Rigid_pose_3(q.toRotationMatrix(), translation);
}

Rigid_pose_3 Rigid_pose_3::inverse() const {
  Rigid_pose_3 r;
  r.m_rotation = m_rotation.transpose();
  r.m_translation = -(r.m_rotation * m_translation);
  return r;
}

Rigid_pose_3 Rigid_pose_3::operator*(const Rigid_pose_3& other) const {
  Rigid_pose_3 r;
  r.m_rotation = m_rotation * other.m_rotation;
  r.m_translation = m_rotation * other.m_translation + m_translation;
  return r;
}

Rigid_pose_3 advance(const Rigid_pose_3& X_WA, const Twist_3& twist, double dt) {
  const Vec3 rotvec = twist.angular * dt;
  const double angle = rotvec.norm();
  Mat3 R = X_WA.rotation();
  if (angle > 0.0) R = Eigen::AngleAxisd(angle, rotvec / angle).toRotationMatrix() * R;
  // Re-orthonormalise so long integrations do not drift off SO(3).
  Eigen::Quaterniond q(R);
  q.normalize();
  return Rigid_pose_3(q.toRotationMatrix(), X_WA.translation() + twist.linear * dt);
}

Nurbs_surface_3 transformed(const Nurbs_surface_3& s, const Rigid_pose_3& X) {
  std::vector<Point_3> poles;
  poles.reserve(s.poles().size());
  for (const auto& p : s.poles()) poles.push_back(X(p));
  Nurbs_surface_3 r(s.degree_u(), s.degree_v(), s.number_of_poles_u(), s.number_of_poles_v(),
                    std::move(poles), s.knots_u(), s.knots_v(), s.weights());
  r.set_outward_sign(s.outward_sign());
  r.set_closed(s.is_closed_u(), s.is_closed_v());
  return r;
}

Nurbs_curve_3 transformed(const Nurbs_curve_3& c, const Rigid_pose_3& X) {
  std::vector<Point_3> poles;
  poles.reserve(c.poles().size());
  for (const auto& p : c.poles()) poles.push_back(X(p));
  Nurbs_curve_3 r(c.degree(), std::move(poles), c.knots(), c.weights());
  r.set_closed(c.is_closed());
  return r;
}

Bbox_3 transformed(const Bbox_3& box, const Rigid_pose_3& X) {
  Bbox_3 out;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 c((corner & 1) ? box.xmax() : box.xmin(), (corner & 2) ? box.ymax() : box.ymin(),
                 (corner & 4) ? box.zmax() : box.zmin());
    out += to_point(X.apply_point(c)).bbox();
  }
  return out;
}

}  // namespace extremal
