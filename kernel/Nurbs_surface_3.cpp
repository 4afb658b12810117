#include "kernel/Nurbs_surface_3.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "kernel/Error.h"
#include "kernel/internal/Bspline_basis.h"
#include "kernel/internal/Knot_vector.h"
#include "kernel/internal/Tensor_product.h"

namespace extremal {

Nurbs_surface_3::Nurbs_surface_3(int degree_u, int degree_v, int n_u, int n_v,
                                 std::vector<Point_3> poles, std::vector<double> knots_u,
                                 std::vector<double> knots_v, std::vector<double> weights)
    : m_degree_u(degree_u),
      m_degree_v(degree_v),
      m_n_u(n_u),
      m_n_v(n_v),
      m_poles(std::move(poles)),
      m_weights(std::move(weights)),
      m_knots_u(std::move(knots_u)),
      m_knots_v(std::move(knots_v)) {
  if (n_u < 1 || n_v < 1) {
    std::ostringstream os;
    os << "NURBS surface: control grid " << n_u << " x " << n_v << " is empty";
    throw Invalid_input(os.str());
  }
  const std::size_t count = static_cast<std::size_t>(n_u) * static_cast<std::size_t>(n_v);
  if (m_poles.size() != count) {
    std::ostringstream os;
    os << "NURBS surface: " << m_poles.size() << " control points for a " << n_u << " x " << n_v
       << " grid";
    throw Invalid_input(os.str());
  }
  internal::validate_knots(m_knots_u, n_u, degree_u, "NURBS surface u knots");
  internal::validate_knots(m_knots_v, n_v, degree_v, "NURBS surface v knots");
  if (m_weights.empty()) m_weights.assign(count, 1.0);
  if (m_weights.size() != count) {
    std::ostringstream os;
    os << "NURBS surface: " << m_weights.size() << " weights for " << count
       << " control points";
    throw Invalid_input(os.str());
  }
  m_hom.resize(count);
  for (std::size_t k = 0; k < count; ++k) {
    const double w = m_weights[k];
    const Point_3& P = m_poles[k];
    if (!(std::isfinite(w) && w > 0.0)) {
      std::ostringstream os;
      os << "NURBS surface: weight of control point (" << k / n_v << ", " << k % n_v << ") is "
         << w << ", weights must be finite and > 0";
      throw Invalid_input(os.str());
    }
    if (!(std::isfinite(P.x()) && std::isfinite(P.y()) && std::isfinite(P.z()))) {
      std::ostringstream os;
      os << "NURBS surface: control point (" << k / n_v << ", " << k % n_v
         << ") has a non-finite coordinate";
      throw Invalid_input(os.str());
    }
    if (w != 1.0) m_rational = true;
    m_hom[k] = Eigen::Vector4d(w * P.x(), w * P.y(), w * P.z(), w);
  }

  // Closedness: compare opposite boundary curves at a few parameters.
  const Bbox_3 box = hull_bbox();
  const double size = std::max({box.xmax() - box.xmin(), box.ymax() - box.ymin(),
                                box.zmax() - box.zmin(), 1e-300});
  const double tol = 1e-12 * size;
  constexpr int samples = 7;
  bool cu = true, cv = true;
  Surface_point a, b;
  for (int s = 0; s <= samples; ++s) {
    // min(): lo + (hi - lo) * 1 can round past hi, and evaluate() rejects that.
    const double fv = std::min(v_max(), v_min() + (v_max() - v_min()) * s / samples);
    const double fu = std::min(u_max(), u_min() + (u_max() - u_min()) * s / samples);
    evaluate(u_min(), fv, a, 0);
    evaluate(u_max(), fv, b, 0);
    cu = cu && (a.p - b.p).norm() <= tol;
    evaluate(fu, v_min(), a, 0);
    evaluate(fu, v_max(), b, 0);
    cv = cv && (a.p - b.p).norm() <= tol;
  }
  m_closed_u = cu;
  m_closed_v = cv;

  // At a collapsed edge (sphere pole, disk centre) f_u or f_v vanishes only up to rounding, about
  // eps * |coordinates| per unit of the other derivative; normalising that noise would give an
  // arbitrary direction. outward_normal treats |f_u x f_v| below this floor as zero.
  const double reach = std::max({std::abs(box.xmin()), std::abs(box.xmax()), std::abs(box.ymin()),
                                 std::abs(box.ymax()), std::abs(box.zmin()), std::abs(box.zmax())});
  m_normal_floor = 1e-12 * reach * size / ((u_max() - u_min()) * (v_max() - v_min()));
}

Nurbs_surface_3 Nurbs_surface_3::from_homogeneous(int degree_u, int degree_v, int n_u, int n_v,
                                                  const Homogeneous& poles,
                                                  std::vector<double> knots_u,
                                                  std::vector<double> knots_v) {
  std::vector<Point_3> pts;
  std::vector<double> ws;
  pts.reserve(poles.size());
  ws.reserve(poles.size());
  for (const auto& h : poles) {
    pts.emplace_back(h.x() / h.w(), h.y() / h.w(), h.z() / h.w());
    ws.push_back(h.w());
  }
  return Nurbs_surface_3(degree_u, degree_v, n_u, n_v, std::move(pts), std::move(knots_u),
                         std::move(knots_v), std::move(ws));
}

namespace {

// The placed kernel's rows (p, du, dv, duu, duv, dvv; lane 3 unused) into `out`.
template <int Order>
inline void write_placed(const double (&w)[6][4], Surface_point& out) {
  out.p = Vec3::Map(w[0]);
  if constexpr (Order >= 1) {
    out.du = Vec3::Map(w[1]);
    out.dv = Vec3::Map(w[2]);
  }
  if constexpr (Order >= 2) {
    out.duu = Vec3::Map(w[3]);
    out.duv = Vec3::Map(w[4]);
    out.dvv = Vec3::Map(w[5]);
  }
}

// The tensor-product sum and the quotient rule at (u, v) in spans (su, sv). P, Q > 0 fix the
// degrees at compile time (arrays sized to them, loops unrolled); 0 takes them from p, q. Order
// is the derivative order. Every instance does the same operations in the same order, so the
// results do not depend on which one runs. Each instance is one flat function (everything
// inlined into it, and it into nothing): left to itself GCC inlines the instances into
// evaluate() until its budget runs out and then calls Eigen's small kernels out of line.
// The sum itself runs in `fast` (AVX2 + FMA, kernel/internal/Tensor_product.h) when the CPU
// has it: all of its instances also share one order of operations.
template <int P, int Q, int Order>
[[gnu::noinline, gnu::flatten]] bool evaluate_in_span(const Eigen::Vector4d* hom, int n_v,
                                                     const double* knots_u,
                                                     const double* knots_v, int p, int q, int su,
                                                     int sv, double u, double v, bool rational,
                                                     const internal::Simd_kernels& fast,
                                                     const double* R, const double* t,
                                                     Surface_point& out, double* rows) {
  if constexpr (P > 0) p = P;
  if constexpr (Q > 0) q = Q;
  const Eigen::Vector4d* corner = hom + static_cast<std::size_t>(su - p) * n_v + (sv - q);
#if defined(__SSE2__)
  if constexpr (P > 0 && P == Q) {
    if (R != nullptr && fast.placed != nullptr) {
      // The kernel reads the two bases interleaved as the SSE2 pair leaves them: no unpacking.
      internal::Double_pair pairs[3 * (P + 1)];
      internal::basis_derivative_pairs<P>(knots_u, su, u, knots_v, sv, v, Order, pairs);
      double basis[6 * (P + 1)];  // rows 0..Order are written (zeros above the degree)
      for (int k = 0; k < (Order + 1) * (P + 1); ++k) _mm_storeu_pd(basis + 2 * k, pairs[k].x);
      double w[6][4];
      fast.placed(corner->data(), n_v, basis, basis + 1, 2 * (P + 1), 2, p, q, Order, rational,
                  R, t, rows != nullptr ? rows : &w[0][0]);
      if (rows != nullptr) return true;
      write_placed<Order>(w, out);
      return false;
    }
  }
#endif
  internal::Basis_derivatives Nu, Nv;
  if constexpr (P > 0 && P == Q) {
    internal::basis_derivatives_pair<P>(knots_u, su, u, knots_v, sv, v, Order, Nu, Nv);
  } else {
    if constexpr (P > 0)
      internal::basis_derivatives_impl<P>(knots_u, su, p, u, Order, Nu);
    else
      internal::basis_derivatives(knots_u, su, p, u, Order, Nu);
    if constexpr (Q > 0)
      internal::basis_derivatives_impl<Q>(knots_v, sv, q, v, Order, Nv);
    else
      internal::basis_derivatives(knots_v, sv, q, v, Order, Nv);
  }

  // S[k][l] = d^(k+l) / du^k dv^l of the homogeneous surface, k + l <= Order.
  Eigen::Vector4d S[3][3];
  if (R != nullptr && fast.placed != nullptr) {
    double w[6][4];
    fast.placed(corner->data(), n_v, &Nu.ders[0][0], &Nv.ders[0][0], k_max_degree + 1, 1, p, q,
                Order, rational, R, t, rows != nullptr ? rows : &w[0][0]);
    if (rows != nullptr) return true;
    write_placed<Order>(w, out);
    return false;
  }
  if (fast.sum != nullptr) {
    double s[6][4];
    fast.sum(corner->data(), n_v, &Nu.ders[0][0], &Nv.ders[0][0], k_max_degree + 1, 1, p, q,
             Order, &s[0][0]);
    S[0][0] = Eigen::Vector4d::Map(s[0]);
    if constexpr (Order >= 1) {
      S[1][0] = Eigen::Vector4d::Map(s[1]);
      S[0][1] = Eigen::Vector4d::Map(s[2]);
    }
    if constexpr (Order >= 2) {
      S[2][0] = Eigen::Vector4d::Map(s[3]);
      S[1][1] = Eigen::Vector4d::Map(s[4]);
      S[0][2] = Eigen::Vector4d::Map(s[5]);
    }
  } else {
    for (int k = 0; k <= Order; ++k)
      for (int l = 0; l + k <= Order; ++l) S[k][l].setZero();
    for (int i = 0; i <= p; ++i) {
      const Eigen::Vector4d* row = corner + static_cast<std::size_t>(i) * n_v;
      Eigen::Vector4d t0 = Eigen::Vector4d::Zero(), t1 = Eigen::Vector4d::Zero(),
                      t2 = Eigen::Vector4d::Zero();
      for (int j = 0; j <= q; ++j) {
        t0 += Nv.ders[0][j] * row[j];
        if constexpr (Order >= 1) t1 += Nv.ders[1][j] * row[j];
        if constexpr (Order >= 2) t2 += Nv.ders[2][j] * row[j];
      }
      S[0][0] += Nu.ders[0][i] * t0;
      if constexpr (Order >= 1) {
        S[1][0] += Nu.ders[1][i] * t0;
        S[0][1] += Nu.ders[0][i] * t1;
      }
      if constexpr (Order >= 2) {
        S[2][0] += Nu.ders[2][i] * t0;
        S[1][1] += Nu.ders[1][i] * t1;
        S[0][2] += Nu.ders[0][i] * t2;
      }
    }
  }
  if (!rational) {
    out.p = S[0][0].head<3>();
    if constexpr (Order >= 1) {
      out.du = S[1][0].head<3>();
      out.dv = S[0][1].head<3>();
    }
    if constexpr (Order >= 2) {
      out.duu = S[2][0].head<3>();
      out.duv = S[1][1].head<3>();
      out.dvv = S[0][2].head<3>();
    }
  } else {
    // Quotient rule on A / w, A the Cartesian part of the homogeneous derivatives.
    const double inv = 1.0 / S[0][0].w();
    out.p = S[0][0].head<3>() * inv;
    if constexpr (Order >= 1) {
      const double wu = S[1][0].w(), wv = S[0][1].w();
      out.du = (S[1][0].head<3>() - wu * out.p) * inv;
      out.dv = (S[0][1].head<3>() - wv * out.p) * inv;
      if constexpr (Order >= 2) {
        out.duu = (S[2][0].head<3>() - 2.0 * wu * out.du - S[2][0].w() * out.p) * inv;
        out.duv = (S[1][1].head<3>() - wu * out.dv - wv * out.du - S[1][1].w() * out.p) * inv;
        out.dvv = (S[0][2].head<3>() - 2.0 * wv * out.dv - S[0][2].w() * out.p) * inv;
      }
    }
  }
  if (R != nullptr) {
    const Eigen::Map<const Mat3> rotation(R);
    out.p = rotation * out.p + Vec3::Map(t);
    if constexpr (Order >= 1) {
      out.du = rotation * out.du;
      out.dv = rotation * out.dv;
    }
    if constexpr (Order >= 2) {
      out.duu = rotation * out.duu;
      out.duv = rotation * out.duv;
      out.dvv = rotation * out.dvv;
    }
  }
  return false;
}

// Compile-time degrees for the common low-degree patches (planes, conics, bicubics).
template <int Order>
bool evaluate_dispatch(const Eigen::Vector4d* hom, int n_v, const double* knots_u,
                       const double* knots_v, int p, int q, int su, int sv, double u, double v,
                       bool rational, const internal::Simd_kernels& fast, const double* R,
                       const double* t, Surface_point& out, double* rows) {
#define EXTREMAL_SPAN_CASE(PP, QQ)                                                           \
  if (p == PP && q == QQ)                                                                    \
    return evaluate_in_span<PP, QQ, Order>(hom, n_v, knots_u, knots_v, p, q, su, sv, u, v, \
                                           rational, fast, R, t, out, rows)
  EXTREMAL_SPAN_CASE(3, 3);
  EXTREMAL_SPAN_CASE(2, 2);
  EXTREMAL_SPAN_CASE(2, 1);
  EXTREMAL_SPAN_CASE(1, 2);
  EXTREMAL_SPAN_CASE(1, 1);
#undef EXTREMAL_SPAN_CASE
  return evaluate_in_span<0, 0, Order>(hom, n_v, knots_u, knots_v, p, q, su, sv, u, v, rational,
                                       fast, R, t, out, rows);
}

}  // namespace

void Nurbs_surface_3::evaluate(double u, double v, Surface_point& out, int order) const {
  evaluate_in_frame(u, v, nullptr, nullptr, out, order);
}

void Nurbs_surface_3::evaluate_placed(double u, double v, const Mat3& rotation,
                                      const Vec3& translation, Surface_point& out,
                                      int order) const {
  evaluate_in_frame(u, v, rotation.data(), translation.data(), out, order);
}

void Nurbs_surface_3::evaluate_placed_rows(double u, double v, const Mat3& rotation,
                                           const Vec3& translation, double (&rows)[6][4],
                                           int order, Span_hint* hint) const {
  Surface_point sp{Surface_point::Unset{}};
  if (evaluate_in_frame(u, v, rotation.data(), translation.data(), sp, order, &rows[0][0], hint))
    return;
  // The portable path filled sp.
  const Vec3* in[6] = {&sp.p, &sp.du, &sp.dv, &sp.duu, &sp.duv, &sp.dvv};
  const int count = order == 0 ? 1 : order == 1 ? 3 : 6;
  for (int k = 0; k < count; ++k) Vec3::Map(rows[k]) = *in[k];
}

bool Nurbs_surface_3::evaluate_in_frame(double u, double v, const double* R, const double* t,
                                        Surface_point& out, int order, double* rows,
                                        Span_hint* hint) const {
  EXTREMAL_PRECONDITION(order >= 0 && order <= 2);
  const int p = m_degree_u, q = m_degree_v;
  const double* ku = m_knots_u.data();
  const double* kv = m_knots_v.data();
  // Inside the hinted spans (half-open, so the same spans find_span returns) the parameters are
  // in the domain: the checks and the search are done.
  const auto in_span = [](const double* knots, int n, int deg, int k, double t) {
    return k >= deg && k < n && knots[k] <= t && t < knots[k + 1];
  };
  const Span_hint given = hint != nullptr ? *hint : Span_hint{};
  int su, sv;
  if (in_span(ku, m_n_u, p, given.u, u) && in_span(kv, m_n_v, q, given.v, v)) {
    su = given.u;
    sv = given.v;
  } else {
    EXTREMAL_PRECONDITION_MSG(u >= u_min() && u <= u_max(),
                              "u = " << u << " outside [" << u_min() << ", " << u_max() << "]");
    EXTREMAL_PRECONDITION_MSG(v >= v_min() && v <= v_max(),
                              "v = " << v << " outside [" << v_min() << ", " << v_max() << "]");
    su = internal::find_span(ku, m_n_u, p, u);
    sv = internal::find_span(kv, m_n_v, q, v);
    if (hint != nullptr) *hint = {su, sv};
  }
  const Eigen::Vector4d* hom = m_hom.data();
  const internal::Simd_kernels& fast = internal::fast_kernels();
  switch (order) {
    case 0:
      return evaluate_dispatch<0>(hom, m_n_v, ku, kv, p, q, su, sv, u, v, m_rational, fast, R, t,
                                  out, rows);
    case 1:
      return evaluate_dispatch<1>(hom, m_n_v, ku, kv, p, q, su, sv, u, v, m_rational, fast, R, t,
                                  out, rows);
    default:
      return evaluate_dispatch<2>(hom, m_n_v, ku, kv, p, q, su, sv, u, v, m_rational, fast, R, t,
                                  out, rows);
  }
}

Point_3 Nurbs_surface_3::point(double u, double v) const {
  Surface_point sp;
  evaluate(u, v, sp, 0);
  return to_point(sp.p);
}

Vec3 Nurbs_surface_3::outward_normal(const Surface_point& sp) const {
  const Vec3 n = sp.du.cross(sp.dv);
  const double len = n.norm();
  if (!(len > m_normal_floor)) return Vec3::Zero();
  return (m_outward_sign / len) * n;
}

Bbox_3 Nurbs_surface_3::hull_bbox() const {
  Bbox_3 box;
  for (const auto& p : m_poles) box += p.bbox();
  return box;
}

}  // namespace extremal
