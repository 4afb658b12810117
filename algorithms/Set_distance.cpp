#include "algorithms/Set_distance.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include "kernel/Error.h"

namespace extremal {

namespace {

using Clock = std::chrono::steady_clock;

void check_set(const std::vector<Placed_body>& set, const char* which, bool need_body) {
  EXTREMAL_PRECONDITION_MSG(!set.empty(), "set " << which << " holds no body");
  for (std::size_t i = 0; i < set.size(); ++i) {
    EXTREMAL_PRECONDITION_MSG(set[i].hierarchy != nullptr,
                              "set " << which << ", body " << i << ": no hierarchy");
    EXTREMAL_PRECONDITION_MSG(!need_body || set[i].body != nullptr,
                              "set " << which << ", body " << i << ": no body");
  }
}

Bbox_3 world_box(const Placed_body& p) { return transformed(p.hierarchy->box(), p.pose); }

struct Body_pair {
  double bound;  // certified lower bound from the boxes
  int a, b;
};

// Every body pair with its box bound, smallest first; ties keep A-major order.
template <class Bound>
std::vector<Body_pair> pairs_by_bound(const std::vector<Placed_body>& A,
                                      const std::vector<Placed_body>& B, Bound bound) {
  std::vector<Bbox_3> boxes_b;
  for (const Placed_body& p : B) boxes_b.push_back(world_box(p));
  std::vector<Body_pair> order;
  order.reserve(A.size() * B.size());
  for (std::size_t i = 0; i < A.size(); ++i) {
    const Bbox_3 box_a = world_box(A[i]);
    for (std::size_t j = 0; j < B.size(); ++j)
      order.push_back({bound(box_a, boxes_b[j]), static_cast<int>(i), static_cast<int>(j)});
  }
  std::stable_sort(order.begin(), order.end(),
                   [](const Body_pair& x, const Body_pair& y) { return x.bound < y.bound; });
  return order;
}

// The whole set's time: what is left for the next query (nullopt: no limit; <= 0: none left).
class Set_clock {
 public:
  explicit Set_clock(double max_seconds) : m_limit(max_seconds), m_start(Clock::now()) {}
  std::optional<double> left() const {
    if (m_limit <= 0.0) return std::nullopt;
    return m_limit - std::chrono::duration<double>(Clock::now() - m_start).count();
  }

 private:
  double m_limit;
  Clock::time_point m_start;
};

// A query's own limit (0: none) within what the set has left.
double within(double own, const std::optional<double>& left) {
  if (!left) return own;
  return own > 0.0 ? std::min(own, *left) : *left;
}

}  // namespace

Set_distance_result set_distance(const std::vector<Placed_body>& A,
                                 const std::vector<Placed_body>& B,
                                 const Distance_request& request, Distance_workspace& workspace,
                                 double max_seconds) {
  check_set(A, "A", false);
  check_set(B, "B", false);
  EXTREMAL_PRECONDITION_MSG(max_seconds >= 0.0, "max_seconds must be >= 0, got " << max_seconds);
  const std::vector<Body_pair> order =
      pairs_by_bound(A, B, [](const Bbox_3& a, const Bbox_3& b) { return box_distance(a, b); });
  const Set_clock clock(max_seconds);

  Set_distance_result out;
  Distance_result& best = out.result;
  bool any = false;
  double lower = HUGE_VAL;  // smallest lower bound over all pairs, and the status of its pair
  Distance_status lower_status = Distance_status::Converged;
  long pairs = 0, nodes = 0;
  int newton = 0, intersections = 0;
  for (const Body_pair& pair : order) {
    const double cutoff = any ? std::min(request.cutoff, best.upper_bound) : request.cutoff;
    if (pair.bound >= cutoff) {  // nothing of this pair below the cutoff: its boxes say so
      ++out.pairs_skipped;
      if (pair.bound < lower) lower = pair.bound, lower_status = Distance_status::Converged;
      continue;
    }
    const std::optional<double> left = clock.left();
    if (left && *left <= 0.0) {  // the set's time is spent: the boxes are all we know
      ++out.pairs_skipped;
      if (pair.bound < lower) lower = pair.bound, lower_status = Distance_status::Budget_exhausted;
      continue;
    }
    Distance_request query = request;
    query.cutoff = cutoff;
    query.max_seconds = within(request.max_seconds, left);
    const Placed_body& a = A[static_cast<std::size_t>(pair.a)];
    const Placed_body& b = B[static_cast<std::size_t>(pair.b)];
    const Distance_result r =
        extremal_distance(*a.hierarchy, a.pose, *b.hierarchy, b.pose, query, workspace);
    ++out.pairs_queried;
    pairs += r.pairs_processed;
    nodes += r.nodes_created;
    newton += r.newton_runs;
    intersections += r.intersection_attempts;
    if (r.lower_bound < lower) lower = r.lower_bound, lower_status = r.status;
    if (r.element_a < 0) continue;  // nothing below the cutoff
    if (!any || r.upper_bound < best.upper_bound) {
      best = r;
      out.body_a = pair.a;
      out.body_b = pair.b;
      any = true;
    }
  }

  if (!any) {  // nothing below the request's cutoff (or no query could run)
    best = Distance_result();
    best.distance = best.upper_bound = request.cutoff;
    best.lower_bound = std::min(lower, request.cutoff);
    best.tolerance_used = std::max(request.absolute_tolerance,
                                   request.relative_tolerance *
                                       (std::isfinite(request.cutoff) ? request.cutoff : 0.0));
  }
  best.lower_bound = std::min(best.lower_bound, lower);
  best.pairs_processed = pairs;
  best.nodes_created = nodes;
  best.newton_runs = newton;
  best.intersection_attempts = intersections;
  // The sets' distance lies in [lower, best upper]: a pair that stopped short leaves the sets
  // uncertified only when its lower bound opens that gap (bodies that meet stay certified).
  if (!(best.upper_bound - best.lower_bound <= best.tolerance_used))
    best.status = lower_status == Distance_status::Resolution_limit
                      ? Distance_status::Resolution_limit
                      : Distance_status::Budget_exhausted;
  return out;
}

Signed_set_distance_result signed_set_distance(const std::vector<Placed_body>& A,
                                               const std::vector<Placed_body>& B,
                                               const Signed_distance_request& request,
                                               double max_seconds) {
  check_set(A, "A", true);
  check_set(B, "B", true);
  EXTREMAL_PRECONDITION_MSG(max_seconds >= 0.0, "max_seconds must be >= 0, got " << max_seconds);
  const std::vector<Body_pair> order = pairs_by_bound(A, B, signed_box_bound);
  const Set_clock clock(max_seconds);

  Signed_set_distance_result out;
  Signed_distance_result& best = out.result;
  bool any = false;
  double lower = HUGE_VAL;
  Signed_distance_status lower_status = Signed_distance_status::Converged;
  Distance_result work;  // the apart queries' work, summed
  long cells = 0, supports = 0, winding_cells = 0;
  for (const Body_pair& pair : order) {
    if (any && pair.bound >= best.upper_bound) {
      ++out.pairs_skipped;
      if (pair.bound < lower) lower = pair.bound, lower_status = Signed_distance_status::Converged;
      continue;
    }
    const std::optional<double> left = clock.left();
    if (left && *left <= 0.0) {
      ++out.pairs_skipped;
      if (pair.bound < lower)
        lower = pair.bound, lower_status = Signed_distance_status::Budget_exhausted;
      continue;
    }
    Signed_distance_request query = request;
    query.max_seconds = within(request.max_seconds, left);
    query.apart.max_seconds = within(request.apart.max_seconds, left);
    // A pair whose surfaces lie farther apart than a positive best can win only by containment,
    // which signed_distance tests whatever the apart query's cutoff.
    if (any && best.upper_bound > 0.0)
      query.apart.cutoff = std::min(request.apart.cutoff, best.upper_bound);
    const Placed_body& a = A[static_cast<std::size_t>(pair.a)];
    const Placed_body& b = B[static_cast<std::size_t>(pair.b)];
    const Signed_distance_result r =
        signed_distance(*a.body, *a.hierarchy, a.pose, *b.body, *b.hierarchy, b.pose, query);
    ++out.pairs_queried;
    work.pairs_processed += r.apart.pairs_processed;
    work.nodes_created += r.apart.nodes_created;
    work.newton_runs += r.apart.newton_runs;
    work.intersection_attempts += r.apart.intersection_attempts;
    cells += r.cells;
    supports += r.supports;
    winding_cells += r.winding_cells;
    if (r.lower_bound < lower) lower = r.lower_bound, lower_status = r.status;
    if (r.overlap == Overlap_kind::None && r.apart.element_a < 0) continue;  // cut off
    if (!any || r.upper_bound < best.upper_bound) {
      best = r;
      out.body_a = pair.a;
      out.body_b = pair.b;
      any = true;
    }
  }

  if (!any) {
    best = Signed_distance_result();
    best.status = Signed_distance_status::Budget_exhausted;
    best.distance = best.upper_bound = HUGE_VAL;
    best.tolerance_used = request.absolute_tolerance;
  }
  best.lower_bound = std::min(best.lower_bound, lower);
  best.apart.pairs_processed = work.pairs_processed;
  best.apart.nodes_created = work.nodes_created;
  best.apart.newton_runs = work.newton_runs;
  best.apart.intersection_attempts = work.intersection_attempts;
  best.cells = cells;
  best.supports = supports;
  best.winding_cells = winding_cells;
  if (!(best.upper_bound - best.lower_bound <= best.tolerance_used))
    best.status = lower_status == Signed_distance_status::Resolution_limit ||
                          lower_status == Signed_distance_status::Containment_unknown
                      ? lower_status
                      : Signed_distance_status::Budget_exhausted;
  return out;
}

}  // namespace extremal
