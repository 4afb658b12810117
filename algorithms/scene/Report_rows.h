// What `extremal report` makes of a scene's steps, shared by the command and the Python
// module's batch (python/): the names of a batch's output files, and the rows and summaries
// of one scene's report.
#pragma once

#include <string>
#include <vector>

#include "algorithms/Body_pair_tracker.h"
#include "algorithms/scene/Report_writer.h"
#include "algorithms/scene/Step_times.h"
#include "io/Pair_summary.h"
#include "io/Scene.h"

namespace extremal::report {

// The tags of a batch's output names: each scene file's stem, or <k>-<stem> (k = 1, 2, ...
// the scene's position) for every scene when two scenes share a stem.
std::vector<std::string> scene_tags(const std::vector<std::string>& scenes);

// OUT.ext with one scene (batch false); with several, OUT.<tag>.ext. Empty stays empty.
std::string batch_path(const std::string& path, const std::string& tag, bool batch);

// The rows of one scene's report. Each step's reports (one per scene pair, in the order of
// scene.pairs) go to the pairs' summaries, every step. They go to the writer at the written
// steps only: with `every` N, the steps k with k % N == 0 and the scene's last step (N = 1:
// every step). Among the written steps a pair beyond the threshold is written once when it
// goes there (at the first written step it is farther at), not at every step.
class Report_rows {
 public:
  // The scene and the writer must outlive this; every >= 1.
  Report_rows(const io::Scene& scene, Report_writer& writer, int every = 1);
  // Steps come in order, one call each, scene.step_count() in all.
  void add(double t, const std::vector<Pair_report>& reports);
  // After the last step: the summaries, one per scene pair, with their clearance classes,
  // which the writer gets too, with the run's step times.
  std::vector<io::Pair_summary> finish(const Report_timing& timing);

 private:
  const io::Scene& m_scene;
  Report_writer& m_writer;
  int m_every;
  int m_step = 0;  // the index of the next step add() gets
  std::vector<io::Pair_summary_builder> m_summaries;
  std::vector<io::Clearance_class_builder> m_classes;  // per pair, every step
  std::vector<bool> m_was_farther;  // at the last written step
};

}  // namespace extremal::report
