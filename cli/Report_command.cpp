#include <iostream>

#include "cli/Commands.h"

namespace extremal::cli {

int run_report(const Report_options&) {
  std::cerr << "extremal report: not built yet\n";
  return 1;
}

}  // namespace extremal::cli
