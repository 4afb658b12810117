// What `extremal report` makes of a scene's steps, shared by the command and the Python
// module's batch (python/): the names of a batch's output files, and the rows and summaries
// of one scene's report.
#pragma once

#include <string>
#include <vector>

#include "algorithms/Body_pair_tracker.h"
#include "cli/Report_writer.h"
#include "io/Pair_summary.h"
#include "io/Scene.h"

namespace extremal::cli {

// The tags of a batch's output names: each scene file's stem, or <k>-<stem> (k = 1, 2, ...
// the scene's position) for every scene when two scenes share a stem.
std::vector<std::string> scene_tags(const std::vector<std::string>& scenes);

// OUT.ext with one scene (batch false); with several, OUT.<tag>.ext. Empty stays empty.
std::string batch_path(const std::string& path, const std::string& tag, bool batch);

// The rows of one scene's report. Each step's reports (one per scene pair, in the order of
// scene.pairs) go to the pairs' summaries, and to the writer but for a pair's repeated farther
// rows: a pair beyond the threshold is reported once when it goes there, not at every step.
class Report_rows {
 public:
  // The scene and the writer must outlive this.
  Report_rows(const io::Scene& scene, Report_writer& writer);
  void add(double t, const std::vector<Pair_report>& reports);
  // After the last step: the summaries, one per scene pair, which the writer gets too.
  std::vector<io::Pair_summary> finish();

 private:
  const io::Scene& m_scene;
  Report_writer& m_writer;
  std::vector<io::Pair_summary_builder> m_summaries;
  std::vector<bool> m_was_farther;
};

}  // namespace extremal::cli
