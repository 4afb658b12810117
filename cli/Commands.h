// The `extremal` subcommands. Each returns the process exit code (docs/cli.md: 0 success,
// 1 bad input, 2 usage error) and writes errors to stderr naming the file, path or argument.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace extremal::cli {

struct Info_options {
  std::string target;  // a file or a shape spec
  bool json = false;
};
int run_info(const Info_options& options);

struct Distance_options {
  std::string a, b;            // files or shape specs
  std::string pose_a, pose_b;  // "x,y,z[,qw,qx,qy,qz]", empty = identity
  double tolerance = 1e-9;
  bool json = false;
  // --signed: the signed extremal distance (penetration depth while the bodies overlap,
  // algorithms/Penetration_depth.h); max_cells its direction-cell budget (0: the default).
  bool signed_distance = false;
  int max_cells = 0;
};
int run_distance(const Distance_options& options);

struct Report_options {
  std::vector<std::string> scenes;
  std::string output;             // -o: .csv or .json; empty = CSV to stdout
  std::string plot;               // --plot OUT.svg
  std::string snapshot;           // --snapshot OUT.glb
  double snapshot_time = 0.0;     // --at T
  int threads = 1;
  int every = 1;                  // --every N: the rows of steps k % N == 0 and the last step
  // --tolerance A, --relative-tolerance R: every scene's error budget (its "tolerance" key).
  std::optional<double> tolerance, relative_tolerance;
  // --clearance D: every scene's clearance (its "clearance" key), the `clearance` class's bound.
  std::optional<double> clearance;
  // --memory-limit MIB: every scene's memory limit per pair (its "tracker.memory_limit_mib").
  std::optional<double> memory_limit_mib;
  // --fail-on LEVEL: "clash", "contact" or "clearance"; empty: no check. Exit 3 when a pair's
  // class, or the most severe class it leaves open, reaches LEVEL (docs/cli.md).
  std::string fail_on;
  bool quiet = false;
};
// 0, 1 (bad input), 3 (a --fail-on check failed).
int run_report(const Report_options& options);

struct Tessellate_options {
  std::string target;       // a file or a shape spec
  std::string output;       // OUT.stl, OUT.ply or OUT.obj
  double deflection = 0.0;  // 0: not given (relative 1e-3)
  bool relative = false;    // deflection times the bounding-box diagonal
  std::size_t max_triangles = 20'000'000;
};
int run_tessellate(const Tessellate_options& options);

}  // namespace extremal::cli
