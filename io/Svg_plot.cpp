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

const char* const k_colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e",
                                 "#9467bd", "#8c564b", "#e377c2", "#17becf"};

std::string escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '&') out += "&amp;";
    else out += c;
  }
  return out;
}

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

}  // namespace

std::string Svg_plot::to_svg() const {
  const double left = 90, right = 30, top = 40, bottom = 60;
  const double pw = width - left - right, ph = height - top - bottom;
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  for (const auto& s : series)
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      if (log_y && !(s.y[i] > 0.0)) continue;
      const double y = log_y ? std::log10(s.y[i]) : s.y[i];
      x0 = std::min(x0, s.x[i]);
      x1 = std::max(x1, s.x[i]);
      y0 = std::min(y0, y);
      y1 = std::max(y1, y);
    }
  if (!(x0 <= x1)) x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  if (x1 - x0 <= 0) x1 = x0 + 1;
  if (log_y) {
    y0 = std::floor(y0);
    y1 = std::ceil(y1);
  } else {
    const double pad = 0.05 * std::max(y1 - y0, 1e-12);
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
    if (c <= a) continue;
    os << "<rect x=\"" << fmt(a) << "\" y=\"" << top << "\" width=\"" << fmt(c - a)
       << "\" height=\"" << ph << "\" fill=\"" << b.colour << "\" fill-opacity=\"0.25\"/>\n";
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
  for (double v : xt) os << "<line x1=\"" << fmt(X(v)) << "\" y1=\"" << top << "\" x2=\"" << fmt(X(v)) << "\" y2=\"" << top + ph << "\"/>\n";
  for (double v : yt) os << "<line x1=\"" << left << "\" y1=\"" << fmt(Y(v)) << "\" x2=\"" << left + pw << "\" y2=\"" << fmt(Y(v)) << "\"/>\n";
  os << "</g>\n";
  os << "<rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << pw << "\" height=\"" << ph
     << "\" fill=\"none\" stroke=\"black\"/>\n";
  os << "<g font-size=\"12\" fill=\"black\">\n";
  for (double v : xt)
    os << "<text x=\"" << fmt(X(v)) << "\" y=\"" << top + ph + 18 << "\" text-anchor=\"middle\">" << fmt(v) << "</text>\n";
  for (double v : yt)
    os << "<text x=\"" << left - 8 << "\" y=\"" << fmt(Y(v) + 4) << "\" text-anchor=\"end\">"
       << (log_y ? "1e" + fmt(v) : fmt(v)) << "</text>\n";
  os << "</g>\n";
  os << "<text x=\"" << left + pw / 2 << "\" y=\"" << height - 15
     << "\" font-size=\"14\" text-anchor=\"middle\">" << escape(x_label) << "</text>\n";
  os << "<text x=\"20\" y=\"" << top + ph / 2 << "\" font-size=\"14\" text-anchor=\"middle\" transform=\"rotate(-90 20 "
     << top + ph / 2 << ")\">" << escape(y_label) << "</text>\n";
  os << "<text x=\"" << left + pw / 2 << "\" y=\"24\" font-size=\"16\" text-anchor=\"middle\">"
     << escape(title) << "</text>\n";
  // Series, clipped to the plot area.
  os << "<clipPath id=\"area\"><rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << pw
     << "\" height=\"" << ph << "\"/></clipPath>\n<g clip-path=\"url(#area)\" fill=\"none\" stroke-width=\"1.5\">\n";
  for (std::size_t k = 0; k < series.size(); ++k) {
    const auto& s = series[k];
    os << "<polyline stroke=\"" << k_colours[k % 8] << "\" points=\"";
    // Thin dense series to at most ~4 points per pixel column.
    const std::size_t n = std::min(s.x.size(), s.y.size());
    const std::size_t stride = std::max<std::size_t>(1, n / static_cast<std::size_t>(4 * pw));
    for (std::size_t i = 0; i < n; i += stride) {
      if (!std::isfinite(s.y[i]) || (log_y && !(s.y[i] > 0.0))) continue;
      const double y = log_y ? std::log10(s.y[i]) : s.y[i];
      os << fmt(X(s.x[i])) << "," << fmt(Y(y)) << " ";
    }
    os << "\"/>\n";
  }
  os << "</g>\n";
  // Legend.
  int row = 0;
  for (std::size_t k = 0; k < series.size(); ++k, ++row) {
    const double ly = top + 16 + 18 * row;
    os << "<line x1=\"" << left + pw - 200 << "\" y1=\"" << ly << "\" x2=\"" << left + pw - 175
       << "\" y2=\"" << ly << "\" stroke=\"" << k_colours[k % 8] << "\" stroke-width=\"2\"/>\n";
    os << "<text x=\"" << left + pw - 168 << "\" y=\"" << ly + 4 << "\" font-size=\"12\">"
       << escape(series[k].label) << "</text>\n";
  }
  for (const auto& b : bands) {
    bool first = true;
    for (const auto& o : bands)
      if (&o != &b && o.label == b.label && &o < &b) first = false;
    if (!first || b.label.empty()) continue;
    const double ly = top + 16 + 18 * row++;
    os << "<rect x=\"" << left + pw - 200 << "\" y=\"" << ly - 6 << "\" width=\"25\" height=\"12\" fill=\""
       << b.colour << "\" fill-opacity=\"0.25\"/>\n";
    os << "<text x=\"" << left + pw - 168 << "\" y=\"" << ly + 4 << "\" font-size=\"12\">"
       << escape(b.label) << "</text>\n";
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

}  // namespace extremal::io
