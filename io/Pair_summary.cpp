#include "io/Pair_summary.h"

namespace extremal::io {

void Pair_summary_builder::extend(std::vector<Time_interval>& runs, bool in_run, bool was_in_run,
                                  double t) {
  if (!in_run) return;
  if (was_in_run)
    runs.back().end = t;
  else
    runs.push_back({t, t});
}

void Pair_summary_builder::add(double t, double distance, Clearance_state state) {
  Pair_summary& s = m_summary;
  ++s.rows;
  const bool farther = state == Clearance_state::Farther;
  const bool penetrating = state == Clearance_state::Penetrating;
  const bool touching = penetrating || state == Clearance_state::Contact;
  const bool uncertified = state == Clearance_state::Uncertified;
  if (!farther) {
    ++s.tracked_rows;
    if (!s.min_distance || distance < *s.min_distance) {
      s.min_distance = distance;
      s.min_time = t;
    }
  }
  if (penetrating && (!s.deepest_penetration || -distance > *s.deepest_penetration)) {
    s.deepest_penetration = -distance;
    s.deepest_time = t;
  }
  extend(s.contact, touching, m_was_contact, t);
  extend(s.penetration, penetrating, m_was_penetrating, t);
  extend(s.farther, farther, m_was_farther, t);
  extend(s.uncertified, uncertified, m_was_uncertified, t);
  m_was_contact = touching;
  m_was_penetrating = penetrating;
  m_was_farther = farther;
  m_was_uncertified = uncertified;
}

}  // namespace extremal::io
