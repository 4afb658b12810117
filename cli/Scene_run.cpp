#include "cli/Scene_run.h"

#include <algorithm>
#include <chrono>
#include <memory>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "algorithms/scene/Scene_stepper.h"
#include "kernel/Error.h"

namespace extremal::cli {

Body_pair_options pair_options_of(const io::Scene& scene) {
  Body_pair_options o;
  o.tracker.gain.setConstant(scene.tracker.gain);  // 0: 1/step (Tracker_options)
  o.tracker.substeps = scene.tracker.substeps;
  o.tracker.integrator = scene.tracker.rk4 ? Integrator::Rk4 : Integrator::Euler;
  o.threshold = scene.threshold.value_or(0.0);
  o.audit_every = scene.tracker.audit_every;
  o.own_basin_gap = scene.tracker.own_basin_gap;
  o.tolerance = {scene.tolerance.absolute, scene.tolerance.relative};
  return o;
}

Scene_run::Scene_run(const io::Scene& scene, const Scene_run_options& options)
    : m_scene(scene), m_options(options) {
  EXTREMAL_PRECONDITION(options.threads >= 1 && options.block_steps >= 1);
  const Body_pair_options pair_options = pair_options_of(scene);
  m_models.resize(scene.bodies.size());
  m_trackers.reserve(scene.pairs.size());
  for (const auto& [a, b] : scene.pairs) {
    const io::Scene_body& A = scene.bodies[a];
    const io::Scene_body& B = scene.bodies[b];
    try {
      for (int i : {a, b})
        if (!m_models[i]) m_models[i] = std::make_shared<const Tracking_model>(scene.bodies[i].body);
      m_trackers.emplace_back(m_models[a], m_models[b], pair_options);
    } catch (const Invalid_input& e) {
      throw Invalid_input(scene.path + ": pair " + A.name + " - " + B.name + ": " + e.what());
    }
  }
  m_step_times_us.assign(scene.pairs.size(),
                         std::vector<float>(static_cast<std::size_t>(scene.step_count())));
}

Scene_run::~Scene_run() = default;

void Scene_run::run(const Step_callback& on_step) {
  const io::Scene& scene = m_scene;
  const Scene_run_options& options = m_options;
  auto& trackers = m_trackers;
  auto& step_times = m_step_times_us;
  const std::size_t n_pairs = scene.pairs.size(), n_bodies = scene.bodies.size();
  const int steps = scene.step_count();
  const int block = std::min(options.block_steps, steps);
  std::vector<std::vector<Pair_report>> buffer(n_pairs, std::vector<Pair_report>(block));
  std::vector<Pair_report> row(n_pairs);
  // The watched bodies' poses and twists at the block's steps, [step][body]; a static body's
  // once, at the first step.
  std::vector<std::vector<Rigid_pose_3>> poses(block, std::vector<Rigid_pose_3>(n_bodies));
  std::vector<std::vector<Twist_3>> twists(block, std::vector<Twist_3>(n_bodies));
  std::vector<char> still(n_pairs);
  for (std::size_t k = 0; k < n_pairs; ++k)
    still[k] = scene.bodies[scene.pairs[k].first].motion.is_static() &&
               scene.bodies[scene.pairs[k].second].motion.is_static();
  tbb::task_arena arena(options.threads);
  for (int first = 0; first < steps; first += block) {
    const int count = std::min(block, steps - first);
    for (std::size_t b = 0; b < n_bodies; ++b) {
      if (!m_models[b]) continue;
      const Scene_stepper_body body{&scene.bodies[b].body, &scene.bodies[b].motion};
      for (int i = 0; i < count; ++i)
        if (i == 0 || !scene.bodies[b].motion.is_static())
          body_pose_at(body, scene.time_of(first + i), poses[i][b], twists[i][b]);
        else
          poses[i][b] = poses[0][b], twists[i][b] = twists[0][b];
    }
    auto run_pairs = [&](std::size_t k0, std::size_t k1) {
      for (std::size_t k = k0; k < k1; ++k) {
        const auto [a, b] = scene.pairs[k];
        for (int i = 0; i < count; ++i) {
          const int index = first + i;
          const double t = scene.time_of(index);
          if (still[k] && index > 0) {  // (its row stands)
            buffer[k][i] = i > 0 ? buffer[k][i - 1] : buffer[k][block - 1];
            buffer[k][i].time = t;
            step_times[k][static_cast<std::size_t>(index)] = 0.0f;
            continue;
          }
          try {
            // Only this pair's step is timed; each (k, step) slot is written by one thread.
            const auto start = std::chrono::steady_clock::now();
            buffer[k][i] = trackers[k].step(t, poses[i][a], twists[i][a], poses[i][b], twists[i][b],
                                            scene.step);
            const auto stop = std::chrono::steady_clock::now();
            step_times[k][static_cast<std::size_t>(index)] =
                std::chrono::duration<float, std::micro>(stop - start).count();
          } catch (const Invalid_input& e) {
            throw Invalid_input(scene.path + ": pair " + scene.bodies[a].name + " - " +
                                scene.bodies[b].name + ": " + e.what());
          }
        }
      }
    };
    if (options.threads == 1 || n_pairs == 1) {
      run_pairs(0, n_pairs);
    } else {
      arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n_pairs, 1),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                            run_pairs(r.begin(), r.end());
                          });
      });
    }
    for (int i = 0; i < count; ++i) {
      for (std::size_t k = 0; k < n_pairs; ++k) row[k] = buffer[k][i];
      on_step(first + i, scene.time_of(first + i), row);
    }
  }
}

}  // namespace extremal::cli
