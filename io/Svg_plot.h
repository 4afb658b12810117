// A small SVG line plot: labelled axes with ticks, linear or log y, a legend, and optional
// shaded time intervals. Used for the tracker's error plots and `extremal report --plot`.
#pragma once

#include <string>
#include <vector>

namespace extremal::io {

struct Svg_series {
  std::string label;
  std::vector<double> x, y;
};

struct Svg_band {  // a shaded x-interval, e.g. contact or penetration
  double x0, x1;
  std::string colour;  // CSS colour
  std::string label;
};

struct Svg_plot {
  std::string title, x_label, y_label;
  bool log_y = false;
  std::vector<Svg_series> series;
  std::vector<Svg_band> bands;
  int width = 900, height = 520;

  std::string to_svg() const;
  // Throws Invalid_input naming the path if it cannot be written.
  void write(const std::string& path) const;
};

}  // namespace extremal::io
