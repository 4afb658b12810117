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
};

struct Loglog_plot {
  std::string title, x_label, y_label;
  std::vector<Loglog_series> series;
  double y_floor = 1e-16;  // values at or below it are drawn at it
  int width = 1000, height = 640;
  std::string to_svg() const;
  // Throws std::runtime_error naming the path if it cannot be written.
  void write(const std::string& path) const;
};

}  // namespace extremal::bench
