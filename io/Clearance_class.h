// The clearance class of a watched pair over a run (docs/cli.md, "Clearance classes"): a
// verdict per pair, decided from each row's certified bounds, not from its distance alone.
//
// A row bounds the bodies' true distance x at its step: a `penetrating` row is a clash and a
// `contact` row a contact (the tracker's status); an apart row has lower <= x <= distance (its
// distance is a real pair's: an upper bound; its lower bound certified, none: unbounded below);
// a `farther` row has lower <= x, unbounded above. The class of a distance x is
//   clash      x < -contact
//   contact    |x| <= contact
//   clearance  contact < x < clearance  (only with a clearance)
//   clear      otherwise
// and the row's proven class is that of its upper end, its possible class that of its lower end.
// The pair's proven class is the most severe proven at any row, its possible class the most
// severe possible at any row; it is decided when the two agree, else `undecided`.
// Shown by test_clearance_class.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace extremal::io {

// The state of a row, from the report's status word (the summaries' too, io/Pair_summary.h).
enum class Clearance_state {
  Apart,        // tracked, apart (tracking, boundary, fallback)
  Contact,      // |distance| within the contact tolerance
  Penetrating,  // distance below minus the contact tolerance
  Farther,      // beyond the threshold, not tracked: the distance is only a lower bound
  Uncertified,  // apart, its certified lower bound short of the error budget
};

// A run of consecutive rows in one state: the times of its first and last row. An interval of
// one row has start == end.
struct Time_interval {
  double start = 0.0, end = 0.0;
};

// In increasing severity; Undecided is no severity of its own.
enum class Clearance_class { Clear, Clearance, Contact, Clash, Undecided };
const char* to_string(Clearance_class c);
// "clear", "clearance", "contact", "clash" (a --fail-on level); nullopt for anything else.
std::optional<Clearance_class> clearance_class_named(const std::string& name);

struct Clearance_thresholds {
  double contact = 0.0;             // |distance| at or below it is contact (> 0)
  std::optional<double> clearance;  // closer than it is `clearance` (none: no such class)
};

// The class of a true signed distance x.
Clearance_class class_of_distance(double x, const Clearance_thresholds& thresholds);

// What one row proves and leaves open: the least and the most severe class of its true distance.
struct Class_range {
  Clearance_class proven = Clearance_class::Clear, possible = Clearance_class::Clear;
};
Class_range row_class(Clearance_state state, double distance, std::optional<double> lower_bound,
                      const Clearance_thresholds& thresholds);

struct Clearance_verdict {
  Clearance_class verdict = Clearance_class::Clear;  // Undecided when proven != possible
  Class_range range;  // the pair's proven and possible classes
  // The rows whose possible class is more severe than the pair's proven class: where a bound
  // leaves the verdict open (empty when decided).
  std::vector<Time_interval> undecided;
};

// Whether a --fail-on LEVEL check fails: the pair's possible class reaches LEVEL (so an
// undecided pair fails every level its range reaches; a gate passes only what is proved).
bool fails(const Clearance_verdict& v, Clearance_class level);

class Clearance_class_builder {
 public:
  explicit Clearance_class_builder(const Clearance_thresholds& thresholds);
  // Rows in increasing time.
  void add(double t, Clearance_state state, double distance, std::optional<double> lower_bound);
  Clearance_verdict verdict() const;

 private:
  Clearance_thresholds m_thresholds;
  Class_range m_range;
  bool m_any = false;
  // Runs of consecutive rows whose possible class exceeds their proven one, one possible class
  // per run (the verdict keeps those above the pair's proven class, joining neighbours).
  struct Run {
    Time_interval span;
    long first_row = 0, last_row = 0;
    Clearance_class possible = Clearance_class::Clear;
  };
  std::vector<Run> m_open_runs;
  long m_rows = 0;
};

}  // namespace extremal::io
