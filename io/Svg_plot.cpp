#include "io/Svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>

#include "kernel/Error.h"

namespace extremal::io {

namespace {

const char* const k_colours[] = {"#1f77b4", "#2ca02c", "#9467bd", "#8c564b",
                                 "#e377c2", "#17becf", "#bcbd22", "#7f7f7f"};


std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

// About five round tick values covering [lo, hi].
std::vector<double> linear_ticks(double lo, double hi) {
  const double span = hi - lo;
  const double raw = span / 5.0;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * mag >= raw) {
      step = m * mag;
      break;
    }
  std::vector<double> t;
  for (double v = std::ceil(lo / step) * step; v <= hi + 1e-9 * span; v += step)
    t.push_back(std::abs(v) < 1e-12 * span ? 0.0 : v);
  return t;
}

struct Legend_entry {
  enum Kind { Line, Box, Dot } kind;
  std::string colour, label;
  double opacity;
};

}  // namespace

const char* plot_colour(std::size_t k) { return k_colours[k % 8]; }

std::string Svg_plot::to_svg() const {
  auto plotted = [&](double y) { return std::isfinite(y) && (!log_y || y > 0.0); };
  auto ty = [&](double y) { return log_y ? std::log10(y) : y; };

  // Legend entries: series, then one per band label, then markers with labels.
  std::vector<Legend_entry> legend;
  for (std::size_t k = 0; k < series.size(); ++k)
    legend.push_back({Legend_entry::Line,
                      series[k].colour.empty() ? plot_colour(k) : series[k].colour,
                      series[k].label, 1.0});
  for (const auto& b : bands) {
    if (b.label.empty()) continue;
    bool seen = false;
    for (const auto& e : legend) seen = seen || (e.kind == Legend_entry::Box && e.label == b.label);
    if (!seen) legend.push_back({Legend_entry::Box, b.colour, b.label, b.opacity});
  }
  if (!markers.empty() && !marker_label.empty())
    legend.push_back({Legend_entry::Dot, "#444444", marker_label, 1.0});
  std::size_t longest = 0;
  for (const auto& e : legend) longest = std::max(longest, e.label.size());
  const double legend_width =
      legend.empty() ? 0.0 : std::min(320.0, 48.0 + 6.6 * static_cast<double>(longest));

  const double left = 90, right = 24 + legend_width, top = 44, bottom = 62;
  const double pw = width - left - right, ph = height - top - bottom;
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  auto include = [&](double x, double y) {
    if (std::isfinite(x)) x0 = std::min(x0, x), x1 = std::max(x1, x);
    if (plotted(y)) y0 = std::min(y0, ty(y)), y1 = std::max(y1, ty(y));
  };
  for (const auto& s : series)
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i)
      if (plotted(s.y[i])) include(s.x[i], s.y[i]);
  for (const auto& m : markers) include(m.x, m.y);
  for (const auto& r : rules) include(std::numeric_limits<double>::quiet_NaN(), r.y);
  if (!(x0 <= x1)) x0 = 0, x1 = 1;
  if (!(y0 <= y1)) y0 = 0, y1 = 1;
  if (x1 - x0 <= 0) x1 = x0 + 1;
  if (log_y) {
    y0 = std::floor(y0);
    y1 = std::ceil(y1);
  } else {
    const double pad = 0.06 * std::max(y1 - y0, 1e-12 * std::max(1.0, std::abs(y1)));
    y0 -= pad;
    y1 += pad;
  }
  if (y1 - y0 <= 0) y1 = y0 + 1;
  auto X = [&](double x) { return left + (x - x0) / (x1 - x0) * pw; };
  auto Y = [&](double y) { return top + (1.0 - (y - y0) / (y1 - y0)) * ph; };

  std::ostringstream os;
  os << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height
     << "\" viewBox=\"0 0 " << width << " " << height << "\" font-family=\"sans-serif\">\n";
  os << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  for (const auto& b : bands) {
    const double a = X(std::max(b.x0, x0)), c = X(std::min(b.x1, x1));
    if (!(c > a)) continue;
    os << "<rect x=\"" << fmt(a) << "\" y=\"" << top << "\" width=\"" << fmt(std::max(c - a, 1.0))
       << "\" height=\"" << ph << "\" fill=\"" << b.colour << "\" fill-opacity=\"" << b.opacity
       << "\"/>\n";
  }
  // Grid and ticks.
  os << "<g stroke=\"#dddddd\" stroke-width=\"1\">\n";
  const std::vector<double> xt = linear_ticks(x0, x1);
  std::vector<double> yt;
  if (log_y) {
    const int stride = std::max(1, static_cast<int>((y1 - y0) / 8));
    for (double v = y0; v <= y1; v += stride) yt.push_back(v);
  } else {
    yt = linear_ticks(y0, y1);
  }
  for (double v : xt)
    os << "<line x1=\"" << fmt(X(v)) << "\" y1=\"" << top << "\" x2=\"" << fmt(X(v))
       << "\" y2=\"" << top + ph << "\"/>\n";
  for (double v : yt)
    os << "<line x1=\"" << left << "\" y1=\"" << fmt(Y(v)) << "\" x2=\"" << left + pw
       << "\" y2=\"" << fmt(Y(v)) << "\"/>\n";
  os << "</g>\n";
  os << "<rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << pw << "\" height=\"" << ph
     << "\" fill=\"none\" stroke=\"black\"/>\n";
  os << "<g font-size=\"12\" fill=\"black\">\n";
  for (double v : xt)
    os << "<text x=\"" << fmt(X(v)) << "\" y=\"" << top + ph + 18
       << "\" text-anchor=\"middle\">" << fmt(v) << "</text>\n";
  for (double v : yt)
    os << "<text x=\"" << left - 8 << "\" y=\"" << fmt(Y(v) + 4) << "\" text-anchor=\"end\">"
       << (log_y ? "1e" + fmt(v) : fmt(v)) << "</text>\n";
  os << "</g>\n";
  os << "<text x=\"" << left + pw / 2 << "\" y=\"" << height - 18
     << "\" font-size=\"14\" text-anchor=\"middle\">" << xml_escape(x_label) << "</text>\n";
  os << "<text x=\"22\" y=\"" << top + ph / 2
     << "\" font-size=\"14\" text-anchor=\"middle\" transform=\"rotate(-90 22 " << top + ph / 2
     << ")\">" << xml_escape(y_label) << "</text>\n";
  os << "<text x=\"" << left + pw / 2 << "\" y=\"26\" font-size=\"16\" text-anchor=\"middle\">"
     << xml_escape(title) << "</text>\n";

  // Everything inside the plot area is clipped to it.
  os << "<clipPath id=\"" << clip_id << "\"><rect x=\"" << left << "\" y=\"" << top
     << "\" width=\"" << pw << "\" height=\"" << ph << "\"/></clipPath>\n<g clip-path=\"url(#"
     << clip_id << ")\">\n";
  for (const auto& r : rules) {
    if (!plotted(r.y)) continue;
    const double y = Y(ty(r.y));
    os << "<line x1=\"" << left << "\" y1=\"" << fmt(y) << "\" x2=\"" << left + pw << "\" y2=\""
       << fmt(y) << "\" stroke=\"#444444\" stroke-width=\"1\" stroke-dasharray=\"6 4\"/>\n";
    if (!r.label.empty())
      os << "<text x=\"" << left + pw - 6 << "\" y=\"" << fmt(y - 5)
         << "\" font-size=\"11\" fill=\"#444444\" text-anchor=\"end\">" << xml_escape(r.label)
         << "</text>\n";
  }
  for (std::size_t k = 0; k < series.size(); ++k) {
    const auto& s = series[k];
    const std::string colour = s.colour.empty() ? plot_colour(k) : s.colour;
    // Dense series keep, per half pixel column, the first, lowest, highest and last point, so
    // a short dip (a contact) survives; a non-finite y ends the polyline (a gap).
    std::string points;
    auto flush_line = [&] {
      if (!points.empty())
        os << "<polyline fill=\"none\" stroke=\"" << colour
           << "\" stroke-width=\"1.6\" stroke-linejoin=\"round\" points=\"" << points << "\"/>\n";
      points.clear();
    };
    const std::size_t n = std::min(s.x.size(), s.y.size());
    long bucket = std::numeric_limits<long>::min();
    std::size_t first = 0, lo = 0, hi = 0, last = 0;
    bool open = false;
    auto emit_bucket = [&] {
      if (!open) return;
      std::size_t idx[4] = {first, lo, hi, last};
      std::sort(idx, idx + 4);
      std::size_t prev = n;
      for (std::size_t i : idx) {
        if (i == prev) continue;
        prev = i;
        points += fmt(X(s.x[i])) + "," + fmt(Y(ty(s.y[i]))) + " ";
      }
      open = false;
    };
    for (std::size_t i = 0; i < n; ++i) {
      if (!plotted(s.y[i]) || !std::isfinite(s.x[i])) {
        emit_bucket();
        flush_line();
        bucket = std::numeric_limits<long>::min();
        continue;
      }
      const long b = static_cast<long>(std::floor(2.0 * X(s.x[i])));
      if (b != bucket) {
        emit_bucket();
        bucket = b;
        first = lo = hi = last = i;
        open = true;
        continue;
      }
      if (s.y[i] < s.y[lo]) lo = i;
      if (s.y[i] > s.y[hi]) hi = i;
      last = i;
    }
    emit_bucket();
    flush_line();
  }
  os << "</g>\n";
  // Markers unclipped: a minimum at the first or last time shows whole.
  for (const auto& m : markers) {
    if (!plotted(m.y) || !std::isfinite(m.x)) continue;
    os << "<circle cx=\"" << fmt(X(m.x)) << "\" cy=\"" << fmt(Y(ty(m.y)))
       << "\" r=\"4.5\" fill=\"" << m.colour << "\" stroke=\"#222222\" stroke-width=\"1\"/>\n";
  }

  // Legend, beside the plot area.
  const double lx = left + pw + 16;
  for (std::size_t row = 0; row < legend.size(); ++row) {
    const Legend_entry& e = legend[row];
    const double ly = top + 10 + 20 * static_cast<double>(row);
    if (e.kind == Legend_entry::Line)
      os << "<line x1=\"" << lx << "\" y1=\"" << ly << "\" x2=\"" << lx + 24 << "\" y2=\"" << ly
         << "\" stroke=\"" << e.colour << "\" stroke-width=\"2.5\"/>\n";
    else if (e.kind == Legend_entry::Box)
      os << "<rect x=\"" << lx << "\" y=\"" << ly - 7 << "\" width=\"24\" height=\"14\" fill=\""
         << e.colour << "\" fill-opacity=\"" << e.opacity << "\"/>\n";
    else
      os << "<circle cx=\"" << lx + 12 << "\" cy=\"" << ly << "\" r=\"4\" fill=\"" << e.colour
         << "\"/>\n";
    os << "<text x=\"" << lx + 32 << "\" y=\"" << ly + 4 << "\" font-size=\"12\">"
       << xml_escape(e.label) << "</text>\n";
  }
  os << "</svg>\n";
  return os.str();
}

void Svg_plot::write(const std::string& path) const {
  std::ofstream f(path);
  if (!f) throw Invalid_input(path + ": cannot open for writing");
  f << to_svg();
  if (!f) throw Invalid_input(path + ": write failed");
}

std::string xml_escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '&') out += "&amp;";
    else if (c == '"') out += "&quot;";
    else out += c;
  }
  return out;
}

}  // namespace extremal::io
