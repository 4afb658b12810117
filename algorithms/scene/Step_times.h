// The step times of a report (docs/cli.md, "Summary"): each pair's wall time per step, measured
// around the pair's tracker step only (writing rows is not in it) less its audits, the audits'
// time apart, and their mean, median, 99th percentile and maximum for the summaries.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace extremal::report {

struct Step_time_stats {
  std::size_t samples = 0;  // 0: no samples, every statistic 0
  double mean = 0.0, median = 0.0, p99 = 0.0, max = 0.0;  // microseconds
};

// Nearest-rank statistics: the p-th percentile of n samples is the ceil(p n / 100)-th smallest
// (1-based), always one of the samples; the median is the 50th percentile (the lower middle
// sample when n is even). Invariant of the result: median <= p99 <= max and mean <= max.
Step_time_stats step_time_stats(std::vector<float> samples_us);

// The step times of a run (audits excluded), per pair and the scene's, and the audits' times.
struct Report_timing {
  std::vector<Step_time_stats> pairs;  // one per scene pair, in the order of scene.pairs
  // The scene's step time at a step is the sum of its pairs' step times there: the work of the
  // step (on one thread its wall time, less what writing rows and audits cost).
  Step_time_stats scene;
  // The same of the audits' times (Body_pair_options::audit_every; all 0 without audits).
  std::vector<Step_time_stats> audit_pairs;
  Step_time_stats audit_scene;
};

// per_pair[k][i]: pair k's time at step i, in microseconds, and audits[k][i] its audits' (empty:
// none); every pair has the same steps.
Report_timing report_timing(const std::vector<std::vector<float>>& per_pair,
                            const std::vector<std::vector<float>>& audits = {});

// {"mean", "median", "p99", "max"}, in microseconds.
nlohmann::json step_time_json(const Step_time_stats& s);

// "mean M us, median Q us, p99 P us, max X us".
std::string step_time_text(const Step_time_stats& s);

}  // namespace extremal::report
