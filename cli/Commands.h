// The `extremal` subcommands. Each returns the process exit code (../shared/CLI.md: 0 success,
// 1 bad input, 2 usage error) and writes errors to stderr naming the file, path or argument.
#pragma once

#include <string>
#include <vector>

namespace extremal::cli {

struct Info_options {
  std::string target;  // a file or a shape spec
  bool json = false;
};
int run_info(const Info_options& options);

}  // namespace extremal::cli
