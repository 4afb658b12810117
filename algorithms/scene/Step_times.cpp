#include "algorithms/scene/Step_times.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "kernel/Error.h"

namespace extremal::report {

namespace {

// The ceil(p n / 100)-th smallest of n sorted samples (nearest rank), n >= 1.
double nearest_rank(const std::vector<float>& sorted, int percent) {
  const std::size_t n = sorted.size();
  const std::size_t rank = (static_cast<std::size_t>(percent) * n + 99) / 100;  // ceil, >= 1
  return sorted[std::clamp<std::size_t>(rank, 1, n) - 1];
}

// Three significant digits, whole microseconds from 1000 up (no exponents).
std::string short_us(double x) {
  char buf[48];
  std::snprintf(buf, sizeof buf, x < 1000.0 ? "%.3g us" : "%.0f us", x);
  return buf;
}

}  // namespace

Step_time_stats step_time_stats(std::vector<float> samples_us) {
  Step_time_stats s;
  s.samples = samples_us.size();
  if (samples_us.empty()) return s;
  std::sort(samples_us.begin(), samples_us.end());
  double sum = 0.0;
  for (float x : samples_us) sum += x;
  s.max = samples_us.back();
  // The mean of floats summed in double can exceed the largest by rounding: clamp it.
  s.mean = std::min(sum / static_cast<double>(samples_us.size()), s.max);
  s.median = nearest_rank(samples_us, 50);
  s.p99 = nearest_rank(samples_us, 99);
  return s;
}

namespace {

// Each pair's statistics and those of the pairs' sums per step.
void pair_and_scene_stats(const std::vector<std::vector<float>>& per_pair,
                          std::vector<Step_time_stats>& pairs, Step_time_stats& scene_stats) {
  const std::size_t steps = per_pair.empty() ? 0 : per_pair.front().size();
  std::vector<float> scene(steps, 0.0f);
  for (const auto& times : per_pair) {
    EXTREMAL_PRECONDITION_MSG(times.size() == steps,
                              "step times: " << times.size() << " steps, expected " << steps);
    for (std::size_t i = 0; i < steps; ++i) scene[i] += times[i];
    pairs.push_back(step_time_stats(times));
  }
  scene_stats = step_time_stats(std::move(scene));
}

}  // namespace

Report_timing report_timing(const std::vector<std::vector<float>>& per_pair,
                            const std::vector<std::vector<float>>& audits) {
  Report_timing timing;
  pair_and_scene_stats(per_pair, timing.pairs, timing.scene);
  if (audits.empty())
    timing.audit_pairs.assign(per_pair.size(), Step_time_stats{});
  else
    pair_and_scene_stats(audits, timing.audit_pairs, timing.audit_scene);
  EXTREMAL_PRECONDITION(timing.audit_pairs.size() == timing.pairs.size());
  return timing;
}

nlohmann::json step_time_json(const Step_time_stats& s) {
  return {{"mean", s.mean}, {"median", s.median}, {"p99", s.p99}, {"max", s.max}};
}

std::string step_time_text(const Step_time_stats& s) {
  return "mean " + short_us(s.mean) + ", median " + short_us(s.median) + ", p99 " +
         short_us(s.p99) + ", max " + short_us(s.max);
}

}  // namespace extremal::report
