// Runs the `extremal` binary with arguments and captures its exit code, stdout and stderr.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace extremal::test {

struct Cli_run {
  int exit_code;
  std::string out, err;
};

// A scratch folder of this test process: concurrent test runs (ctest --parallel, or two
// checkouts testing at once) never write each other's files.
inline std::filesystem::path scratch_dir() {
  const auto dir =
      std::filesystem::temp_directory_path() / ("extremal-tests-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir;
}

inline Cli_run run_cli(const std::string& args) {
  const std::string binary = std::string(EXTREMAL_BINARY_DIR) + "/cli/extremal";
  // One capture pair per process, so tests running in parallel do not share files.
  const auto dir = scratch_dir();
  const std::string out = (dir / "extremal_cli_out.txt").string();
  const std::string err = (dir / "extremal_cli_err.txt").string();
  const int status = std::system((binary + " " + args + " >" + out + " 2>" + err).c_str());
  auto slurp = [](const std::string& p) {
    std::ifstream f(p);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
  };
  return {WEXITSTATUS(status), slurp(out), slurp(err)};
}

}  // namespace extremal::test
