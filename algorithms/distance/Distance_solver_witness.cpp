// Witnesses of the branch and bound: corner points of sub-patch pairs, and Newton polishes of the
// element pair whenever one beats the best so far (Global_distance.h).
#include "algorithms/distance/internal/Distance_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "kernel/Error.h"

namespace extremal::internal {

void Distance_solver::offer(double dist, const Vec3& pa, const Vec3& pb, int ea, const double* qa, int eb,
                   const double* qb) {
  if (!(dist < m_best.distance)) return;
  m_best.distance = dist;
  m_best.pa = pa;
  m_best.pb = pb;
  m_best.ea = ea;
  m_best.eb = eb;
  m_best.qa[0] = qa[0];
  m_best.qa[1] = qa[1];
  m_best.qb[0] = qb[0];
  m_best.qb[1] = qb[1];
  if (dist > m_resolution) {
    m_axis = (pb - pa) / dist;
    m_have_axis = true;
    ++m_axis_stamp;
  }
}

void Distance_solver::corner_candidates(const Live_node& a, const Live_node& b) {
  const Vec3* ca = m_side[0].cart(a);
  const Vec3* cb = m_side[1].cart(b);
  const Distance_hierarchy& ha = *m_side[0].h;
  const Distance_hierarchy& hb = *m_side[1].h;
  // Only pairs that can beat the best witness (offer takes nothing else) are asked whether
  // their corners lie on the body (inside the trim: a point location each), once per corner.
  const double limit2 = m_best.distance < HUGE_VAL
                            ? m_best.distance * m_best.distance * (1.0 + 1e-12)
                            : HUGE_VAL;
  double best = HUGE_VAL;
  int bi = -1, bj = -1;
  int on_b[4] = {-1, -1, -1, -1};  // unknown, no, yes
  for (int i = 0; i < corner_count(a); ++i) {
    double qa[2], qb[2];
    const Vec3& p = ca[corner(a, i, qa)];
    int on_a = -1;
    for (int j = 0; j < corner_count(b); ++j) {
      const double d2 = (cb[corner(b, j, qb)] - p).squaredNorm();
      if (!(d2 < best && d2 < limit2)) continue;
      if (on_a < 0) on_a = ha.on_body(a.element, qa) ? 1 : 0;
      if (!on_a) break;  // outside the trim: not on the body
      if (on_b[j] < 0) on_b[j] = hb.on_body(b.element, qb) ? 1 : 0;
      if (on_b[j]) {
        best = d2;
        bi = i;
        bj = j;
      }
    }
  }
  if (bi < 0) return;
  double qa[2], qb[2];
  const Vec3 pa = ca[corner(a, bi, qa)];
  const Vec3 pb = cb[corner(b, bj, qb)];
  offer(std::sqrt(best), pa, pb, a.element, qa, b.element, qb);
}

bool Distance_solver::inside_known_solution(const Live_node& a, const Live_node& b) const {
  for (const auto& s : m_scratch.solutions) {
    if (s.ea != a.element || s.eb != b.element) continue;
    bool inside = true;
    for (int k = 0; k < a.dim; ++k) inside = inside && s.params[k] >= a.lo[k] && s.params[k] <= a.hi[k];
    for (int k = 0; k < b.dim; ++k)
      inside = inside && s.params[a.dim + k] >= b.lo[k] && s.params[a.dim + k] <= b.hi[k];
    if (inside) return true;
  }
  return false;
}

void Distance_solver::polish(const Live_node& a, const Live_node& b) {
  if (!m_req.newton_polish || inside_known_solution(a, b)) return;
  const Feature& fa = feature(0, a.element);
  const Feature& fb = feature(1, b.element);
  Vec4 start = Vec4::Zero();
  for (int k = 0; k < a.dim; ++k) start[k] = 0.5 * (a.lo[k] + a.hi[k]);
  for (int k = 0; k < b.dim; ++k) start[a.dim + k] = 0.5 * (b.lo[k] + b.hi[k]);
  const Posed_feature pa{&fa, m_side[0].X, nullptr}, pb{&fb, m_side[1].X, nullptr};
  Newton_options opt;
  opt.max_iterations = 30;
  ++m_newton_runs;
  const Newton_result r = solve_pair_at_rest(pa, pb, start, opt);
  if (!r.params.allFinite()) return;
  Feature_point xa, xb;
  evaluate_feature(fa, *m_side[0].X, r.params.data(), xa, 0);
  evaluate_feature(fb, *m_side[1].X, r.params.data() + a.dim, xb, 0);
  const double d = (xb.p - xa.p).norm();
  if (r.converged) {
    m_scratch.solutions.push_back({a.element, b.element, r.params});
    m_scratch.solutions.back().distance = d;
  }
  if (!std::isfinite(d)) return;
  double qa[2] = {0, 0}, qb[2] = {0, 0};
  for (int k = 0; k < a.dim; ++k) qa[k] = r.params[k];
  for (int k = 0; k < b.dim; ++k) qb[k] = r.params[a.dim + k];
  if (!m_side[0].h->on_body(a.element, qa) || !m_side[1].h->on_body(b.element, qb)) return;
  offer(d, xa.p, xb.p, a.element, qa, b.element, qb);
}

}  // namespace extremal::internal
