// A scene file's run: its bodies, motions, pairs and settings handed to the scene runner
// (Scene_stepper), as `extremal report` and the Python module run it.
#pragma once

#include <memory>

#include "algorithms/scene/Scene_stepper.h"
#include "io/Scene.h"

namespace extremal {

// The tracker settings of a scene (gain, substeps, integrator, threshold, audits, the
// own-basin gap and the error budget).
Body_pair_options pair_options_of(const io::Scene& scene);

// A stepper over the scene's bodies and watched pairs with the scene's settings, on `threads`
// threads; its errors name the scene file, the pair and the body. The scene must outlive it.
std::unique_ptr<Scene_stepper> scene_stepper(const io::Scene& scene, int threads = 1);

// Runs every step of the scene (scene.step_count() of them, at scene.time_of(i)).
void run_scene(const io::Scene& scene, Scene_stepper& stepper, const Scene_step_callback& on_step);

}  // namespace extremal
