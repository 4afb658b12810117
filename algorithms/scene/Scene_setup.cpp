#include "algorithms/scene/Scene_setup.h"

namespace extremal {

Body_pair_options pair_options_of(const io::Scene& scene) {
  Body_pair_options o;
  o.tracker.gain.setConstant(scene.tracker.gain);  // 0: 1/step (Tracker_options)
  o.tracker.substeps = scene.tracker.substeps;
  o.tracker.integrator = scene.tracker.rk4 ? Integrator::Rk4 : Integrator::Euler;
  o.threshold = scene.threshold.value_or(0.0);
  o.audit_every = scene.tracker.audit_every;
  o.own_basin_gap = scene.tracker.own_basin_gap;
  if (scene.tracker.memory_limit_mib > 0.0)
    o.memory_limit = static_cast<std::size_t>(scene.tracker.memory_limit_mib * 1024.0 * 1024.0);
  o.tolerance = {scene.tolerance.absolute, scene.tolerance.relative};
  return o;
}

std::unique_ptr<Scene_stepper> scene_stepper(const io::Scene& scene, int threads) {
  std::vector<Scene_stepper_body> bodies;
  bodies.reserve(scene.bodies.size());
  for (const io::Scene_body& b : scene.bodies) bodies.push_back({&b.body, &b.motion, b.name});
  Scene_stepper_options options;
  options.threads = threads;
  options.source = scene.path;
  return std::make_unique<Scene_stepper>(std::move(bodies), scene.pairs, pair_options_of(scene),
                                         options);
}

void run_scene(const io::Scene& scene, Scene_stepper& stepper, const Scene_step_callback& on_step) {
  stepper.run(scene.step_count(), [&scene](int i) { return scene.time_of(i); }, scene.step, on_step);
}

}  // namespace extremal
