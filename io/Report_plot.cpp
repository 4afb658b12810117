#include "io/Report_plot.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

namespace extremal::io {

namespace {

// The parts of `outer` (runs of rows) not covered by `inner` (runs of rows within them), on
// the grid of rows `step` apart.
std::vector<io::Time_interval> minus(const std::vector<io::Time_interval>& outer,
                                     const std::vector<io::Time_interval>& inner, double step) {
  std::vector<io::Time_interval> out;
  for (const auto& o : outer) {
    double start = o.start;
    for (const auto& i : inner) {
      if (i.end < o.start || i.start > o.end) continue;
      if (i.start - 0.5 * step > start) out.push_back({start, i.start - step});
      start = i.end + step;
    }
    if (start <= o.end + 0.5 * step) out.push_back({start, o.end});
  }
  return out;
}

}  // namespace

Pair_series::Pair_series(long total_rows, long points)
    : m_bucket(std::max(1L, total_rows / std::max(1L, points / 4))) {}

void Pair_series::flush() {
  if (m_in_bucket == 0) return;
  Row rows[4] = {m_first, m_low, m_high, m_last};
  std::sort(rows, rows + 4, [](const Row& a, const Row& b) { return a.t < b.t; });
  for (int i = 0; i < 4; ++i) {
    if (i > 0 && rows[i].t == rows[i - 1].t) continue;
    m_t.push_back(rows[i].t);
    m_d.push_back(rows[i].d);
  }
  m_in_bucket = 0;
}

void Pair_series::add(double t, double distance) {
  if (!std::isfinite(distance)) {  // a gap: ends the bucket, recorded once
    flush();
    if (m_d.empty() || std::isfinite(m_d.back())) {
      m_t.push_back(t);
      m_d.push_back(distance);
    }
    return;
  }
  const Row row{t, distance};
  if (m_in_bucket == 0) {
    m_first = m_low = m_high = row;
  } else {
    if (distance < m_low.d) m_low = row;
    if (distance > m_high.d) m_high = row;
  }
  m_last = row;
  if (++m_in_bucket == m_bucket) flush();
}

void Pair_series::finish() { flush(); }

io::Svg_plot report_plot(const io::Scene& scene, const std::vector<Pair_series>& series,
                         const std::vector<io::Pair_summary>& summaries) {
  std::vector<std::size_t> pairs(series.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) pairs[k] = k;
  return report_plot(scene, series, summaries, pairs);
}

io::Svg_plot report_plot(const io::Scene& scene, const std::vector<Pair_series>& series,
                         const std::vector<io::Pair_summary>& summaries,
                         const std::vector<std::size_t>& pairs) {
  io::Svg_plot plot;
  std::string subject = std::filesystem::path(scene.path).filename().string();
  if (pairs.size() == 1 && scene.pairs.size() > 1) {
    const auto& [a, b] = scene.pairs[pairs[0]];
    subject = scene.bodies[a].name + " - " + scene.bodies[b].name;
  }
  plot.title = subject + ": distance over time";
  plot.x_label = "time (s)";
  plot.y_label = "signed distance (" + scene.units + "; < 0: penetration depth)";
  // A row stands for its time step: intervals are widened by half a step each side so that a
  // single row in contact still shows.
  const double half = 0.5 * scene.step;
  const double t_first = scene.start, t_last = scene.time_of(scene.step_count() - 1);
  // Shading by kind; its legend names the pairs it concerns when there are several.
  struct Kind {
    const char* name;
    const char* colour;
    double opacity;
    std::vector<io::Time_interval> runs;
    std::vector<std::string> pairs;
  };
  Kind kinds[3] = {{"farther than the threshold", "#999999", 0.2, {}, {}},
                   {"contact", "#ff7f0e", 0.3, {}, {}},
                   {"penetration", "#d62728", 0.3, {}, {}}};
  bool touches = false;
  double lowest = HUGE_VAL, highest = -HUGE_VAL;
  for (std::size_t k : pairs) {
    const auto& [a, b] = scene.pairs[k];
    const std::string name = scene.bodies[a].name + " - " + scene.bodies[b].name;
    io::Svg_series s;
    s.label = name;
    s.x = series[k].t();
    s.y = series[k].distance();
    s.colour = io::plot_colour(k);
    for (double d : s.y)
      if (std::isfinite(d)) lowest = std::min(lowest, d), highest = std::max(highest, d);
    plot.series.push_back(std::move(s));
    const io::Pair_summary& sum = summaries[k];
    // Contact shading where touching but not inside, so every shaded region has one colour.
    const std::vector<io::Time_interval> runs[3] = {
        sum.farther, minus(sum.contact, sum.penetration, scene.step), sum.penetration};
    for (int c = 0; c < 3; ++c) {
      if (runs[c].empty()) continue;
      kinds[c].runs.insert(kinds[c].runs.end(), runs[c].begin(), runs[c].end());
      kinds[c].pairs.push_back(name);
    }
    touches = touches || !sum.contact.empty();
    if (sum.min_distance) plot.markers.push_back({sum.min_time, *sum.min_distance, io::plot_colour(k)});
  }
  for (const Kind& kind : kinds) {
    std::string label = kind.name;
    if (pairs.size() > 1 && !kind.runs.empty()) {
      label += " (";
      for (std::size_t i = 0; i < kind.pairs.size(); ++i)
        label += (i ? ", " : "") + kind.pairs[i];
      label += ")";
    }
    for (const auto& r : kind.runs)
      plot.bands.push_back({std::max(t_first, r.start - half), std::min(t_last, r.end + half),
                            kind.colour, label, kind.opacity});
  }
  plot.marker_label = pairs.size() == 1 ? "minimum" : "minimum of each pair";
  // The contact level, when the curves come near it (else it would squash them).
  if (touches || (lowest <= highest && lowest < 0.25 * (highest - lowest)))
    plot.rules.push_back({0.0, "contact (distance 0)"});
  return plot;
}

}  // namespace extremal::io
