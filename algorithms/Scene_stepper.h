// Steps a scene of moving bodies through time and reports the extremal distance of each
// watched body pair at every step.
#pragma once

#include <utility>
#include <vector>

#include "algorithms/Body_pair_tracker.h"
#include "kernel/Body.h"
#include "kernel/Motion.h"

namespace extremal {

struct Scene_stepper_body {
  const Body* body;      // must outlive the stepper
  const Motion* motion;  // must outlive the stepper; the body sits at motion * body->placement
};

class Scene_stepper {
 public:
  Scene_stepper(std::vector<Scene_stepper_body> bodies, std::vector<std::pair<int, int>> pairs,
                const Body_pair_options& options);

  // Throws Invalid_input naming a body the trackers cannot work on (a mesh body).
  // The reports of all watched pairs at time t, then the trackers advance over [t, t + dt].
  const std::vector<Pair_report>& step(double t, double dt);

  const std::vector<std::pair<int, int>>& pairs() const { return m_pairs; }

 private:
  std::vector<Scene_stepper_body> m_bodies;
  std::vector<std::pair<int, int>> m_pairs;
  std::vector<Body_pair_tracker> m_trackers;
  std::vector<Pair_report> m_reports;
  std::vector<Rigid_pose_3> m_poses;
  std::vector<Twist_3> m_twists;
};

}  // namespace extremal
