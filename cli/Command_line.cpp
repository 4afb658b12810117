// The `extremal` command line (Command_line.h). Contract: docs/cli.md.
#include "cli/Command_line.h"

#include <cmath>
#include <exception>
#include <limits>

#include <CLI/CLI.hpp>

namespace extremal::cli {

namespace {

// An error budget's value: a finite number > 0, and < 1 when `relative`.
CLI::Validator budget_check(bool relative) {
  return CLI::Validator(
      [relative](std::string& value) -> std::string {
        try {
          std::size_t used = 0;
          const double x = std::stod(value, &used);
          if (used == value.size() && x > 0.0 && x < (relative ? 1.0 : HUGE_VAL)) return "";
        } catch (const std::exception&) {
        }
        return std::string(relative ? "must be a number > 0 and < 1" : "must be a finite number > 0") +
               " (an error budget), got '" + value + "'";
      },
      relative ? "0<R<1" : "A>0");
}

}  // namespace

Command_line parse_command_line(int argc, const char* const* argv, std::ostream& out,
                                std::ostream& err) {
  Command_line cl;
  CLI::App app{"Extremal: exact distances between moving NURBS bodies"};
  app.require_subcommand(1);
  // The subcommands pass options they do not know to this one: the import limits may come
  // before or after the subcommand. (Set before adding them: they copy it.)
  app.fallthrough();

  CLI::App* info_cmd = app.add_subcommand("info", "What a file or shape spec holds");
  info_cmd->add_option("FILE", cl.info.target, "CAD/mesh file or shape spec (e.g. sphere:1)")
      ->required();
  info_cmd->add_flag("--json", cl.info.json, "JSON output");

  CLI::App* distance_cmd =
      app.add_subcommand("distance", "One-shot certified extremal distance between two bodies");
  distance_cmd->add_option("A", cl.distance.a,
                           "File (STEP, IGES, BREP, OBJ, STL, ...; all its bodies as one set, "
                           "JSON body_a names the witness's body) or shape spec (point, "
                           "sphere:r, ...)")->required();
  distance_cmd->add_option("B", cl.distance.b, "File or shape spec")->required();
  distance_cmd->add_option("--pose-a", cl.distance.pose_a, "Pose of A: x,y,z[,qw,qx,qy,qz]");
  distance_cmd->add_option("--pose-b", cl.distance.pose_b, "Pose of B: x,y,z[,qw,qx,qy,qz]");
  distance_cmd->add_option("--tolerance", cl.distance.tolerance, "Certificate tolerance")
      ->check(CLI::PositiveNumber);
  distance_cmd->add_flag("--json", cl.distance.json, "JSON output with the bounds");
  CLI::Option* signed_opt = distance_cmd->add_flag(
      "--signed", cl.distance.signed_distance,
      "Signed distance: negative penetration depth when the bodies overlap (surfaces meet or "
      "one lies inside the other), -min over n of h_A(n) + h_B(-n) (support functions): the "
      "minimum translation distance for convex bodies, their convex hulls' depth otherwise; "
      "status 'penetrating'");
  distance_cmd->add_option("--max-cells", cl.distance.max_cells,
                           "With --signed: budget of direction cells for the depth (default 200000)")
      ->check(CLI::PositiveNumber)
      ->needs(signed_opt);
  distance_cmd->footer(
      "Exit codes: 0 success, 1 bad input (message on stderr), 2 usage error.");

  CLI::App* report_cmd = app.add_subcommand(
      "report", "Batch distance report over time for the watched pairs of one or more scenes");
  report_cmd->footer(
      "With no -o, CSV rows go to stdout and the summary to stderr. Several scene files run as a\n"
      "batch: with -o/--plot/--snapshot each scene writes OUT.<stem>.<ext>, <stem> being the\n"
      "scene file's stem (or <k>-<stem> for every scene when two scenes share a stem, k its\n"
      "position); to stdout, one CSV header and a trailing 'scene' column.\n"
      "Exit codes: 0 success, 1 bad input (message on stderr), 2 usage error, 3 a --fail-on\n"
      "check failed (the pairs on stderr).");
  report_cmd->add_option("SCENE", cl.report.scenes, "Scene file(s) (JSON, docs/cli.md)")
      ->required();
  report_cmd->add_option("-o,--output", cl.report.output,
                         "Write the report to OUT.csv or OUT.json (rows plus a summary per pair), "
                         "or OUT.html (a page: the summary with each pair's class, plots, a 3D "
                         "view of the worst moment)");
  report_cmd->add_option("--plot", cl.report.plot,
                         "Distance against time per pair as SVG, contact and penetration shaded");
  CLI::Option* snapshot_opt = report_cmd->add_option(
      "--snapshot", cl.report.snapshot, "The scene at --at T as binary glTF (.glb): surfaces and witness segments");
  CLI::Option* at_opt =
      report_cmd->add_option("--at", cl.report.snapshot_time, "Snapshot time T (the nearest step)");
  at_opt->needs(snapshot_opt);
  snapshot_opt->needs(at_opt);
  report_cmd->add_option("--threads", cl.report.threads,
                         "Worker threads for the pairs (default 1; the rows do not depend on it)")
      ->check(CLI::PositiveNumber);
  report_cmd->add_option("--every", cl.report.every,
                         "Write the rows of every N-th step only (steps k with k % N == 0, and "
                         "the last step); the summary covers every step (default 1)")
      ->check(CLI::Validator(
          [](std::string& value) -> std::string {
            try {
              std::size_t used = 0;
              const long n = std::stol(value, &used);
              if (used == value.size() && n >= 1 && n <= 100'000'000) return "";
            } catch (const std::exception&) {
            }
            return "must be an integer from 1 to 100000000 (write every N-th step's rows), got '" +
                   value + "'";
          },
          "N>=1"));
  double tolerance = 0.0, relative_tolerance = 0.0;
  CLI::Option* tolerance_opt = report_cmd->add_option("--tolerance", tolerance,
                         "Error budget, absolute (scene units): every apart row's lower_bound is "
                         "at least distance - max(A, R |distance|) (default 1e-9, or the scene's "
                         "\"tolerance\" key)")
      ->check(budget_check(false));
  CLI::Option* relative_tolerance_opt = report_cmd->add_option("--relative-tolerance", relative_tolerance,
                         "Error budget, relative to the distance (default 1e-9, or the scene's)")
      ->check(budget_check(true));
  double memory_limit_mib = 0.0;
  CLI::Option* memory_limit_opt = report_cmd->add_option("--memory-limit", memory_limit_mib,
                         "Most memory one pair's candidate stage may hold, in MiB (default 1024, "
                         "or the scene's \"tracker.memory_limit_mib\"); past it the pair is "
                         "certified by the global solver and its rows say memory_limit")
      ->check(CLI::PositiveNumber);
  double clearance = 0.0;
  CLI::Option* clearance_opt = report_cmd->add_option("--clearance", clearance,
                         "Clearance D (scene units): pairs closer than D, not in contact, are of "
                         "the class 'clearance' (default: the scene's \"clearance\" key, or none)")
      ->check(CLI::PositiveNumber);
  report_cmd->add_option("--fail-on", cl.report.fail_on,
                         "Exit 3 when a pair's class, or the most severe class its bounds leave "
                         "open (undecided), is LEVEL or worse: clash, contact or clearance")
      ->check(CLI::IsMember({"clash", "contact", "clearance"}));
  report_cmd->add_flag("--quiet", cl.report.quiet, "No summary, no progress bar");

  CLI::App* tessellate_cmd = app.add_subcommand(
      "tessellate", "Triangle mesh of a CAD part within a chordal deviation, written as STL, PLY or OBJ");
  tessellate_cmd->add_option("FILE", cl.tessellate.target,
                             "CAD/mesh file (STEP, IGES, BREP, OBJ, ...; every body) or shape spec")
      ->required();
  tessellate_cmd->add_option("-o,--output", cl.tessellate.output,
                             "OUT.stl (binary), OUT.ply (ASCII) or OUT.obj, by the extension")
      ->required();
  tessellate_cmd->add_option("--deflection", cl.tessellate.deflection,
                             "Largest distance from the mesh to the surface, in mm (default: "
                             "1e-3 of the bounding-box diagonal)")
      ->check(CLI::PositiveNumber);
  tessellate_cmd->add_flag("--relative", cl.tessellate.relative,
                           "--deflection is a fraction of the bounding-box diagonal");
  tessellate_cmd->add_option("--max-triangles", cl.tessellate.max_triangles,
                             "Fail (exit 1) rather than write more triangles (default 20000000)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1'000'000'000}));
  tessellate_cmd->footer(
      "Each face is sampled on a (u, v) grid fine enough that every point of every triangle is\n"
      "within the deflection of the surface (a bound from the second derivatives per knot span).\n"
      "Vertices are shared within a face only: the mesh is not watertight across faces. A trimmed\n"
      "face's cells are clipped where the grid edges cross the trim, so its border is a polyline\n"
      "through points of the trim (what is thinner than a cell is lost). A summary line goes to\n"
      "stderr.\n"
      "Exit codes: 0 success, 1 bad input or unwritable output (message on stderr), 2 usage error.");

  // Import limits (io::Import_limits).
  // Their defaults are Import_limits{}'s, shown by CLI11 from the bound fields.
  app.add_option("--max-patch-poles", cl.limits.max_patch_poles,
                 "Refuse a STEP/IGES file with a B-spline of more control points (0: no limit)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--max-total-poles", cl.limits.max_total_poles,
                 "Refuse a STEP/IGES file whose B-splines have more control points in all "
                 "(0: no limit)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--import-memory-mb", cl.limits.max_memory_mb,
                 "Stop reading a STEP/IGES/BREP file that needs more memory, in MiB (0: no limit)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--import-seconds", cl.limits.max_seconds,
                 "Stop reading a STEP/IGES/BREP file after this many seconds (0: no limit)")
      ->check(CLI::Range(0.0, 1e9))
      ->capture_default_str();

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI11 maps --help to success and real usage errors to non-zero; ours is 2.
    const int code = app.exit(e, out, err);
    cl.exit_code = code == 0 ? 0 : 2;
    return cl;
  }
  if (info_cmd->parsed()) {
    cl.command = Command_line::Command::Info;
  } else if (distance_cmd->parsed()) {
    cl.command = Command_line::Command::Distance;
  } else if (report_cmd->parsed()) {
    cl.command = Command_line::Command::Report;
    if (tolerance_opt->count()) cl.report.tolerance = tolerance;
    if (relative_tolerance_opt->count()) cl.report.relative_tolerance = relative_tolerance;
    if (clearance_opt->count()) cl.report.clearance = clearance;
    if (memory_limit_opt->count()) cl.report.memory_limit_mib = memory_limit_mib;
  } else if (tessellate_cmd->parsed()) {
    cl.command = Command_line::Command::Tessellate;
  } else {
    cl.exit_code = 2;
  }
  return cl;
}

}  // namespace extremal::cli
