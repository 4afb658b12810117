// `extremal distance A B`: one-shot certified extremal distance (issue: global solver).
#include <iostream>

#include "cli/Commands.h"

namespace extremal::cli {

int run_distance(const Distance_options&) {
  std::cerr << "extremal distance: the certified global solver is not built yet\n";
  return 1;
}

}  // namespace extremal::cli
