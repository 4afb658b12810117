// `extremal report --plot OUT.svg`: the signed distance of each watched pair against time, its
// contact and penetration intervals shaded, its minimum marked, the contact level drawn.
#pragma once

#include <string>
#include <vector>

#include "io/Pair_summary.h"
#include "io/Scene.h"
#include "io/Svg_plot.h"

namespace extremal::io {

// The distance curve of a pair, thinned as it is collected so long runs stay small: each run of
// `bucket` consecutive rows keeps its first, lowest, highest and last row (a short dip survives).
class Pair_series {
 public:
  explicit Pair_series(long total_rows = 0, long points = 8000);
  // NaN distance where the pair is farther than the threshold (a gap in the curve).
  void add(double t, double distance);
  // Flushes the last bucket; call once after the last row.
  void finish();
  const std::vector<double>& t() const { return m_t; }
  const std::vector<double>& distance() const { return m_d; }

 private:
  void flush();
  long m_bucket;
  long m_in_bucket = 0;
  struct Row {
    double t, d;
  };
  Row m_first{}, m_low{}, m_high{}, m_last{};
  std::vector<double> m_t, m_d;
};

io::Svg_plot report_plot(const io::Scene& scene, const std::vector<Pair_series>& series,
                         const std::vector<io::Pair_summary>& summaries);
// The same for the listed pairs only (indices into scene.pairs, series and summaries).
io::Svg_plot report_plot(const io::Scene& scene, const std::vector<Pair_series>& series,
                         const std::vector<io::Pair_summary>& summaries,
                         const std::vector<std::size_t>& pairs);

}  // namespace extremal::io
