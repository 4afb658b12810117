// The `extremal` command: batch distance reports, one-shot distances, file information.
// Contract: ../shared/CLI.md.
#include <iostream>

#include <CLI/CLI.hpp>

#include "cli/Commands.h"

int main(int argc, char** argv) {
  CLI::App app{"Extremal: exact distances between moving NURBS bodies"};
  app.require_subcommand(1);

  extremal::cli::Info_options info;
  CLI::App* info_cmd = app.add_subcommand("info", "What a file or shape spec holds");
  info_cmd->add_option("FILE", info.target, "CAD/mesh file or shape spec (e.g. sphere:1)")
      ->required();
  info_cmd->add_flag("--json", info.json, "JSON output");

  extremal::cli::Distance_options distance;
  CLI::App* distance_cmd =
      app.add_subcommand("distance", "One-shot certified extremal distance between two bodies");
  distance_cmd->add_option("A", distance.a,
                           "File (STEP, IGES, BREP, OBJ, STL, ...; all its bodies as one set, "
                           "JSON body_a names the witness's body) or shape spec (point, "
                           "sphere:r, ...)")->required();
  distance_cmd->add_option("B", distance.b, "File or shape spec")->required();
  distance_cmd->add_option("--pose-a", distance.pose_a, "Pose of A: x,y,z[,qw,qx,qy,qz]");
  distance_cmd->add_option("--pose-b", distance.pose_b, "Pose of B: x,y,z[,qw,qx,qy,qz]");
  distance_cmd->add_option("--tolerance", distance.tolerance, "Certificate tolerance")
      ->check(CLI::PositiveNumber);
  distance_cmd->add_flag("--json", distance.json, "JSON output with the bounds");

  extremal::cli::Report_options report;
  CLI::App* report_cmd =
      app.add_subcommand("report", "Batch distance report over time for a scene file");
  report_cmd->add_option("SCENE", report.scenes, "Scene file(s) (JSON)")->required();
  report_cmd->add_option("-o,--output", report.output, "Write the report to OUT.csv or OUT.json");
  report_cmd->add_option("--plot", report.plot, "Distance against time as SVG");
  report_cmd->add_option("--snapshot", report.snapshot, "The scene at --at T as glTF (.glb)");
  CLI::Option* at_opt = report_cmd->add_option("--at", report.snapshot_time, "Snapshot time");
  report_cmd->add_option("--threads", report.threads, "Worker threads")
      ->check(CLI::PositiveNumber);
  report_cmd->add_flag("--quiet", report.quiet, "No summary, no progress bar");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI11 maps --help to success and real usage errors to non-zero; ours is 2.
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  if (info_cmd->parsed()) return extremal::cli::run_info(info);
  if (distance_cmd->parsed()) return extremal::cli::run_distance(distance);
  if (report_cmd->parsed()) {
    report.snapshot_time_given = at_opt->count() > 0;
    if (!report.snapshot.empty() && !report.snapshot_time_given) {
      std::cerr << "extremal report: --snapshot needs --at T\n";
      return 2;
    }
    return extremal::cli::run_report(report);
  }
  return 2;
}
