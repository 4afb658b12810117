#include "compare_budget.h"

#include <cstdio>
#include <iterator>

#include "support/Loglog_plot.h"

namespace extremal::bench {

namespace {

// FCL's row of `mover` with the smallest maximum error (FCL's best accuracy), or null.
const Budget_sweep_row* best_fcl(const std::vector<Budget_sweep_row>& rows,
                                 const std::string& mover) {
  const Budget_sweep_row* best = nullptr;
  for (const Budget_sweep_row& r : rows)
    if (!r.check && r.mover == mover && (!best || r.max_error < best->max_error)) best = &r;
  return best;
}

}  // namespace

void report_budget_sweep(const Budget_sweep& sweep, const std::string& out_dir) {
  std::printf("\n### (%s) the error budget against FCL's ladder: %s\n\n%s\n\n", sweep.key.c_str(),
              sweep.title.c_str(), sweep.notes.c_str());
  std::printf("Budget E: Body_pair_options::tolerance, absolute and relative E. Against the "
              "budget at a distance d, max(E, E d): the error at the reference distance, and the "
              "certified gap (distance - lower bound) at the row's distance over the pair rows "
              "certified; uncertified: pair rows reported Uncertified. Speed-up = FCL's median "
              "time at its best error / the row's.\n\n");
  std::printf("| method | budget | setting | frames | median time per frame (us) | max error | "
              "max error / budget | max certified gap / budget | uncertified | failed | "
              "speed-up vs FCL at its best error |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Budget_sweep_row& r : sweep.rows) {
    char budget[32] = "-", error_share[32] = "-", gap_share[32] = "-", uncertified[32] = "-",
         speed_up[32] = "-";
    if (r.check) {
      std::snprintf(budget, sizeof budget, "%.0e", r.check->budget.absolute);
      std::snprintf(error_share, sizeof error_share, "%.1e", r.check->max_error_share);
      std::snprintf(gap_share, sizeof gap_share, "%.2f", r.check->max_gap_share);
      std::snprintf(uncertified, sizeof uncertified, "%ld", r.check->uncertified);
    }
    const Budget_sweep_row* fcl = best_fcl(sweep.rows, r.mover);
    if (fcl && fcl != &r)
      std::snprintf(speed_up, sizeof speed_up, "%.3g", fcl->median_us / r.median_us);
    std::printf("| %s | %s | %s | %ld | %.3g | %.1e | %s | %s | %s | %d | %s |\n", r.method.c_str(),
                budget, r.setting.c_str(), r.frames, r.median_us, r.max_error, error_share,
                gap_share, uncertified, r.failures, speed_up);
  }
  std::fflush(stdout);

  Loglog_plot plot =
      time_error_plot("(" + sweep.key + ") " + sweep.title + ": the error budget against FCL's ladder");
  for (const Budget_sweep_row& r : sweep.rows)
    plot.add_point(r.series, r.median_us, r.max_error, r.point_label);
  // The budgets' points of a series often lie close together (the budget changes the time,
  // not the error): their labels in as many rows as there are budgets.
  for (Loglog_series& series : plot.series)
    series.label_rows = static_cast<int>(std::size(k_swept_budgets));
  std::printf("\n");
  plot.write_or_note(out_dir, "compare_budget_" + sweep.key + ".svg");
}

}  // namespace extremal::bench
