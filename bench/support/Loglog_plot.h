// A log-log scatter plot with connected series, written as SVG (bench/compare's time against
// error plot; io/Svg_plot draws linear-x line plots only).
#pragma once

#include <string>
#include <vector>

namespace extremal::bench {

struct Loglog_series {
  std::string label;
  std::vector<double> x, y;  // positive; points joined in order
  bool joined = true;
  std::vector<std::string> point_labels;  // optional, one per point, drawn beside it
  // Consecutive points' labels stacked in this many rows above them (points close in x).
  int label_rows = 1;
};

struct Loglog_plot {
  std::string title, x_label, y_label;
  std::vector<Loglog_series> series;
  double y_floor = 1e-16;  // values at or below it are drawn at it
  int width = 1000, height = 640;
  // Adds (x, y) to the series labelled `series_label`, a new joined series at the end if none is.
  void add_point(const std::string& series_label, double x, double y,
                 const std::string& point_label = "");
  std::string to_svg() const;
  // Throws std::runtime_error naming the path if it cannot be written.
  void write(const std::string& path) const;
  // Writes out_dir/file_name and prints "- plot: " and its path; without an out_dir (a partial
  // run, which leaves the committed plots of full runs alone) prints that it was not written.
  void write_or_note(const std::string& out_dir, const std::string& file_name) const;
};

// bench/compare's plot of the median time per frame against the maximum error.
Loglog_plot time_error_plot(const std::string& title);

}  // namespace extremal::bench
