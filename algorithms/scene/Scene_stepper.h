// Steps a scene of moving bodies through time and reports the extremal distance of each
// watched body pair at every step.
#pragma once

#include <memory>
#include <utility>
#include <vector>

#include "algorithms/body_pair/Body_pair_tracker.h"
#include "algorithms/body_pair/Tracking_model.h"
#include "kernel/Body.h"
#include "kernel/Motion.h"

namespace extremal {

struct Scene_stepper_body {
  const Body* body;      // must outlive the stepper
  const Motion* motion;  // must outlive the stepper; the body sits at motion * body->placement
};

// Body `b`'s frame at time t: its motion's pose times its placement in its file, and its twist
// with the linear part the velocity of that frame's origin.
void body_pose_at(const Scene_stepper_body& b, double t, Rigid_pose_3& pose, Twist_3& twist);

struct Scene_stepper_options {
  // Worker threads stepping the watched pairs (TBB); 1 steps them in this thread. Every pair
  // is stepped by one thread with its own state, so the reports are bit-identical to one
  // thread's whatever the count.
  int threads = 1;
};

class Scene_stepper {
 public:
  // Bodies may be NURBS (imported or generated), points or meshes. Throws Invalid_input for an
  // empty body and Precondition_violation for a bad pair or thread count.
  Scene_stepper(std::vector<Scene_stepper_body> bodies, std::vector<std::pair<int, int>> pairs,
                const Body_pair_options& options, const Scene_stepper_options& stepper = {});
  ~Scene_stepper();

  // The reports of all watched pairs at time t, then the trackers advance over [t, t + dt].
  const std::vector<Pair_report>& step(double t, double dt);

  const std::vector<std::pair<int, int>>& pairs() const { return m_pairs; }
  // The work pair k's tracker has done since its start.
  const Pair_statistics& statistics(std::size_t k) const { return m_trackers[k].statistics(); }
  // Threads used by step() (>= 1).
  void set_threads(int threads);
  int threads() const { return m_threads; }

 private:
  std::vector<Scene_stepper_body> m_bodies;
  std::vector<std::pair<int, int>> m_pairs;
  std::vector<std::shared_ptr<const Tracking_model>> m_models;  // per body, built if watched
  std::vector<Body_pair_tracker> m_trackers;
  // Pairs of two static bodies are stepped once: their report stands, with the time updated.
  std::vector<char> m_still;
  bool m_stepped = false;
  std::vector<Pair_report> m_reports;
  std::vector<Rigid_pose_3> m_poses;
  std::vector<Twist_3> m_twists;
  int m_threads = 1;
  struct Parallel;  // the TBB arena
  std::unique_ptr<Parallel> m_parallel;
};

}  // namespace extremal
