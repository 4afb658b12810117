#include "algorithms/Scene_stepper.h"

#include "kernel/Error.h"

namespace extremal {

Scene_stepper::Scene_stepper(std::vector<Scene_stepper_body> bodies,
                             std::vector<std::pair<int, int>> pairs,
                             const Body_pair_options& options)
    : m_bodies(std::move(bodies)), m_pairs(std::move(pairs)) {
  const int n = static_cast<int>(m_bodies.size());
  for (const auto& b : m_bodies)
    if (!b.body->is_point && b.body->faces.empty() && b.body->curves.empty())
      throw Invalid_input("body '" + b.body->name +
                          "' has no NURBS faces or curves (mesh bodies are not tracked yet)");
  m_trackers.reserve(m_pairs.size());
  for (const auto& [a, b] : m_pairs) {
    EXTREMAL_PRECONDITION(a >= 0 && a < n && b >= 0 && b < n && a != b);
    m_trackers.emplace_back(*m_bodies[a].body, *m_bodies[b].body, options);
  }
  m_reports.resize(m_pairs.size());
  m_poses.resize(m_bodies.size());
  m_twists.resize(m_bodies.size());
}

const std::vector<Pair_report>& Scene_stepper::step(double t, double dt) {
  for (std::size_t i = 0; i < m_bodies.size(); ++i) {
    // The body frame sits at the entry's pose times the body's placement in its file; the
    // twist's linear part is the velocity of that frame's origin.
    const Rigid_pose_3 entry = m_bodies[i].motion->pose_at(t);
    const Twist_3 v = m_bodies[i].motion->twist_at(t);
    m_poses[i] = entry * m_bodies[i].body->placement;
    m_twists[i].angular = v.angular;
    m_twists[i].linear = v.linear + v.angular.cross(m_poses[i].translation() - entry.translation());
  }
  for (std::size_t k = 0; k < m_pairs.size(); ++k) {
    const auto [a, b] = m_pairs[k];
    m_reports[k] = m_trackers[k].step(t, m_poses[a], m_twists[a], m_poses[b], m_twists[b], dt);
  }
  return m_reports;
}

}  // namespace extremal
