#include "kernel/Nurbs_curve_3.h"

#include <cmath>
#include <sstream>

#include "kernel/Error.h"
#include "kernel/internal/Bspline_basis.h"
#include "kernel/internal/Knot_vector.h"

namespace extremal {

namespace {
bool is_finite(const Point_3& p) {
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z());
}
}  // namespace

Nurbs_curve_3::Nurbs_curve_3(int degree, std::vector<Point_3> poles, std::vector<double> knots,
                             std::vector<double> weights)
    : m_degree(degree),
      m_poles(std::move(poles)),
      m_weights(std::move(weights)),
      m_knots(std::move(knots)) {
  const int n = static_cast<int>(m_poles.size());
  internal::validate_knots(m_knots, n, m_degree, "NURBS curve knots");
  if (m_weights.empty()) m_weights.assign(n, 1.0);
  if (static_cast<int>(m_weights.size()) != n) {
    std::ostringstream os;
    os << "NURBS curve: " << m_weights.size() << " weights for " << n << " control points";
    throw Invalid_input(os.str());
  }
  m_hom.resize(n);
  for (int i = 0; i < n; ++i) {
    const double w = m_weights[i];
    if (!(std::isfinite(w) && w > 0.0)) {
      std::ostringstream os;
      os << "NURBS curve: weight " << i << " is " << w << ", weights must be finite and > 0";
      throw Invalid_input(os.str());
    }
    if (!is_finite(m_poles[i])) {
      std::ostringstream os;
      os << "NURBS curve: control point " << i << " has a non-finite coordinate";
      throw Invalid_input(os.str());
    }
    if (w != 1.0) m_rational = true;
    m_hom[i] = Eigen::Vector4d(w * m_poles[i].x(), w * m_poles[i].y(), w * m_poles[i].z(), w);
  }
  const Bbox_3 box = hull_bbox();
  const double size = std::max({box.xmax() - box.xmin(), box.ymax() - box.ymin(),
                                box.zmax() - box.zmin()});
  // Closed when the domain's end points meet (to 1e-12 of the curve's size).
  Curve_point s, e;
  evaluate(domain_min(), s, 0);
  evaluate(domain_max(), e, 0);
  m_closed = (s.p - e.p).norm() <= 1e-12 * std::max(size, 1e-300);
}

Nurbs_curve_3 Nurbs_curve_3::from_homogeneous(int degree, const Homogeneous& poles,
                                              std::vector<double> knots) {
  std::vector<Point_3> pts;
  std::vector<double> ws;
  pts.reserve(poles.size());
  ws.reserve(poles.size());
  for (const auto& h : poles) {
    pts.emplace_back(h.x() / h.w(), h.y() / h.w(), h.z() / h.w());
    ws.push_back(h.w());
  }
  return Nurbs_curve_3(degree, std::move(pts), std::move(knots), std::move(ws));
}

void Nurbs_curve_3::evaluate(double t, Curve_point& out, int order) const {
  EXTREMAL_PRECONDITION_MSG(t >= domain_min() && t <= domain_max(),
                            "t = " << t << " outside [" << domain_min() << ", " << domain_max()
                                   << "]");
  EXTREMAL_PRECONDITION(order >= 0 && order <= 2);
  const int n = number_of_poles();
  const int p = m_degree;
  const int span = internal::find_span(m_knots.data(), n, p, t);
  internal::Basis_derivatives N;
  internal::basis_derivatives(m_knots.data(), span, p, t, order, N);
  Eigen::Vector4d c[3] = {Eigen::Vector4d::Zero(), Eigen::Vector4d::Zero(),
                          Eigen::Vector4d::Zero()};
  for (int j = 0; j <= p; ++j) {
    const Eigen::Vector4d& P = m_hom[span - p + j];
    for (int k = 0; k <= order; ++k) c[k] += N.ders[k][j] * P;
  }
  if (!m_rational) {
    out.p = c[0].head<3>();
    if (order >= 1) out.d1 = c[1].head<3>();
    if (order >= 2) out.d2 = c[2].head<3>();
    return;
  }
  const double w = c[0].w(), inv = 1.0 / w;
  out.p = c[0].head<3>() * inv;
  if (order >= 1) out.d1 = (c[1].head<3>() - c[1].w() * out.p) * inv;
  if (order >= 2) out.d2 = (c[2].head<3>() - 2.0 * c[1].w() * out.d1 - c[2].w() * out.p) * inv;
}

Point_3 Nurbs_curve_3::point(double t) const {
  Curve_point cp;
  evaluate(t, cp, 0);
  return to_point(cp.p);
}

Bbox_3 Nurbs_curve_3::hull_bbox() const {
  Bbox_3 box;
  for (const auto& p : m_poles) box += p.bbox();
  return box;
}

}  // namespace extremal
