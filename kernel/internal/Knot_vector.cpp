#include "kernel/internal/Knot_vector.h"

#include <cmath>
#include <sstream>

#include "kernel/Error.h"
#include "kernel/internal/Bspline_basis.h"

namespace extremal::internal {

void validate_knots(const std::vector<double>& knots, int n_poles, int degree,
                    const std::string& what) {
  auto fail = [&](const std::string& reason) {
    throw Invalid_input(what + ": " + reason);
  };
  if (degree < 1 || degree > k_max_degree) {
    std::ostringstream os;
    os << "degree " << degree << " is outside 1.." << k_max_degree;
    fail(os.str());
  }
  if (n_poles < degree + 1) {
    std::ostringstream os;
    os << n_poles << " control points are too few for degree " << degree << " (need at least "
       << degree + 1 << ")";
    fail(os.str());
  }
  const std::size_t expected = static_cast<std::size_t>(n_poles + degree + 1);
  if (knots.size() != expected) {
    std::ostringstream os;
    os << "knot count is " << knots.size() << ", expected " << expected << " (" << n_poles
       << " control points + degree " << degree << " + 1)";
    fail(os.str());
  }
  for (std::size_t i = 0; i < knots.size(); ++i) {
    if (!std::isfinite(knots[i])) {
      std::ostringstream os;
      os << "knot " << i << " is not finite";
      fail(os.str());
    }
    if (i > 0 && knots[i] < knots[i - 1]) {
      std::ostringstream os;
      os << "knots decrease at index " << i << " (" << knots[i - 1] << " then " << knots[i]
         << ")";
      fail(os.str());
    }
  }
  // Multiplicity: at most degree + 1 anywhere, at most degree strictly inside the domain
  // (a higher one would split the patch into disconnected pieces).
  const double lo = knots[degree], hi = knots[n_poles];
  if (!(lo < hi)) fail("the domain [knot p, knot n] is empty");
  std::size_t i = 0;
  while (i < knots.size()) {
    std::size_t j = i;
    while (j + 1 < knots.size() && knots[j + 1] == knots[i]) ++j;
    const int mult = static_cast<int>(j - i + 1);
    const bool interior = knots[i] > lo && knots[i] < hi;
    const int allowed = interior ? degree : degree + 1;
    if (mult > allowed) {
      std::ostringstream os;
      os << "knot " << knots[i] << " has multiplicity " << mult << ", more than " << allowed
         << (interior ? " allowed inside the domain" : " allowed");
      fail(os.str());
    }
    i = j + 1;
  }
}

int knot_multiplicity(const std::vector<double>& knots, double t) {
  int m = 0;
  for (double k : knots) m += (k == t);
  return m;
}

}  // namespace extremal::internal
