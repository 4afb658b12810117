// bench/compare --budget-sweep: what the error budget costs the body-pair tracker, against
// FCL's tessellation ladder on the same scenario (the sweeps of (b) and (c) in compare.cpp, of
// (d) in compare_assembly.cpp; the table and the plot here).
#pragma once

#include <algorithm>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/body_pair/Body_pair_options.h"
#include "algorithms/body_pair/Pair_report.h"

namespace extremal::bench {

// The budgets swept (Body_pair_options::tolerance, absolute and relative alike), loose to tight.
inline constexpr double k_swept_budgets[] = {1e-3, 1e-6, 1e-9, 1e-12};

// A tracker run read against its budget (Error_budget::at the distance): its largest error
// against the reference, its largest certified gap (distance - Pair_report::lower_bound) over
// the pair rows it certified, and the rows it left Uncertified (whose bound is short of it).
struct Budget_check {
  Error_budget budget;
  double max_error_share = 0.0, max_gap_share = 0.0;
  long uncertified = 0;

  void add_error(double error, double reference) {
    max_error_share = std::max(max_error_share, error / budget.at(reference));
  }
  void add_report(const Pair_report& r) {
    if (r.status == Pair_status::Uncertified)
      ++uncertified;
    else if (r.lower_bound)
      max_gap_share = std::max(max_gap_share, (r.distance - *r.lower_bound) / budget.at(r.distance));
  }
};

// One row of a sweep: the tracker at one budget and rate, or FCL on one tessellation.
struct Budget_sweep_row {
  std::string series;       // the plot's series the row's point joins
  std::string point_label;  // beside its point in the plot (the budget, FCL's triangles)
  std::string method, setting;
  // The moving body where a scenario has several (d): a row's speed-up is against FCL's rows of
  // the same body only.
  std::string mover;
  long frames = 0;  // frames per run (trackers); else the number of timed queries
  double median_us = std::numeric_limits<double>::quiet_NaN();  // per frame
  double max_error = std::numeric_limits<double>::quiet_NaN();  // against the reference
  int failures = 0;  // frames without a finite distance
  std::optional<Budget_check> check;  // tracker rows
};

struct Budget_sweep {
  std::string key, title;
  std::string notes;  // what was run and how the rows are measured, printed above the table
  std::vector<Budget_sweep_row> rows;
};

// Prints the sweep's Markdown table, with each row's speed-up over FCL's most accurate row of
// the same mover measured in the same run, and with an `out_dir` writes out_dir/compare_budget_<key>.svg:
// log-log median time per frame against maximum error, a line per series.
void report_budget_sweep(const Budget_sweep& sweep, const std::string& out_dir);

}  // namespace extremal::bench
