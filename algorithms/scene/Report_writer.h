// The rows and summaries of `extremal report` (docs/cli.md): CSV rows, the JSON report
// (rows plus a summary per pair), and the readable summary for the terminal.
#pragma once

#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "algorithms/body_pair/Body_pair_tracker.h"
#include "algorithms/scene/Step_times.h"
#include "io/Pair_summary.h"
#include "io/Scene.h"

namespace extremal::report {

// The CSV header: the contract's columns, then ours (detail, the pair's parameters, the
// certified lower bound, empty where there is none) and, in a batch written to one stream, the
// scene file.
std::string csv_header(bool with_scene_column);

// A CSV field, quoted when it holds a comma, a quote or a line break (RFC 4180).
std::string csv_field(const std::string& text);

// Numbers at 17 significant digits: rows read back to the same doubles.
std::string format_number(double x);

io::Clearance_state clearance_state(Pair_status status);

// The thresholds of the clearance classes of a scene's pairs: the trackers' contact tolerance
// and the scene's "clearance" (docs/cli.md, "Clearance classes").
io::Clearance_thresholds clearance_thresholds(const io::Scene& scene);

class Report_writer {
 public:
  virtual ~Report_writer() = default;
  virtual void row(double t, const std::string& body_a, const std::string& body_b,
                   const Pair_report& r) = 0;
  // After the last row: the summaries and step times, one per scene pair, and the scene's.
  virtual void finish(const std::vector<io::Pair_summary>& summaries,
                      const Report_timing& timing) = 0;
};

// CSV rows; the header first when `header`; a trailing scene column when `scene_column` is not
// empty (its value on every row).
std::unique_ptr<Report_writer> make_csv_writer(std::ostream& out, bool header,
                                               const std::string& scene_column);
// One JSON object: the scene, its bodies and pairs, the rows, then the summaries (each with its
// pair's "step_time_us" and "audit_time_us") and the scene's "step_time_us" and "audit_time_us".
std::unique_ptr<Report_writer> make_json_writer(std::ostream& out, const io::Scene& scene);

// A summary as JSON: {"body_a", "body_b", "class", "class_range": [proven, possible],
// "undecided": [...], "rows", "min_distance", "min_time", "contact": [[start, end], ...],
// "penetration": [...], "deepest_penetration", "deepest_time", "farther", "uncertified",
// "step_time_us": {"mean", "median", "p99", "max"}, "audit_time_us": {the same}}.
nlohmann::json summary_json(const std::string& body_a, const std::string& body_b,
                            const io::Pair_summary& s, const Step_time_stats& step_time,
                            const Step_time_stats& audit_time);

// "1 clash, 2 clear": how many pairs are of each class, the most severe first.
std::string class_counts_text(const std::vector<io::Pair_summary>& summaries);

// The readable summary of a scene run, a few lines per pair, with the step times.
void print_summary(std::ostream& out, const io::Scene& scene, const std::string& written_to,
                   const std::vector<io::Pair_summary>& summaries, const Report_timing& timing);

}  // namespace extremal::report
