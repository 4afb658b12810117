#include "experiments/Egg_crate.h"

#include <cmath>
#include <utility>
#include <vector>

#include "kernel/Shapes.h"

namespace extremal::experiments {

Body egg_crate() {
  Body b;
  b.name = "egg crate";
  const int n = 6;  // poles per face and direction
  auto height = [](double x, double y) { return 0.25 * std::sin(2.0 * x) * std::cos(2.0 * y); };
  for (int fi = 0; fi < 3; ++fi)
    for (int fj = 0; fj < 3; ++fj) {
      std::vector<Point_3> poles;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          const double x = -1.5 + fi + static_cast<double>(i) / (n - 1);
          const double y = -1.5 + fj + static_cast<double>(j) / (n - 1);
          poles.emplace_back(x, y, height(x, y));
        }
      b.faces.emplace_back(make_freeform(3, 3, n, n, std::move(poles)), "bspline");
    }
  return b;
}

}  // namespace extremal::experiments
