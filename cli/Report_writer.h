// The rows and summaries of `extremal report` (docs/cli.md): CSV rows, the JSON report
// (rows plus a summary per pair), and the readable summary for the terminal.
#pragma once

#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "algorithms/body_pair/Body_pair_tracker.h"
#include "io/Pair_summary.h"
#include "io/Scene.h"

namespace extremal::cli {

// The CSV header: the contract's columns, then ours (detail, the pair's parameters) and, in a
// batch written to one stream, the scene file.
std::string csv_header(bool with_scene_column);

// A CSV field, quoted when it holds a comma, a quote or a line break (RFC 4180).
std::string csv_field(const std::string& text);

// Numbers at 17 significant digits: rows read back to the same doubles.
std::string format_number(double x);

io::Clearance_state clearance_state(Pair_status status);

class Report_writer {
 public:
  virtual ~Report_writer() = default;
  virtual void row(double t, const std::string& body_a, const std::string& body_b,
                   const Pair_report& r) = 0;
  // After the last row: the summaries, one per scene pair.
  virtual void finish(const std::vector<io::Pair_summary>& summaries) = 0;
};

// CSV rows; the header first when `header`; a trailing scene column when `scene_column` is not
// empty (its value on every row).
std::unique_ptr<Report_writer> make_csv_writer(std::ostream& out, bool header,
                                               const std::string& scene_column);
// One JSON object: the scene, its bodies and pairs, the rows, then the summaries.
std::unique_ptr<Report_writer> make_json_writer(std::ostream& out, const io::Scene& scene);

// A summary as JSON: {"body_a", "body_b", "rows", "min_distance", "min_time", "contact":
// [[start, end], ...], "penetration": [...], "deepest_penetration", "deepest_time", "farther"}.
nlohmann::json summary_json(const std::string& body_a, const std::string& body_b,
                            const io::Pair_summary& s);

// The readable summary of a scene run, a few lines per pair.
void print_summary(std::ostream& out, const io::Scene& scene, const std::string& written_to,
                   const std::vector<io::Pair_summary>& summaries);

}  // namespace extremal::cli
