#include "algorithms/scene/Scene_stepper.h"

#include <algorithm>
#include <chrono>

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

namespace {

std::string body_name(const std::vector<Scene_stepper_body>& bodies, int i) {
  const std::string& name = bodies[static_cast<std::size_t>(i)].name;
  return name.empty() ? "body " + std::to_string(i) : name;
}

}  // namespace

Scene_stepper::Scene_stepper(std::vector<Scene_stepper_body> bodies,
                             std::vector<std::pair<int, int>> pairs,
                             const Body_pair_options& options, const Scene_stepper_options& stepper)
    : m_bodies(std::move(bodies)), m_pairs(std::move(pairs)), m_options(stepper) {
  EXTREMAL_PRECONDITION_MSG(stepper.block_steps >= 1,
                            "block_steps must be >= 1, got " << stepper.block_steps);
  const int n = static_cast<int>(m_bodies.size());
  m_models.resize(m_bodies.size());
  m_trackers.reserve(m_pairs.size());
  for (std::size_t k = 0; k < m_pairs.size(); ++k) {
    const auto [a, b] = m_pairs[k];
    EXTREMAL_PRECONDITION(a >= 0 && a < n && b >= 0 && b < n && a != b);
    try {
      // One model per watched body, shared by its pairs; unwatched bodies cost nothing.
      for (int i : {a, b})
        if (!m_models[i]) m_models[i] = std::make_shared<const Tracking_model>(*m_bodies[i].body);
      m_trackers.emplace_back(m_models[a], m_models[b], options);
    } catch (const Invalid_input& e) {
      rethrow_for_pair(k, e);
    }
  }
  m_reports.resize(m_pairs.size());
  set_threads(stepper.threads);
}

Scene_stepper::~Scene_stepper() = default;

void Scene_stepper::rethrow_for_pair(std::size_t k, const std::exception& e) const {
  const auto [a, b] = m_pairs[k];
  std::string prefix = m_options.source.empty() ? std::string() : m_options.source + ": ";
  throw Invalid_input(prefix + "pair " + body_name(m_bodies, a) + " - " + body_name(m_bodies, b) +
                      ": " + e.what());
}

void Scene_stepper::set_threads(int threads) {
  EXTREMAL_PRECONDITION_MSG(threads >= 1, "threads must be >= 1, got " << threads);
  m_options.threads = threads;
  m_parallel.reset();
  if (threads > 1) m_parallel = std::make_unique<Parallel>(threads);
}

template <class F>
void Scene_stepper::for_each_pair(F f) {
  if (m_parallel && m_pairs.size() > 1) {
    m_parallel->arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, m_pairs.size(), 1),
                        [&](const tbb::blocked_range<std::size_t>& range) {
                          for (std::size_t k = range.begin(); k != range.end(); ++k) f(k);
                        });
    });
  } else {
    for (std::size_t k = 0; k < m_pairs.size(); ++k) f(k);
  }
}

void Scene_stepper::place_bodies(int first, int count, const std::function<double(int)>& time_of) {
  if (m_poses.size() < static_cast<std::size_t>(count)) {
    m_poses.resize(count, std::vector<Rigid_pose_3>(m_bodies.size()));
    m_twists.resize(count, std::vector<Twist_3>(m_bodies.size()));
  }
  for (std::size_t b = 0; b < m_bodies.size(); ++b) {
    if (!m_models[b]) continue;  // in no watched pair
    const bool fixed = m_bodies[b].motion->is_static();
    for (int i = 0; i < count; ++i) {
      if (fixed && (i > 0 || m_placed)) {  // (where it was)
        m_poses[i][b] = m_poses[0][b];
        m_twists[i][b] = m_twists[0][b];
        continue;
      }
      body_pose_at(m_bodies[b], time_of(first + i), m_poses[i][b], m_twists[i][b]);
    }
  }
  m_placed = true;
}

void Scene_stepper::run_pair(std::size_t k, int first, int count,
                             const std::function<double(int)>& time_of, double dt, bool timed) {
  const auto [a, b] = m_pairs[k];
  Body_pair_tracker& tracker = m_trackers[k];
  for (int i = 0; i < count; ++i) {
    const int index = first + i;
    try {
      // Only this pair's step is timed; each (k, step) slot is written by one thread.
      const auto start = std::chrono::steady_clock::now();
      m_block[k][i] = tracker.step(time_of(index), m_poses[i][a], m_twists[i][a], m_poses[i][b],
                                   m_twists[i][b], dt);
      if (!timed) continue;
      const auto stop = std::chrono::steady_clock::now();
      const float audit = static_cast<float>(tracker.audit_time_us());
      const float total = std::chrono::duration<float, std::micro>(stop - start).count();
      m_step_times_us[k][static_cast<std::size_t>(index)] = std::max(total - audit, 0.0f);
      m_audit_times_us[k][static_cast<std::size_t>(index)] = audit;
    } catch (const Invalid_input& e) {
      rethrow_for_pair(k, e);
    }
  }
}

const std::vector<Pair_report>& Scene_stepper::step(double t, double dt) {
  const auto time_of = [t](int) { return t; };
  place_bodies(0, 1, time_of);
  m_block.resize(m_pairs.size(), std::vector<Pair_report>(1));
  for_each_pair([&](std::size_t k) { run_pair(k, 0, 1, time_of, dt, false); });
  for (std::size_t k = 0; k < m_pairs.size(); ++k) m_reports[k] = m_block[k][0];
  return m_reports;
}

void Scene_stepper::run(int count, const std::function<double(int)>& time_of, double dt,
                        const Scene_step_callback& on_step) {
  EXTREMAL_PRECONDITION(count >= 0);
  const std::size_t n_pairs = m_pairs.size();
  const int block = std::max(1, std::min(m_options.block_steps, count));
  m_block.assign(n_pairs, std::vector<Pair_report>(static_cast<std::size_t>(block)));
  // Sized up front (4 bytes per pair and step each): the steps only store.
  m_step_times_us.assign(n_pairs, std::vector<float>(static_cast<std::size_t>(count)));
  m_audit_times_us.assign(n_pairs, std::vector<float>(static_cast<std::size_t>(count)));
  for (int first = 0; first < count; first += block) {
    const int steps = std::min(block, count - first);
    place_bodies(first, steps, time_of);
    for_each_pair([&](std::size_t k) { run_pair(k, first, steps, time_of, dt, true); });
    for (int i = 0; i < steps; ++i) {
      for (std::size_t k = 0; k < n_pairs; ++k) m_reports[k] = m_block[k][i];
      on_step(first + i, time_of(first + i), m_reports);
    }
  }
}

}  // namespace extremal
