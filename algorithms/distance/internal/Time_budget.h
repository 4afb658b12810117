// A wall-time budget shared by the phases or queries of one call (a set of body
// pairs, the apart query and the depth search of a signed distance): each gets
// what is left of it.
#pragma once

#include <algorithm>
#include <chrono>
#include <limits>

namespace extremal::internal {

class Time_budget {
 public:
  // `seconds` 0: no limit.
  explicit Time_budget(double seconds) : m_seconds(seconds), m_start(Clock::now()) {}

  // Whether there is a limit and nothing is left of it.
  bool spent() const { return m_seconds > 0.0 && left() <= 0.0; }

  // A phase's own limit (0: none) within what is left. Never 0 under a limit (0 would mean no
  // limit): a spent budget gives the smallest positive time, which stops the phase at its first
  // check.
  double limit_for(double own) const {
    if (m_seconds <= 0.0) return own;
    const double rest = std::max(left(), std::numeric_limits<double>::min());
    return own > 0.0 ? std::min(own, rest) : rest;
  }

 private:
  using Clock = std::chrono::steady_clock;
  double left() const {
    return m_seconds - std::chrono::duration<double>(Clock::now() - m_start).count();
  }
  double m_seconds;
  Clock::time_point m_start;
};

}  // namespace extremal::internal
