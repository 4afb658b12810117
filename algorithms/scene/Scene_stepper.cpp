#include "algorithms/scene/Scene_stepper.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "kernel/Error.h"

namespace extremal {

struct Scene_stepper::Parallel {
  explicit Parallel(int threads) : arena(threads) {}
  tbb::task_arena arena;
};

void body_pose_at(const Scene_stepper_body& b, double t, Rigid_pose_3& pose, Twist_3& twist) {
  const Rigid_pose_3 entry = b.motion->pose_at(t);
  const Twist_3 v = b.motion->twist_at(t);
  pose = entry * b.body->placement;
  twist.angular = v.angular;
  twist.linear = v.velocity_at(pose.translation(), entry);
}

Scene_stepper::Scene_stepper(std::vector<Scene_stepper_body> bodies,
                             std::vector<std::pair<int, int>> pairs,
                             const Body_pair_options& options, const Scene_stepper_options& stepper)
    : m_bodies(std::move(bodies)), m_pairs(std::move(pairs)) {
  const int n = static_cast<int>(m_bodies.size());
  m_models.resize(m_bodies.size());
  m_trackers.reserve(m_pairs.size());
  for (const auto& [a, b] : m_pairs) {
    EXTREMAL_PRECONDITION(a >= 0 && a < n && b >= 0 && b < n && a != b);
    // One model per watched body, shared by its pairs; unwatched bodies cost nothing.
    for (int i : {a, b})
      if (!m_models[i]) m_models[i] = std::make_shared<const Tracking_model>(*m_bodies[i].body);
    m_trackers.emplace_back(m_models[a], m_models[b], options);
    m_still.push_back(m_bodies[a].motion->is_static() && m_bodies[b].motion->is_static());
  }
  m_reports.resize(m_pairs.size());
  m_poses.resize(m_bodies.size());
  m_twists.resize(m_bodies.size());
  set_threads(stepper.threads);
}

Scene_stepper::~Scene_stepper() = default;

void Scene_stepper::set_threads(int threads) {
  EXTREMAL_PRECONDITION_MSG(threads >= 1, "threads must be >= 1, got " << threads);
  m_threads = threads;
  m_parallel.reset();
  if (threads > 1) m_parallel = std::make_unique<Parallel>(threads);
}

const std::vector<Pair_report>& Scene_stepper::step(double t, double dt) {
  for (std::size_t i = 0; i < m_bodies.size(); ++i) {
    if (!m_models[i]) continue;  // in no watched pair
    if (m_stepped && m_bodies[i].motion->is_static()) continue;  // (where it was)
    body_pose_at(m_bodies[i], t, m_poses[i], m_twists[i]);
  }
  auto step_pair = [&](std::size_t k) {
    if (m_stepped && m_still[k]) {
      m_reports[k].time = t;
      return;
    }
    const auto [a, b] = m_pairs[k];
    m_reports[k] = m_trackers[k].step(t, m_poses[a], m_twists[a], m_poses[b], m_twists[b], dt);
  };
  if (m_parallel && m_pairs.size() > 1) {
    m_parallel->arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, m_pairs.size(), 1),
                        [&](const tbb::blocked_range<std::size_t>& range) {
                          for (std::size_t k = range.begin(); k != range.end(); ++k) step_pair(k);
                        });
    });
  } else {
    for (std::size_t k = 0; k < m_pairs.size(); ++k) step_pair(k);
  }
  m_stepped = true;
  return m_reports;
}

}  // namespace extremal
