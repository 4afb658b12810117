// Common points of the two bodies: Gauss-Newton on f_A = f_B, and whether they cross or touch
// there (Global_distance.h).
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

// Gauss-Newton on f(x_A) = h(x_B) from the centres of the two nodes: a common point ends the
// query with distance 0.
bool Distance_solver::try_intersection(const Live_node& a, const Live_node& b) {
  Vec4 x = Vec4::Zero();
  for (int k = 0; k < a.dim; ++k) x[k] = 0.5 * (a.lo[k] + a.hi[k]);
  for (int k = 0; k < b.dim; ++k) x[a.dim + k] = 0.5 * (b.lo[k] + b.hi[k]);
  return try_intersection(a.element, b.element, x);
}

bool Distance_solver::try_intersection(int ea, int eb, Vec4 x) {
  ++m_intersection_attempts;
  const Feature& fa = feature(0, ea);
  const Feature& fb = feature(1, eb);
  const int na = fa.dimension(), nb = fb.dimension(), n = na + nb;
  if (n == 0) return false;
  Vec4 max_step = Vec4::Zero();
  for (int k = 0; k < na; ++k) max_step[k] = 0.25 * (fa.upper(k) - fa.lower(k));
  for (int k = 0; k < nb; ++k) max_step[na + k] = 0.25 * (fb.upper(k) - fb.lower(k));
  const Parameter_domain domain = Parameter_domain::of(fa, fb);
  Feature_point xa, xb;
  double last = HUGE_VAL;
  int stalls = 0;
  for (int it = 0; it < 40; ++it) {
    const unsigned on_bound = domain.clamp(x), lower = domain.lower_mask(x);
    evaluate_feature(fa, *m_side[0].X, x.data(), xa, 1);
    evaluate_feature(fb, *m_side[1].X, x.data() + na, xb, 1);
    const Vec3 d = xa.p - xb.p;
    const double dn = d.norm();
    if (dn <= m_resolution) {
      double qa[2] = {x[0], na > 1 ? x[1] : 0.0}, qb[2] = {x[na], nb > 1 ? x[na + 1] : 0.0};
      if (na == 0) qa[0] = 0.0;
      if (nb == 0) qb[0] = qb[1] = 0.0;
      // A common point of the untrimmed patches outside a trim is not a common point.
      if (!m_side[0].h->on_body(ea, qa) || !m_side[1].h->on_body(eb, qb)) return false;
      const Vec3 mid = 0.5 * (xa.p + xb.p);
      m_best.distance = 0.0;
      m_best.pa = m_best.pb = mid;
      m_best.ea = ea;
      m_best.eb = eb;
      m_best.qa[0] = qa[0];
      m_best.qa[1] = qa[1];
      m_best.qb[0] = qb[0];
      m_best.qb[1] = qb[1];
      m_met = true;
      return true;
    }
    if (dn > 0.999 * last) {
      if (++stalls >= 3) return false;
    } else {
      stalls = 0;
    }
    last = std::min(last, dn);
    Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 4> J(3, n);
    for (int k = 0; k < na; ++k) J.col(k) = xa.d[k];
    for (int k = 0; k < nb; ++k) J.col(na + k) = -xb.d[k];
    Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 4, 1> s(n);
    // A parameter on a bound that the step would push outward is held and the step taken
    // without it: clamped, it stalled the search (a tilted cap's rim crossing a plate, started
    // from the rim: the bodies read 7e-11 apart, 5 deep).
    unsigned held = 0u;
    for (int pass = 0; pass <= n; ++pass) {
      Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 4> Jf = J;
      int free = n;
      for (int k = 0; k < n; ++k)
        if (held & (1u << k)) {
          Jf.col(k).setZero();
          --free;
        }
      if (free >= 3) {  // minimum-norm step
        Eigen::Matrix3d G = Jf * Jf.transpose();
        G.diagonal().array() += 1e-14 * G.trace() + 1e-300;
        s = -Jf.transpose() * G.ldlt().solve(d);
      } else {  // least squares
        Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 4, 4> G = Jf.transpose() * Jf;
        G.diagonal().array() += 1e-14 * G.trace() + 1e-300;
        s = -G.ldlt().solve(Jf.transpose() * d);  // zero along held columns
      }
      unsigned out = 0u;
      for (int k = 0; k < n; ++k)
        if ((on_bound & ~held & (1u << k)) && ((lower & (1u << k)) ? s[k] < 0.0 : s[k] > 0.0))
          out |= 1u << k;
      if (!out) break;
      held |= out;
    }
    if (!s.allFinite()) return false;
    double scale = 1.0;
    for (int k = 0; k < n; ++k)
      if (std::abs(s[k]) > max_step[k] && max_step[k] > 0.0)
        scale = std::min(scale, max_step[k] / std::abs(s[k]));
    for (int k = 0; k < n; ++k) x[k] += scale * s[k];
  }
  return false;
}

// At a common point: transversal when the tangent spaces together span space (a crossing that
// persists under perturbation), else touching; A's outward normal there when A is a surface.
void Distance_solver::classify_meeting() {
  m_transversal = false;
  m_meet_normal.setZero();
  if (m_best.ea < 0 || m_best.eb < 0) return;
  const Feature& fa = feature(0, m_best.ea);
  const Feature& fb = feature(1, m_best.eb);
  const int na = fa.dimension(), nb = fb.dimension();
  Feature_point xa, xb;
  evaluate_feature(fa, *m_side[0].X, m_best.qa, xa, 1);
  evaluate_feature(fb, *m_side[1].X, m_best.qb, xb, 1);
  if (na + nb >= 3) {
    Eigen::Matrix3d G = Eigen::Matrix3d::Zero();
    for (int k = 0; k < na; ++k) G += xa.d[k].normalized() * xa.d[k].normalized().transpose();
    for (int k = 0; k < nb; ++k) G += xb.d[k].normalized() * xb.d[k].normalized().transpose();
    m_transversal = G.allFinite() && G.determinant() > 1e-9;
  }
  m_meet_normal = surface_normal(0);
  if (m_meet_normal == Vec3::Zero()) m_meet_normal = surface_normal(1);
}

Vec3 Distance_solver::surface_normal(int side) const {
  const int e = side == 0 ? m_best.ea : m_best.eb;
  if (e < 0) return Vec3::Zero();
  const Feature& f = feature(side, e);
  if (f.dimension() != 2) return Vec3::Zero();
  Feature_point x;
  evaluate_feature(f, *m_side[side].X, side == 0 ? m_best.qa : m_best.qb, x, 1);
  const Vec3 nn = x.d[0].cross(x.d[1]) * f.outward_sign();
  // (At a pole the cross product is rounding: no normal.)
  const double n2 = nn.squaredNorm();
  if (!(n2 > 1e-16 * x.d[0].squaredNorm() * x.d[1].squaredNorm()) || !(n2 < HUGE_VAL))
    return Vec3::Zero();
  return (side == 0 ? 1.0 : -1.0) * nn / std::sqrt(n2);
}

}  // namespace extremal::internal
