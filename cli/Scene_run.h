// Runs the watched pairs of a scene through its time steps, on several threads when asked, with
// the same rows as on one thread: each body is prepared once (its Tracking_model, read only and
// shared by its pairs) and placed once a step, each pair has its own tracker, the pairs of a
// block of steps run in parallel in a TBB arena (each pair through the block's steps in turn),
// and the rows of the block are handed over in order (step by step, pair by pair). A pair of
// two static bodies is stepped once: its row stands, at no cost, for the later steps.
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "algorithms/body_pair/Body_pair_tracker.h"
#include "io/Scene.h"


namespace extremal::cli {

// The tracker settings of a scene (gain, substeps, integrator, threshold, audits).
Body_pair_options pair_options_of(const io::Scene& scene);

struct Scene_run_options {
  int threads = 1;
  int block_steps = 512;  // steps each pair runs before the block's rows are handed over
};

// Called once per time step in order: step index, time, and one report per scene pair (in the
// order of scene.pairs).
using Step_callback =
    std::function<void(int step, double t, const std::vector<Pair_report>& reports)>;

class Scene_run {
 public:
  // Sets up one tracker per pair; throws Invalid_input naming the scene file, the pair and the
  // body when a pair cannot be tracked (so nothing is written for a scene that cannot run).
  // The scene must outlive the run.
  Scene_run(const io::Scene& scene, const Scene_run_options& options);
  ~Scene_run();
  void run(const Step_callback& on_step);

  // After run(): step_times_us()[k][i], the wall time of pair k's step i in microseconds,
  // measured (steady_clock) around that pair's step only: its two bodies' poses and its
  // tracker's step, on whichever thread ran it; handing the rows over is not in it.
  const std::vector<std::vector<float>>& step_times_us() const { return m_step_times_us; }

 private:
  const io::Scene& m_scene;
  Scene_run_options m_options;
  std::vector<std::shared_ptr<const Tracking_model>> m_models;  // per body, if watched
  std::vector<Body_pair_tracker> m_trackers;                      // per pair
  // Sized to the scene's steps up front (4 bytes per pair and step): run() only stores.
  std::vector<std::vector<float>> m_step_times_us;
};

}  // namespace extremal::cli
