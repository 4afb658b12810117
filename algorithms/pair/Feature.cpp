#include "algorithms/pair/Feature.h"

#include <cmath>

namespace extremal {

Feature::Feature(Kind k, const Nurbs_curve_3* c, const Nurbs_surface_3* s, const Vec3& p)
    : m_kind(k), m_curve(c), m_surface(s), m_point(p) {
  if (c) m_size = box_diagonal(c->hull_bbox());
  if (!s) return;
  m_size = box_diagonal(s->hull_bbox());
  const double tol = 1e-12 * m_size;
  const int nu = s->number_of_poles_u(), nv = s->number_of_poles_v();
  auto collapsed = [&](bool along_v, int fixed) {
    const int count = along_v ? nv : nu;
    const Point_3& first = along_v ? s->pole(fixed, 0) : s->pole(0, fixed);
    for (int k = 1; k < count; ++k) {
      const Point_3& q = along_v ? s->pole(fixed, k) : s->pole(k, fixed);
      if (std::sqrt(CGAL::squared_distance(first, q)) > tol) return false;
    }
    return true;
  };
  if (collapsed(true, 0)) m_collapsed |= 1u;
  if (collapsed(true, nu - 1)) m_collapsed |= 2u;
  if (collapsed(false, 0)) m_collapsed |= 4u;
  if (collapsed(false, nv - 1)) m_collapsed |= 8u;
}

double Feature::lower(int i) const {
  if (m_surface) return i == 0 ? m_surface->u_min() : m_surface->v_min();
  if (m_curve) return m_curve->domain_min();
  return 0.0;
}

double Feature::upper(int i) const {
  if (m_surface) return i == 0 ? m_surface->u_max() : m_surface->v_max();
  if (m_curve) return m_curve->domain_max();
  return 0.0;
}

bool Feature::is_closed(int i) const {
  if (m_surface) return i == 0 ? m_surface->is_closed_u() : m_surface->is_closed_v();
  if (m_curve) return m_curve->is_closed();
  return false;
}

void evaluate_feature(const Feature& f, const Rigid_pose_3& X_WA, const double* params,
                      Feature_point& out, int order, Span_hint* hint) {
  const Mat3& R = X_WA.rotation();
  switch (f.kind()) {
    case Feature::Kind::Point:
      out.p = X_WA.apply_point(f.point_in_body());
      return;
    case Feature::Kind::Curve: {
      Curve_point cp;
      f.curve()->evaluate(params[0], cp, order);
      out.p = X_WA.apply_point(cp.p);
      if (order >= 1) out.d[0] = R * cp.d1;
      if (order >= 2) out.dd[0][0] = R * cp.d2;
      return;
    }
    case Feature::Kind::Surface: {
      // Rows p, du, dv, duu, duv, dvv, straight from the evaluation kernel (the hot path).
      double rows[6][4];
      f.surface()->evaluate_placed_rows(params[0], params[1], R, X_WA.translation(), rows, order,
                                          hint);
      out.p = Vec3::Map(rows[0]);
      if (order >= 1) {
        out.d[0] = Vec3::Map(rows[1]);
        out.d[1] = Vec3::Map(rows[2]);
      }
      if (order >= 2) {
        out.dd[0][0] = Vec3::Map(rows[3]);
        out.dd[0][1] = out.dd[1][0] = Vec3::Map(rows[4]);
        out.dd[1][1] = Vec3::Map(rows[5]);
      }
      return;
    }
  }
}

// Along a collapsed v_min edge, f_u(u, v0 + h) = h f_uv + O(h^2), so f_u x f_v tends to the
// direction of f_uv x f_v (h > 0; at v_max, h < 0), and likewise along a collapsed u edge.
Vec3 outward_direction(const Feature& f, const Feature_point& fp, const double* q, const Vec3& cross) {
  const unsigned collapsed = f.collapsed_edges();
  if (collapsed == 0u) return cross;
  // The collapsed edge of direction `dir` (0: u) the parameter sits on: +1 lower, -1 upper.
  auto side = [&](int dir) {
    const bool lo = collapsed & (1u << (2 * dir)), hi = collapsed & (2u << (2 * dir));
    if (lo && hi) return q[dir] - f.lower(dir) <= f.upper(dir) - q[dir] ? 1.0 : -1.0;
    return lo ? 1.0 : -1.0;
  };
  const double lu = fp.d[0].squaredNorm(), lv = fp.d[1].squaredNorm();
  if (lu <= 1e-12 * lv && (collapsed & 12u))
    return f.outward_sign() * side(1) * fp.dd[0][1].cross(fp.d[1]);
  if (lv <= 1e-12 * lu && (collapsed & 3u))
    return f.outward_sign() * side(0) * fp.d[0].cross(fp.dd[0][1]);
  return cross;
}

}  // namespace extremal
