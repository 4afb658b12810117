// The numerical stress ladder (bench/experiments/Stress_ladder.h): every rung of every sweep,
// one-shot and tracked, against its quadruple-precision reference. Prints one Markdown table
// per sweep; with --out DIR writes DIR/stress_ladder.md (the same tables) and two log-log plots
// per degeneracy, error and time against the parameter. Exits 1 if a rung fails its checks
// (a NaN, a lower bound above the reference, an error beyond the budget that no status owns).
// Usage: stress_ladder [--out DIR] [--quick | --rung VALUE] [--steps N] [--repeats N] [sweep ...]
// (--rung runs that one parameter value of each sweep named; EXTREMAL_LADDER_TRACE=1 prints
// every tracked row.)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "experiments/Stress_ladder.h"
#include "support/Loglog_plot.h"

using namespace extremal;
using namespace extremal::experiments;

namespace {

std::string sci(double x, int digits = 1) {
  if (std::isinf(x)) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*e", digits, x);
  return buf;
}

std::string rung_row(const Rung_result& r) {
  std::ostringstream os;
  os << "| " << (r.parameter == 0.0 ? "0" : sci(r.parameter, 0)) << " | " << sci(r.reference, 6)
     << " | " << to_string(r.status) << " | " << sci(r.error) << " | " << sci(r.lower_gap)
     << " | " << sci(r.tolerance_used) << " | " << r.nodes << " | " << sci(1e3 * r.seconds, 2)
     << " | " << r.tracked_statuses << " | " << sci(r.tracked_max_error) << " | "
     << (r.bound_rows ? sci(r.tracked_min_lower_gap) + " .. " + sci(r.tracked_max_lower_gap)
                      : std::string("-"))
     << " | " << sci(1e6 * r.step_seconds, 2) << " | ";
  if (r.violations.empty())
    os << "pass";
  else
    for (std::size_t k = 0; k < r.violations.size(); ++k)
      os << (k ? "; " : "") << "**" << r.violations[k] << "**";
  os << " |";
  return os.str();
}

const char* k_header =
    "| rung | reference | one-shot | error | ref - lower | tol. used | nodes | time (ms) | "
    "tracked rows | tracked max error | tracked ref - lower (min .. max) | step (us) | checks |\n"
    "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";

}  // namespace

int main(int argc, char** argv) {
  std::string out;
  bool quick = false;
  std::vector<double> only;
  Ladder_options options;
  std::vector<std::string> names;
  const std::vector<Ladder_sweep>& sweeps = ladder_sweeps();
  auto usage = [&](FILE* to) {
    std::fprintf(to, "usage: stress_ladder [--out DIR] [--quick | --rung VALUE] [--steps N] "
                     "[--repeats N] [sweep ...]\nsweeps:");
    for (const Ladder_sweep& s : sweeps) std::fprintf(to, " %s", s.key.c_str());
    std::fprintf(to, "\n");
  };
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--out") && i + 1 < argc) {
      out = argv[++i];
    } else if (!std::strcmp(argv[i], "--quick")) {
      quick = true;
    } else if (!std::strcmp(argv[i], "--rung") && i + 1 < argc) {
      only.push_back(std::atof(argv[++i]));
    } else if (!std::strcmp(argv[i], "--steps") && i + 1 < argc) {
      options.tracked_steps = std::max(1, std::atoi(argv[++i]));
    } else if (!std::strcmp(argv[i], "--repeats") && i + 1 < argc) {
      options.max_repeats = std::max(1, std::atoi(argv[++i]));  // at least one timed
    } else if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h")) {
      usage(stdout);
      return 0;
    } else if (std::any_of(sweeps.begin(), sweeps.end(),
                           [&](const Ladder_sweep& s) { return s.key == argv[i]; })) {
      names.push_back(argv[i]);
    } else {
      std::fprintf(stderr, "stress_ladder: unknown argument or sweep '%s'\n", argv[i]);
      usage(stderr);
      return 2;
    }
  }
  // Plots and the full table only from a full run (a partial one leaves the committed ones).
  const bool full = names.empty() && !quick && only.empty();
  if (!full && !out.empty())
    std::printf("(a partial run: --out ignored, nothing written)\n");
  std::ostringstream doc;
  doc << "# Stress ladder, every rung\n\nWritten by `stress_ladder --out DIR` (bench/RESULTS.md, "
         "\"Stress ladder\"). One-shot: extremal_distance at 1e-9 (absolute and relative), "
      << options.one_shot.max_nodes << " nodes, median of up to " << options.max_repeats
      << " warm solves. Tracked: Body_pair_tracker, " << options.tracked_steps
      << " rows at 1 kHz about the rung's pose, error budget 1e-9. Errors and bounds against the "
         "quadruple-precision reference.\n";
  std::map<std::string, bench::Loglog_plot> error_plots, time_plots;
  int failed = 0, rungs = 0;
  for (const Ladder_sweep& s : sweeps) {
    if (!names.empty() && std::find(names.begin(), names.end(), s.key) == names.end()) continue;
    std::ostringstream table;
    table << "\n## " << s.title << " (`" << s.key << "`): " << s.parameter << "\n\nReference: "
          << s.reference << ".\n\n" << k_header;
    std::printf("%s", table.str().c_str());
    auto& ep = error_plots[s.family_key];
    auto& tp = time_plots[s.family_key];
    ep.title = "Stress ladder, " + s.family + ": error against the reference";
    ep.x_label = s.family_key == "weights" || s.family_key == "offset"
                     ? s.parameter
                     : s.parameter + " (the rung at 0 is not drawn)";
    ep.y_label = "|distance - reference| (B: budget exhausted; U: uncertified rows)";
    ep.y_floor = 1e-17;
    tp.title = "Stress ladder, " + s.family + ": time";
    tp.x_label = ep.x_label;
    tp.y_label = "one-shot median solve, tracked median step [s]";
    for (double value : !only.empty() ? only : quick ? s.quick : s.values) {
      const Rung_result r = run_rung(s, value, options);
      ++rungs;
      failed += !r.violations.empty();
      const std::string row = rung_row(r);
      std::printf("%s\n", row.c_str());
      std::fflush(stdout);
      table << row << "\n";
      if (value > 0.0) {
        std::string mark;
        if (r.status == Distance_status::Budget_exhausted) mark = "B";
        if (r.status == Distance_status::Resolution_limit) mark = "R";
        ep.add_point(s.title + ", one-shot", value, r.error, mark);
        ep.add_point(s.title + ", tracked", value, r.tracked_max_error,
                     r.uncertified_rows ? "U" : "");
        tp.add_point(s.title + ", one-shot", value, r.seconds, mark);
        tp.add_point(s.title + ", tracked", value, r.step_seconds);
      }
    }
    doc << table.str();
  }
  std::printf("\n%d of %d rungs failed their checks\n", failed, rungs);
  if (full && !out.empty()) {
    for (auto& [family, plot] : error_plots) {
      double lo = HUGE_VAL, hi = 0.0;
      for (const auto& series : plot.series)
        for (double x : series.x) lo = std::min(lo, x), hi = std::max(hi, x);
      plot.add_point("error budget 1e-9", lo, 1e-9);
      plot.add_point("error budget 1e-9", hi, 1e-9);
      plot.write_or_note(out, "stress_ladder_" + family + "_error.svg");
    }
    for (auto& [family, plot] : time_plots)
      plot.write_or_note(out, "stress_ladder_" + family + "_time.svg");
    const std::string path = out + "/stress_ladder.md";
    std::ofstream f(path);
    f << doc.str();
    if (!f) {
      std::fprintf(stderr, "stress_ladder: cannot write '%s'\n", path.c_str());
      return 1;
    }
    std::printf("- table: %s\n", path.c_str());
  }
  return failed ? 1 : 0;
}
