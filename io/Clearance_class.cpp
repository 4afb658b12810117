#include "io/Clearance_class.h"

#include <algorithm>
#include <cmath>

namespace extremal::io {

namespace {

Clearance_class more_severe(Clearance_class a, Clearance_class b) { return std::max(a, b); }

// The class of a row's lower end; no bound (or a NaN one) leaves every class open.
Clearance_class lower_class(std::optional<double> lower, const Clearance_thresholds& t) {
  if (!lower || std::isnan(*lower)) return Clearance_class::Clash;
  return class_of_distance(*lower, t);
}

}  // namespace

const char* to_string(Clearance_class c) {
  switch (c) {
    case Clearance_class::Clear: return "clear";
    case Clearance_class::Clearance: return "clearance";
    case Clearance_class::Contact: return "contact";
    case Clearance_class::Clash: return "clash";
    case Clearance_class::Undecided: return "undecided";
  }
  return "undecided";
}

std::optional<Clearance_class> clearance_class_named(const std::string& name) {
  for (Clearance_class c : {Clearance_class::Clear, Clearance_class::Clearance,
                            Clearance_class::Contact, Clearance_class::Clash})
    if (name == to_string(c)) return c;
  return std::nullopt;
}

Clearance_class class_of_distance(double x, const Clearance_thresholds& t) {
  if (x < -t.contact) return Clearance_class::Clash;
  if (x <= t.contact) return Clearance_class::Contact;
  if (t.clearance && x < *t.clearance) return Clearance_class::Clearance;
  return Clearance_class::Clear;
}

Class_range row_class(Clearance_state state, double distance, std::optional<double> lower_bound,
                      const Clearance_thresholds& t) {
  switch (state) {
    case Clearance_state::Penetrating: return {Clearance_class::Clash, Clearance_class::Clash};
    case Clearance_state::Contact: return {Clearance_class::Contact, Clearance_class::Contact};
    case Clearance_state::Farther:  // a box bound below, nothing above
      return {Clearance_class::Clear, lower_class(lower_bound, t)};
    case Clearance_state::Apart:
    case Clearance_state::Uncertified: break;
  }
  // Apart: the distance is a real pair's (an upper bound), the lower bound certified.
  if (std::isnan(distance)) return {Clearance_class::Clear, Clearance_class::Clash};
  const Clearance_class proven = class_of_distance(distance, t);
  return {proven, more_severe(proven, lower_class(lower_bound, t))};
}

bool fails(const Clearance_verdict& v, Clearance_class level) {
  return v.range.possible >= level;
}

Clearance_class_builder::Clearance_class_builder(const Clearance_thresholds& thresholds)
    : m_thresholds(thresholds) {}

void Clearance_class_builder::add(double t, Clearance_state state, double distance,
                                  std::optional<double> lower_bound) {
  const Class_range r = row_class(state, distance, lower_bound, m_thresholds);
  m_range = m_any ? Class_range{more_severe(m_range.proven, r.proven),
                                more_severe(m_range.possible, r.possible)}
                  : r;
  m_any = true;
  const long row = m_rows++;
  if (r.possible == r.proven) return;
  if (!m_open_runs.empty() && m_open_runs.back().last_row == row - 1 &&
      m_open_runs.back().possible == r.possible) {
    m_open_runs.back().span.end = t;
    m_open_runs.back().last_row = row;
  } else {
    m_open_runs.push_back({{t, t}, row, row, r.possible});
  }
}

Clearance_verdict Clearance_class_builder::verdict() const {
  Clearance_verdict v;
  v.range = m_range;
  v.verdict = m_range.proven == m_range.possible ? m_range.proven : Clearance_class::Undecided;
  long last_row = -2;
  for (const Run& run : m_open_runs) {
    if (!(run.possible > m_range.proven)) continue;
    if (!v.undecided.empty() && run.first_row == last_row + 1)
      v.undecided.back().end = run.span.end;
    else
      v.undecided.push_back(run.span);
    last_row = run.last_row;
  }
  return v;
}

}  // namespace extremal::io
