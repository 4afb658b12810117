#include "algorithms/distance/Set_distance.h"

#include <algorithm>
#include <cmath>

#include "algorithms/distance/internal/Time_budget.h"
#include "kernel/Error.h"

namespace extremal {

namespace {

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

// The smallest lower bound over the pairs, and how the pair holding it ended.
template <class Status>
struct Lowest {
  double bound = HUGE_VAL;
  Status status = Status::Converged;
  void offer(double lower, Status s) {
    if (lower < bound) bound = lower, status = s;
  }
};

// The loop both set queries share: `query(pair)` on each pair in order, except pairs whose box
// bound reaches `beat()` (the best so far) and those left when the set's time is spent, which
// count with their box bound.
template <class Status, class Beat, class Query>
void query_pairs(const std::vector<Body_pair>& order, const internal::Time_budget& budget,
                 Set_work& work, Lowest<Status>& lowest, Beat beat, Query query) {
  for (const Body_pair& pair : order) {
    if (pair.bound >= beat()) {  // nothing of this pair can beat the best: its boxes say so
      ++work.body_pairs_bounded;
      lowest.offer(pair.bound, Status::Converged);
      continue;
    }
    if (budget.spent()) {  // the boxes are all we know
      ++work.body_pairs_bounded;
      lowest.offer(pair.bound, Status::Budget_exhausted);
      continue;
    }
    ++work.body_pairs_queried;
    query(pair);
  }
}

}  // namespace

Set_distance_result set_distance(const std::vector<Placed_body>& A,
                                 const std::vector<Placed_body>& B, const Distance_request& request,
                                 Distance_workspace& workspace, double max_seconds) {
  check_set(A, "A", false);
  check_set(B, "B", false);
  EXTREMAL_PRECONDITION_MSG(max_seconds >= 0.0, "max_seconds must be >= 0, got " << max_seconds);
  const std::vector<Body_pair> order =
      pairs_by_bound(A, B, [](const Bbox_3& a, const Bbox_3& b) { return box_distance(a, b); });

  Set_distance_result out;
  Distance_result& best = out.result;
  Set_work& work = out.work;
  bool any = false;
  Lowest<Distance_status> lowest;
  auto beat = [&] { return any ? std::min(request.cutoff, best.upper_bound) : request.cutoff; };
  const internal::Time_budget budget(max_seconds);
  query_pairs(order, budget, work, lowest, beat, [&](const Body_pair& pair) {
    Distance_request query = request;
    query.cutoff = beat();
    query.max_seconds = budget.limit_for(request.max_seconds);
    const Placed_body& a = A[static_cast<std::size_t>(pair.a)];
    const Placed_body& b = B[static_cast<std::size_t>(pair.b)];
    const Distance_result r =
        extremal_distance(*a.hierarchy, a.pose, *b.hierarchy, b.pose, query, workspace);
    work.add(r);
    lowest.offer(r.lower_bound, r.status);
    if (r.element_a < 0) return;  // nothing below the cutoff
    if (!any || r.upper_bound < best.upper_bound) {
      best = r;
      out.body_a = pair.a;
      out.body_b = pair.b;
      any = true;
    }
  });

  if (!any) {  // nothing below the request's cutoff, or no query ran
    best = Distance_result();
    best.distance = best.upper_bound = request.cutoff;
    best.lower_bound = HUGE_VAL;
    best.tolerance_used = std::max(
        request.absolute_tolerance,
        request.relative_tolerance * (std::isfinite(request.cutoff) ? request.cutoff : 0.0));
  }
  best.lower_bound = std::min(best.lower_bound, lowest.bound);
  // The sets' distance lies in [lower, best upper]: a pair that stopped short
  // leaves the sets uncertified only when its lower bound opens that gap
  // (bodies that meet stay certified).
  if (!(best.upper_bound - best.lower_bound <= best.tolerance_used))
    best.status = lowest.status == Distance_status::Resolution_limit
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

  Signed_set_distance_result out;
  Signed_distance_result& best = out.result;
  Set_work& work = out.work;
  bool any = false;
  Lowest<Signed_distance_status> lowest;
  auto beat = [&] { return any ? best.upper_bound : HUGE_VAL; };
  const internal::Time_budget budget(max_seconds);
  query_pairs(order, budget, work, lowest, beat, [&](const Body_pair& pair) {
    Signed_distance_request query = request;
    query.total_seconds = budget.limit_for(request.total_seconds);
    // Cut off only well above the tolerance: a query cut off at c settles pairs
    // at c less the tolerance, and only a positive clearance lets containment
    // be tested (at or below it the bodies may overlap unseen).
    const double tol =
        std::max({request.absolute_tolerance,
                  request.relative_tolerance * std::abs(best.upper_bound), best.tolerance_used});
    if (any && best.upper_bound > 2.0 * tol)
      query.apart.cutoff = std::min(request.apart.cutoff, best.upper_bound);
    const Placed_body& a = A[static_cast<std::size_t>(pair.a)];
    const Placed_body& b = B[static_cast<std::size_t>(pair.b)];
    const Signed_distance_result r =
        signed_distance(*a.body, *a.hierarchy, a.pose, *b.body, *b.hierarchy, b.pose, query);
    work.add(r.apart);
    work.cells += r.cells;
    work.supports += r.supports;
    work.winding_cells += r.winding_cells;
    lowest.offer(r.lower_bound, r.status);
    if (r.overlap == Overlap_kind::None && r.apart.element_a < 0) {  // cut off
      // Without a positive clearance (a tolerance raised to the scene's
      // resolution) containment went untested: only the boxes bound the pair.
      if (!(r.apart.lower_bound > 0.0))
        lowest.offer(pair.bound, Signed_distance_status::Budget_exhausted);
      return;
    }
    if (!any || r.upper_bound < best.upper_bound) {
      best = r;
      out.body_a = pair.a;
      out.body_b = pair.b;
      any = true;
    }
  });

  if (!any) {  // no query ran
    best = Signed_distance_result();
    best.status = Signed_distance_status::Budget_exhausted;
    best.distance = best.upper_bound = HUGE_VAL;
    best.lower_bound = HUGE_VAL;
    best.tolerance_used = request.absolute_tolerance;
  }
  best.lower_bound = std::min(best.lower_bound, lowest.bound);
  if (!(best.upper_bound - best.lower_bound <= best.tolerance_used))
    best.status = lowest.status == Signed_distance_status::Resolution_limit ||
                          lowest.status == Signed_distance_status::Containment_unknown
                      ? lowest.status
                      : Signed_distance_status::Budget_exhausted;
  return out;
}

}  // namespace extremal
