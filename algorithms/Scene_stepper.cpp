#include "algorithms/Scene_stepper.h"

#include "kernel/Error.h"

namespace extremal {

Scene_stepper::Scene_stepper(std::vector<Scene_stepper_body> bodies,
                             std::vector<std::pair<int, int>> pairs,
                             const Body_pair_options& options)
    : m_bodies(std::move(bodies)), m_pairs(std::move(pairs)) {
  const int n = static_cast<int>(m_bodies.size());
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
    m_poses[i] = m_bodies[i].motion->pose_at(t);
    m_twists[i] = m_bodies[i].motion->twist_at(t);
  }
  for (std::size_t k = 0; k < m_pairs.size(); ++k) {
    const auto [a, b] = m_pairs[k];
    m_reports[k] = m_trackers[k].step(t, m_poses[a], m_twists[a], m_poses[b], m_twists[b], dt);
  }
  return m_reports;
}

}  // namespace extremal
