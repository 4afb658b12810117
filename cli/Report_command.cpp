// `extremal report SCENE.json... [-o OUT.csv|OUT.json|OUT.html] [--plot OUT.svg] [--snapshot
// OUT.glb --at T] [--clearance D] [--fail-on LEVEL] [--threads N] [--every N] [--memory-limit
// MIB] [--quiet]`: batch
// distance reports over time (docs/cli.md).
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>

#include "cli/Commands.h"
#include "cli/Html_report.h"
#include "cli/Progress_bar.h"
#include "io/Report_plot.h"
#include "algorithms/scene/Report_rows.h"
#include "algorithms/scene/Report_writer.h"
#include "algorithms/scene/Scene_setup.h"
#include "io/Model_reader.h"
#include "io/Pair_summary.h"
#include "io/Scene.h"
#include "kernel/Error.h"

#include "io/Snapshot_writer.h"

namespace extremal::cli {

namespace {

using namespace report;
using io::Pair_series;
using io::report_plot;

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string short_number(double x) {
  std::ostringstream os;
  os << x;
  return os.str();
}

struct Scene_outputs {
  std::string report, plot, snapshot;  // empty: none (report empty: stdout)
};

int snapshot_step(const io::Scene& scene, double at) {
  const int steps = scene.step_count();
  const double t_last = scene.time_of(steps - 1);
  if (!(at >= scene.start - 0.5 * scene.step && at <= t_last + 0.5 * scene.step)) {
    std::ostringstream os;
    os << "--at " << at << ": outside the time of " << scene.path << " (" << scene.start
       << " to " << t_last << " s)";
    throw Invalid_input(os.str());
  }
  return std::clamp(static_cast<int>(std::lround((at - scene.start) / scene.step)), 0, steps - 1);
}

void write_snapshot(const io::Scene& scene, const std::string& path, double t,
                    const std::vector<Pair_report>& reports) {
  std::vector<io::Snapshot_body> bodies;
  for (const auto& b : scene.bodies)
    bodies.push_back({b.name, &b.body, b.motion.pose_at(t) * b.body.placement});
  std::vector<io::Snapshot_segment> segments;
  for (std::size_t k = 0; k < reports.size(); ++k) {
    if (reports[k].status == Pair_status::Farther) continue;  // no witness pair
    const auto& [a, b] = scene.pairs[k];
    segments.push_back({scene.bodies[a].name + " - " + scene.bodies[b].name, reports[k].point_a,
                        reports[k].point_b});
  }
  io::Snapshot_options options;
  options.unit_in_metres = io::unit_in_mm(scene.units) / 1000.0;
  io::write_snapshot_glb(path, bodies, segments, options);
}

std::vector<io::Pair_summary> run_one(const io::Scene& scene, Scene_stepper& run,
                                      const Scene_outputs& out, const Report_options& options,
                                      bool batch, bool first) {
  std::unique_ptr<std::ofstream> file;
  std::ostream* stream = &std::cout;
  if (!out.report.empty()) {
    file = std::make_unique<std::ofstream>(out.report);
    if (!*file) throw Invalid_input(out.report + ": cannot open for writing");
    stream = file.get();
  }
  std::unique_ptr<Html_report> page;  // -o OUT.html: the page, after the run; no rows
  if (ends_with(out.report, ".html")) page = std::make_unique<Html_report>(scene);
  std::unique_ptr<Report_writer> writer =
      page ? make_null_writer()
      : ends_with(out.report, ".json")
          ? make_json_writer(*stream, scene)
          : make_csv_writer(*stream, first || !out.report.empty(),
                            batch && out.report.empty() ? scene.path : std::string());

  const std::size_t n_pairs = scene.pairs.size();
  Report_rows rows(scene, *writer, options.every);
  std::vector<Pair_series> series(out.plot.empty() ? 0 : n_pairs,
                                  Pair_series(scene.step_count()));
  const int snap_step = out.snapshot.empty() ? -1 : snapshot_step(scene, options.snapshot_time);
  std::vector<Pair_report> snap_reports;
  const int steps = scene.step_count();
  // No bar between rows printed on the same terminal.
  const bool rows_on_terminal = out.report.empty() && ::isatty(STDOUT_FILENO) == 1;
  Progress_bar progress(!options.quiet && !rows_on_terminal,
                        std::filesystem::path(scene.path).filename().string(), steps);

  run_scene(scene, run, [&](int step, double t, const std::vector<Pair_report>& reports) {
    rows.add(t, reports);
    if (page) page->add(step, t, reports);
    for (std::size_t k = 0; k < series.size(); ++k) {
      const bool farther = clearance_state(reports[k].status) == io::Clearance_state::Farther;
      series[k].add(t, farther ? std::nan("") : reports[k].distance);
    }
    if (step == snap_step) snap_reports = reports;
    progress.update(step + 1);
  });
  progress.finish();

  const Report_timing timing = report_timing(run.step_times_us(), run.audit_times_us());
  const std::vector<io::Pair_summary> result = rows.finish(timing);
  if (page) {
    file.reset();  // the page is written whole, in place of the empty stream
    page->write(out.report, result, timing);
  }
  if (file && !*file) throw Invalid_input(out.report + ": write failed");
  for (auto& s : series) s.finish();
  if (!out.plot.empty()) report_plot(scene, series, result).write(out.plot);
  if (!out.snapshot.empty())
    write_snapshot(scene, out.snapshot, scene.time_of(snap_step), snap_reports);

  if (options.quiet) return result;
  std::string written;
  for (const std::string* p : {&out.report, &out.plot, &out.snapshot})
    if (!p->empty()) written += (written.empty() ? "" : ", ") + *p;
  if (!out.snapshot.empty() && scene.time_of(snap_step) != options.snapshot_time)
    written += " (snapshot at the nearest step, t = " + short_number(scene.time_of(snap_step)) + ")";
  // With the rows on stdout the summary goes to stderr, so stdout stays one clean CSV.
  print_summary(out.report.empty() ? std::cerr : std::cout, scene, written, result, timing);
  return result;
}

}  // namespace

int run_report(const Report_options& options) {
  const char* const prefix = "extremal report: ";
  try {
    if (!options.output.empty() && !ends_with(options.output, ".csv") &&
        !ends_with(options.output, ".json") && !ends_with(options.output, ".html"))
      throw Invalid_input("-o " + options.output +
                          ": expected a file name ending in .csv, .json or .html");
    std::optional<io::Clearance_class> fail_level;
    if (!options.fail_on.empty()) {
      fail_level = io::clearance_class_named(options.fail_on);
      if (!fail_level || *fail_level == io::Clearance_class::Clear)
        throw Invalid_input("--fail-on " + options.fail_on +
                            ": expected clash, contact or clearance");
    }
    if (options.clearance && !(*options.clearance > 0.0 && std::isfinite(*options.clearance)))
      throw Invalid_input("--clearance: must be a finite number > 0");
    if (options.threads < 1)
      throw Invalid_input("--threads " + std::to_string(options.threads) + ": must be at least 1");
    if (options.every < 1)  // main() checks it (exit 2); this guards other callers
      throw Invalid_input("--every " + std::to_string(options.every) + ": must be at least 1");
    // Every scene is read (and checked) before any runs: a typo in the last scene of a batch
    // costs nothing.
    std::vector<io::Scene> scenes;
    for (const auto& path : options.scenes) {
      scenes.push_back(io::read_scene(path, io::load_bodies));
      if (options.tolerance) scenes.back().tolerance.absolute = *options.tolerance;
      if (options.relative_tolerance) scenes.back().tolerance.relative = *options.relative_tolerance;
      if (options.clearance) scenes.back().clearance = *options.clearance;
      if (options.memory_limit_mib) scenes.back().tracker.memory_limit_mib = *options.memory_limit_mib;
      if (fail_level == io::Clearance_class::Clearance && !scenes.back().clearance)
        throw Invalid_input(path + ": --fail-on clearance: no clearance to check against (give "
                            "--clearance D, or the scene's \"clearance\")");
    }
    const bool batch = scenes.size() > 1;
    const std::vector<std::string> tags = report::scene_tags(options.scenes);
    std::vector<Scene_outputs> outputs;
    std::vector<std::unique_ptr<Scene_stepper>> runs;  // set up (and so checked) before any runs
    for (std::size_t i = 0; i < scenes.size(); ++i) {
      outputs.push_back({report::batch_path(options.output, tags[i], batch),
                         report::batch_path(options.plot, tags[i], batch),
                         report::batch_path(options.snapshot, tags[i], batch)});
      if (!outputs[i].snapshot.empty()) snapshot_step(scenes[i], options.snapshot_time);
      runs.push_back(scene_stepper(scenes[i], options.threads));
    }
    std::vector<std::string> failing;  // "scene: A - B (class)"
    for (std::size_t i = 0; i < scenes.size(); ++i) {
      const std::vector<io::Pair_summary> summaries =
          run_one(scenes[i], *runs[i], outputs[i], options, batch, i == 0);
      for (std::size_t k = 0; fail_level && k < summaries.size(); ++k) {
        const io::Clearance_verdict& v = summaries[k].clearance;
        if (!io::fails(v, *fail_level)) continue;
        const auto& [a, b] = scenes[i].pairs[k];
        std::string why = io::to_string(v.verdict);
        if (v.verdict == io::Clearance_class::Undecided)
          why += std::string(": ") + io::to_string(v.range.possible) + " not ruled out";
        failing.push_back(scenes[i].path + ": " + scenes[i].bodies[a].name + " - " +
                          scenes[i].bodies[b].name + " (" + why + ")");
      }
    }
    if (failing.empty()) return 0;
    std::cerr << prefix << "--fail-on " << options.fail_on << ": " << failing.size() << " pair"
              << (failing.size() == 1 ? "" : "s") << " at or past it:\n";
    for (const auto& f : failing) std::cerr << "  " << f << "\n";
    return 3;
  } catch (const Invalid_input& e) {
    std::cerr << prefix << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {  // Precondition_violation and anything unforeseen
    std::cerr << prefix << "internal error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace extremal::cli
