// Validation and small queries on knot vectors, shared by curves and surfaces.
#pragma once

#include <string>
#include <vector>

namespace extremal::internal {

// Throws Invalid_input naming `what` (e.g. "u knots") and the first problem found: count,
// finiteness, ordering, multiplicity, empty domain.
void validate_knots(const std::vector<double>& knots, int n_poles, int degree,
                    const std::string& what);

// Number of knots equal to t (exact comparison: knots come from files or insertions of the
// same value).
int knot_multiplicity(const std::vector<double>& knots, double t);

}  // namespace extremal::internal
