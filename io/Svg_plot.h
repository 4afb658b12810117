// A small SVG line plot: labelled axes with ticks, linear or log y, a legend beside the plot
// area, optional shaded x-intervals, horizontal rules and point markers. Used for the tracker's
// error plots and `extremal report --plot`.
#pragma once

#include <string>
#include <vector>

namespace extremal::io {

struct Svg_series {
  std::string label;
  std::vector<double> x, y;  // a non-finite y breaks the line (a gap)
  std::string colour;        // CSS colour; empty: the palette's next colour
};

struct Svg_band {  // a shaded x-interval, e.g. contact or penetration
  double x0, x1;
  std::string colour;  // CSS colour
  std::string label;   // bands with the same label share one legend entry
  double opacity = 0.25;
};

struct Svg_rule {  // a dashed horizontal line, e.g. y = 0 (contact)
  double y;
  std::string label;  // written at its right end, inside the plot area
};

struct Svg_marker {  // a dot, e.g. a minimum
  double x, y;
  std::string colour;
};

struct Svg_plot {
  std::string title, x_label, y_label;
  bool log_y = false;
  std::vector<Svg_series> series;
  std::vector<Svg_band> bands;
  std::vector<Svg_rule> rules;
  std::vector<Svg_marker> markers;
  std::string marker_label;  // one legend entry for all markers (none when empty)
  int width = 960, height = 540;
  // The id of the plot area's clip path: unique per plot when several share one HTML page.
  std::string clip_id = "area";

  std::string to_svg() const;
  // Throws Invalid_input naming the path if it cannot be written.
  void write(const std::string& path) const;
};

// The palette's k-th colour.
const char* plot_colour(std::size_t k);

// `text` with the characters XML gives a meaning (< > & ") written as entities.
std::string xml_escape(const std::string& text);

}  // namespace extremal::io
