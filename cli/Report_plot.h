// `extremal report --plot OUT.svg`: the signed distance of each watched pair against time, its
// contact and penetration intervals shaded, its minimum marked, the contact level drawn.
#pragma once

#include <string>
#include <vector>

#include "io/Pair_summary.h"
#include "io/Scene.h"
#include "io/Svg_plot.h"

namespace extremal::cli {

struct Pair_series {
  std::vector<double> t, distance;  // NaN where the pair is farther than the threshold
};

io::Svg_plot report_plot(const io::Scene& scene, const std::vector<Pair_series>& series,
                         const std::vector<io::Pair_summary>& summaries);

}  // namespace extremal::cli
