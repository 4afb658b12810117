#include "algorithms/Feature.h"

namespace extremal {

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
                      Feature_point& out, int order) {
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
      Surface_point sp;
      f.surface()->evaluate(params[0], params[1], sp, order);
      out.p = X_WA.apply_point(sp.p);
      if (order >= 1) {
        out.d[0] = R * sp.du;
        out.d[1] = R * sp.dv;
      }
      if (order >= 2) {
        out.dd[0][0] = R * sp.duu;
        out.dd[0][1] = out.dd[1][0] = R * sp.duv;
        out.dd[1][1] = R * sp.dvv;
      }
      return;
    }
  }
}

}  // namespace extremal
