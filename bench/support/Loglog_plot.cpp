#include "support/Loglog_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "io/Svg_plot.h"

namespace extremal::bench {

namespace {
const char* const k_colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                                 "#8c564b", "#e377c2", "#17becf", "#7f7f7f", "#bcbd22"};
const char* const k_markers[] = {"circle", "square", "diamond", "triangle"};

}  // namespace

std::string Loglog_plot::to_svg() const {
  const double left = 90, right = 330, top = 50, bottom = 70;
  const double pw = width - left - right, ph = height - top - bottom;
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  for (const auto& s : series)
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!(s.x[i] > 0) || !std::isfinite(s.y[i])) continue;
      const double y = std::log10(std::max(s.y[i], y_floor));
      x0 = std::min(x0, std::log10(s.x[i]));
      x1 = std::max(x1, std::log10(s.x[i]));
      y0 = std::min(y0, y);
      y1 = std::max(y1, y);
    }
  if (!(x0 <= x1)) x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  x0 = std::floor(x0), x1 = std::ceil(x1) + (std::ceil(x1) == x0 ? 1 : 0);
  y0 = std::floor(y0), y1 = std::ceil(y1) + (std::ceil(y1) == y0 ? 1 : 0);
  auto X = [&](double x) { return left + pw * (std::log10(x) - x0) / (x1 - x0); };
  auto Y = [&](double y) {
    return top + ph * (1.0 - (std::log10(std::max(y, y_floor)) - y0) / (y1 - y0));
  };
  std::ostringstream os;
  os << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height
     << "\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" "
        "fill=\"white\"/>\n";
  os << "<text x=\"10\" y=\"25\" font-size=\"15\">"
     << io::xml_escape(title) << "</text>\n";
  for (int e = static_cast<int>(x0); e <= static_cast<int>(x1); ++e) {
    const double x = left + pw * (e - x0) / (x1 - x0);
    os << "<line x1=\"" << x << "\" y1=\"" << top << "\" x2=\"" << x << "\" y2=\"" << top + ph
       << "\" stroke=\"#ddd\"/>\n<text x=\"" << x << "\" y=\"" << top + ph + 18
       << "\" text-anchor=\"middle\">1e" << e << "</text>\n";
  }
  for (int e = static_cast<int>(y0); e <= static_cast<int>(y1); ++e) {
    const double y = top + ph * (1.0 - (e - y0) / (y1 - y0));
    os << "<line x1=\"" << left << "\" y1=\"" << y << "\" x2=\"" << left + pw << "\" y2=\"" << y
       << "\" stroke=\"#ddd\"/>\n<text x=\"" << left - 8 << "\" y=\"" << y + 4
       << "\" text-anchor=\"end\">1e" << e << "</text>\n";
  }
  os << "<rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << pw << "\" height=\"" << ph
     << "\" fill=\"none\" stroke=\"black\"/>\n";
  os << "<text x=\"" << left + pw / 2 << "\" y=\"" << height - 20
     << "\" text-anchor=\"middle\">" << io::xml_escape(x_label) << "</text>\n";
  os << "<text transform=\"translate(22," << top + ph / 2
     << ") rotate(-90)\" text-anchor=\"middle\">" << io::xml_escape(y_label) << "</text>\n";
  auto marker = [&](int k, double x, double y, const char* colour) {
    std::ostringstream m;
    const std::string kind = k_markers[k % 4];
    if (kind == "circle")
      m << "<circle cx=\"" << x << "\" cy=\"" << y << "\" r=\"4.5\" fill=\"" << colour << "\"/>";
    else if (kind == "square")
      m << "<rect x=\"" << x - 4 << "\" y=\"" << y - 4 << "\" width=\"8\" height=\"8\" fill=\""
        << colour << "\"/>";
    else if (kind == "diamond")
      m << "<polygon points=\"" << x << "," << y - 5.5 << " " << x + 5.5 << "," << y << " " << x
        << "," << y + 5.5 << " " << x - 5.5 << "," << y << "\" fill=\"" << colour << "\"/>";
    else
      m << "<polygon points=\"" << x << "," << y - 5.5 << " " << x + 5 << "," << y + 4.5 << " "
        << x - 5 << "," << y + 4.5 << "\" fill=\"" << colour << "\"/>";
    return m.str();
  };
  for (std::size_t k = 0; k < series.size(); ++k) {
    const auto& s = series[k];
    const char* colour = k_colours[k % 10];
    if (s.joined && s.x.size() > 1) {
      os << "<polyline fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"1.5\" points=\"";
      for (std::size_t i = 0; i < s.x.size(); ++i)
        if (s.x[i] > 0 && std::isfinite(s.y[i])) os << X(s.x[i]) << "," << Y(s.y[i]) << " ";
      os << "\"/>\n";
    }
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!(s.x[i] > 0 && std::isfinite(s.y[i]))) continue;
      os << marker(static_cast<int>(k / 10 + k), X(s.x[i]), Y(s.y[i]), colour) << "\n";
      if (i < s.point_labels.size() && !s.point_labels[i].empty())
        os << "<text x=\"" << X(s.x[i]) + 7 << "\" y=\""
           << Y(s.y[i]) - 5 - 11.0 * static_cast<double>(i % static_cast<std::size_t>(s.label_rows))
           << "\" font-size=\"10\" fill=\"" << colour << "\">" << io::xml_escape(s.point_labels[i])
           << "</text>\n";
    }
    const double ly = top + 10 + 20.0 * k, lx = left + pw + 20;
    os << marker(static_cast<int>(k / 10 + k), lx, ly, colour) << "<text x=\"" << lx + 12
       << "\" y=\"" << ly + 4 << "\">" << io::xml_escape(s.label) << "</text>\n";
  }
  os << "</svg>\n";
  return os.str();
}

void Loglog_plot::add_point(const std::string& series_label, double x, double y,
                            const std::string& point_label) {
  auto it = std::find_if(series.begin(), series.end(),
                         [&](const Loglog_series& s) { return s.label == series_label; });
  if (it == series.end()) it = series.insert(series.end(), {series_label, {}, {}, true, {}});
  it->x.push_back(x);
  it->y.push_back(y);
  it->point_labels.push_back(point_label);
}

void Loglog_plot::write(const std::string& path) const {
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write plot '" + path + "'");
  f << to_svg();
  if (!f) throw std::runtime_error("cannot write plot '" + path + "'");
}

void Loglog_plot::write_or_note(const std::string& out_dir, const std::string& file_name) const {
  if (out_dir.empty()) {
    std::printf("- plot: not written (a partial run; --out DIR writes it)\n");
    return;
  }
  const std::string path = out_dir + "/" + file_name;
  write(path);
  std::printf("- plot: %s\n", path.c_str());
}

Loglog_plot time_error_plot(const std::string& title) {
  Loglog_plot plot;
  plot.title = title;
  plot.x_label = "median time per frame [us]";
  plot.y_label = "maximum distance error (errors <= 1e-16 drawn at 1e-16)";
  return plot;
}

}  // namespace extremal::bench
