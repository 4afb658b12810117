// What a report says about one watched pair over a run, in a few numbers: the minimum clearance
// and when, the intervals in contact and in penetration, the deepest penetration, and the
// intervals the pair spent farther than the scene's threshold. Fed one row at a time in time
// order (`extremal report` summaries, its JSON report and its plot).
#pragma once

#include <optional>
#include <vector>

#include "io/Clearance_class.h"

namespace extremal::io {

struct Pair_summary {
  int rows = 0;          // rows fed
  int tracked_rows = 0;  // rows not farther
  // Smallest tracked distance and the first time it occurred; empty when every row was farther.
  std::optional<double> min_distance;
  double min_time = 0.0;
  // Rows touching or inside (distance <= the contact tolerance: contact or penetrating).
  std::vector<Time_interval> contact;
  // Rows inside (penetrating).
  std::vector<Time_interval> penetration;
  // Rows beyond the threshold.
  std::vector<Time_interval> farther;
  // Apart rows whose certified lower bound fell short of the error budget.
  std::vector<Time_interval> uncertified;
  // Deepest penetration (a positive depth, -distance) and the first time it occurred; empty
  // when the pair never penetrated.
  std::optional<double> deepest_penetration;
  double deepest_time = 0.0;
  // The pair's clearance class, from every row's bounds (io/Clearance_class.h); filled by the
  // report (algorithms/scene/Report_rows), which knows the thresholds.
  Clearance_verdict clearance;
};

class Pair_summary_builder {
 public:
  // Rows must come in increasing time.
  void add(double t, double distance, Clearance_state state);
  const Pair_summary& summary() const { return m_summary; }

 private:
  static void extend(std::vector<Time_interval>& runs, bool in_run, bool was_in_run, double t);
  Pair_summary m_summary;
  bool m_was_contact = false, m_was_penetrating = false, m_was_farther = false;
  bool m_was_uncertified = false;
};

}  // namespace extremal::io
