// Rigid motions over time (docs/cli.md scene motions): static, constant twist, keyframes
// (linear position, shortest-arc slerp, constant velocities on each segment; at rest outside
// the keyframes) and tables of poses (velocities by differences).
#pragma once

#include <vector>

#include "kernel/Rigid_pose_3.h"

namespace extremal {

struct Keyframe {
  double t = 0.0;
  Rigid_pose_3 pose;
};

class Motion {
 public:
  enum class Type { Static, Twist, Keyframes, Table };

  // At rest in `pose`.
  static Motion still(const Rigid_pose_3& pose);
  // p(t) = p0 + v (t - t0), R(t) = exp([w]x (t - t0)) R0.
  static Motion twist(const Rigid_pose_3& pose_at_t0, const Twist_3& twist, double t0);
  // Keyframes with strictly increasing times (Invalid_input otherwise, naming the index).
  // Tables are keyframes too, at their rows; the type is kept for reporting.
  static Motion keyframes(std::vector<Keyframe> frames, Type type = Type::Keyframes);

  Type type() const { return m_type; }
  Rigid_pose_3 pose_at(double t) const;
  // World velocity of the body origin and angular velocity at t. On a keyframe, the velocity
  // of the segment that starts there.
  Twist_3 twist_at(double t) const;
  bool is_static() const { return m_type == Type::Static; }
  const std::vector<Keyframe>& frames() const { return m_frames; }

 private:
  Type m_type = Type::Static;
  Rigid_pose_3 m_pose;  // static pose, or the pose at m_t0 for a twist
  Twist_3 m_twist;
  double m_t0 = 0.0;
  std::vector<Keyframe> m_frames;
  std::vector<Twist_3> m_segment_twists;  // constant twist of each keyframe segment
};

}  // namespace extremal
