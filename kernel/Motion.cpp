#include "kernel/Motion.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "kernel/Error.h"

namespace extremal {

Motion Motion::still(const Rigid_pose_3& pose) {
  Motion m;
  m.m_pose = pose;
  return m;
}

Motion Motion::twist(const Rigid_pose_3& pose_at_t0, const Twist_3& twist, double t0) {
  if (!twist.linear.allFinite() || !twist.angular.allFinite())
    throw Invalid_input("twist motion: velocity and angular velocity must be finite");
  Motion m;
  m.m_type = twist.is_zero() ? Type::Static : Type::Twist;
  m.m_pose = pose_at_t0;
  m.m_twist = twist;
  m.m_t0 = t0;
  return m;
}

Motion Motion::keyframes(std::vector<Keyframe> frames, Type type) {
  if (frames.empty()) throw Invalid_input("keyframes: at least one keyframe is needed");
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (!std::isfinite(frames[i].t)) {
      std::ostringstream os;
      os << "keyframes[" << i << "].t: not a finite number";
      throw Invalid_input(os.str());
    }
    if (i > 0 && !(frames[i].t > frames[i - 1].t)) {
      std::ostringstream os;
      os << "keyframes[" << i << "].t: times must increase";
      throw Invalid_input(os.str());
    }
  }
  Motion m;
  m.m_type = type;
  m.m_frames = std::move(frames);
  // Each segment is a constant twist: relative rotation on the shortest arc over the segment.
  for (std::size_t i = 0; i + 1 < m.m_frames.size(); ++i) {
    const Keyframe& a = m.m_frames[i];
    const Keyframe& b = m.m_frames[i + 1];
    const double T = b.t - a.t;
    Eigen::Quaterniond qa = a.pose.quaternion(), qb = b.pose.quaternion();
    if (qa.dot(qb) < 0.0) qb.coeffs() = -qb.coeffs();
    const Eigen::AngleAxisd rel(qb * qa.conjugate());
    double angle = rel.angle();
    Vec3 axis = rel.axis();
    if (angle > 3.14159265358979323846) {
      angle = 2 * 3.14159265358979323846 - angle;
      axis = -axis;
    }
    Twist_3 tw;
    tw.linear = (b.pose.translation() - a.pose.translation()) / T;
    tw.angular = axis * (angle / T);
    m.m_segment_twists.push_back(tw);
  }
  m.m_pose = m.m_frames.front().pose;
  return m;
}

Rigid_pose_3 Motion::pose_at(double t) const {
  switch (m_type) {
    case Type::Static: return m_pose;
    case Type::Twist: return advance(m_pose, m_twist, t - m_t0);
    case Type::Keyframes:
    case Type::Table: {
      if (t <= m_frames.front().t) return m_frames.front().pose;
      if (t >= m_frames.back().t) return m_frames.back().pose;
      const auto it = std::upper_bound(m_frames.begin(), m_frames.end(), t,
                                       [](double x, const Keyframe& k) { return x < k.t; });
      const std::size_t i = static_cast<std::size_t>(it - m_frames.begin()) - 1;
      return advance(m_frames[i].pose, m_segment_twists[i], t - m_frames[i].t);
    }
  }
  return m_pose;
}

Twist_3 Motion::twist_at(double t) const {
  switch (m_type) {
    case Type::Static: return Twist_3{};
    case Type::Twist: return m_twist;
    case Type::Keyframes:
    case Type::Table: {
      if (t < m_frames.front().t || t >= m_frames.back().t) return Twist_3{};
      const auto it = std::upper_bound(m_frames.begin(), m_frames.end(), t,
                                       [](double x, const Keyframe& k) { return x < k.t; });
      return m_segment_twists[static_cast<std::size_t>(it - m_frames.begin()) - 1];
    }
  }
  return Twist_3{};
}

}  // namespace extremal
