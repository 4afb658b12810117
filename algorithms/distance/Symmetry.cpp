#include "algorithms/distance/Symmetry.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace extremal {

double symmetry_tolerance(const Bbox_3& box) {
  const Vec3 lo(box.xmin(), box.ymin(), box.zmin()), hi(box.xmax(), box.ymax(), box.zmax());
  const double size = (hi - lo).norm();
  const double coords = std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff());
  return 1e-9 * size + 1e3 * std::numeric_limits<double>::epsilon() * coords;
}

Symmetry Symmetry::placed(const Rigid_pose_3& X) const {
  Symmetry s = *this;
  s.point = X.apply_point(point);
  s.direction = X.apply_vector(direction);
  return s;
}

namespace {

struct Circle {
  Vec3 centre, normal;
  double radius = 0.0;
};

// The circle through three points; false when they are (nearly) collinear.
bool circle_through(const Vec3& p0, const Vec3& p1, const Vec3& p2, Circle& out) {
  const Vec3 a = p1 - p0, b = p2 - p0, n = a.cross(b);
  const double n2 = n.squaredNorm();
  if (!(n2 > 1e-18 * a.squaredNorm() * b.squaredNorm())) return false;
  out.centre = p0 + (a.squaredNorm() * b - b.squaredNorm() * a).cross(n) / (2.0 * n2);
  out.normal = n / std::sqrt(n2);
  out.radius = (p0 - out.centre).norm();
  return std::isfinite(out.radius);
}

// The circle through points of `curve` at three fractions of [t0, t1], checked at four others.
template <typename Point_at>
bool circle_along(const Point_at& point_at, double t0, double t1, double tol, Circle& out) {
  auto at = [&](double f) { return point_at(std::min(t1, t0 + f * (t1 - t0))); };
  if (!circle_through(at(0.1), at(0.45), at(0.8), out)) return false;
  for (const double f : {0.0, 0.3, 0.6, 1.0}) {
    const Vec3 d = at(f) - out.centre;
    if (std::abs(d.norm() - out.radius) > tol || std::abs(d.dot(out.normal)) > tol) return false;
  }
  return true;
}


// An axis through the foot of the origin, pointing to the side of its largest component: the
// same line found on two elements (a cylinder's side and caps) then compares equal.
Symmetry canonical_axis(const Vec3& point, const Vec3& direction) {
  Symmetry sym;
  sym.kind = Symmetry::Kind::Axis;
  Eigen::Index k;
  direction.cwiseAbs().maxCoeff(&k);
  sym.direction = direction[k] < 0.0 ? Vec3(-direction) : direction;
  sym.point = point - point.dot(sym.direction) * sym.direction;
  return sym;
}

}  // namespace

Symmetry find_symmetry(const Nurbs_surface_3& s) {
  const double tol = symmetry_tolerance(s.hull_bbox());
  const double lo[2] = {s.u_min(), s.v_min()}, hi[2] = {s.u_max(), s.v_max()};
  // Iso-curves along `dir` at three values of the other parameter.
  for (int dir = 0; dir < 2; ++dir) {
    const int other = 1 - dir;
    std::array<Circle, 3> circles;
    bool circular = true;
    const double fractions[3] = {0.2, 0.5, 0.8};
    for (int k = 0; k < 3 && circular; ++k) {
      const double fixed = std::min(hi[other], lo[other] + fractions[k] * (hi[other] - lo[other]));
      auto point_at = [&](double t) {
        return to_vec3(dir == 0 ? s.point(t, fixed) : s.point(fixed, t));
      };
      circular = circle_along(point_at, lo[dir], hi[dir], tol, circles[k]);
    }
    if (!circular) continue;
    // One axis: parallel planes, centres along their normal.
    const Vec3& n = circles[0].normal;
    bool coaxial = true;
    for (const Circle& c : circles)
      coaxial = coaxial && c.normal.cross(n).norm() <= 1e-9 &&
                (c.centre - circles[0].centre).cross(n).norm() <= tol;
    if (!coaxial) continue;
    Symmetry sym = canonical_axis(circles[0].centre, n);
    // A sphere: one point of the axis equidistant from all three circles' points,
    // (h_k - t)^2 + r_k^2 = R^2 for their heights h_k along the axis.
    double h[3], r[3];
    for (int k = 0; k < 3; ++k) {
      h[k] = (circles[k].centre - sym.point).dot(sym.direction);
      r[k] = circles[k].radius;
    }
    if (std::abs(h[2] - h[0]) > tol) {
      const double t =
          (h[2] * h[2] - h[0] * h[0] + r[2] * r[2] - r[0] * r[0]) / (2.0 * (h[2] - h[0]));
      const double R = std::hypot(h[0] - t, r[0]);
      if (std::abs(std::hypot(h[1] - t, r[1]) - R) <= tol &&
          std::abs(std::hypot(h[2] - t, r[2]) - R) <= tol) {
        sym.kind = Symmetry::Kind::Centre;
        sym.point += t * sym.direction;
        sym.direction = Vec3::Zero();
      }
    }
    return sym;
  }
  return {};
}

Symmetry find_symmetry(const Nurbs_curve_3& c) {
  Circle circle;
  auto point_at = [&](double t) { return to_vec3(c.point(t)); };
  if (!circle_along(point_at, c.domain_min(), c.domain_max(), symmetry_tolerance(c.hull_bbox()), circle))
    return {};
  return canonical_axis(circle.centre, circle.normal);
}

namespace {

// B^m_i B^m_j = f[m][i][j] B^{2m}_{i+j}, with f = C(m, i) C(m, j) / C(2m, i + j).
struct Product_weights {
  static constexpr int n = k_max_radial_degree + 1;
  double f[n][n][n];
  Product_weights() {
    double binomial[2 * n][2 * n] = {};
    for (int a = 0; a < 2 * n; ++a) {
      binomial[a][0] = 1.0;
      for (int b = 1; b <= a; ++b) binomial[a][b] = binomial[a - 1][b - 1] + binomial[a - 1][b];
    }
    for (int m = 0; m < n; ++m)
      for (int i = 0; i <= m; ++i)
        for (int j = 0; j <= m; ++j)
          f[m][i][j] = binomial[m][i] * binomial[m][j] / binomial[2 * m][i + j];
  }
};

const Product_weights& product_weights() {
  static const Product_weights w;
  return w;
}

}  // namespace

bool radial_range(const Eigen::Vector4d* net, int nu, int nv, const Symmetry& s, double& lo,
                  double& hi) {
  constexpr int n_max = k_max_radial_degree + 1, s_max = 2 * k_max_radial_degree + 1;
  if (!s.any() || nu > n_max || nv > n_max) return false;
  constexpr double eps = std::numeric_limits<double>::epsilon();
  const bool axis = s.kind == Symmetry::Kind::Axis;
  // H_k = w_k (P_k - c), across the axis for an axis: the homogeneous poles of P - c.
  Vec3 H[n_max * n_max];
  double w[n_max * n_max], length[n_max * n_max];
  double scale = s.point.cwiseAbs().maxCoeff(), reach = 0.0;
  const int count = nu * nv;
  for (int k = 0; k < count; ++k) {
    w[k] = net[k][3];
    Vec3 d = net[k].head<3>() - w[k] * s.point;
    if (axis) d -= d.dot(s.direction) * s.direction;
    H[k] = d;
    length[k] = d.norm();
    scale = std::max(scale, net[k].head<3>().cwiseAbs().maxCoeff() / w[k]);
    reach = std::max(reach, length[k] / w[k]);
  }
  // N = |sum B_k H_k|^2 and W = (sum B_k w_k)^2 in the degree-doubled basis, and A the same
  // sums of |H_i| |H_j| (what N's rounding scales with).
  const int mu = nu - 1, mv = nv - 1, sv = 2 * mv + 1, size = (2 * mu + 1) * sv;
  double N[s_max * s_max], W[s_max * s_max], A[s_max * s_max];
  std::fill(N, N + size, 0.0);
  std::fill(W, W + size, 0.0);
  std::fill(A, A + size, 0.0);
  const Product_weights& pw = product_weights();
  for (int i1 = 0; i1 < nu; ++i1)
    for (int i2 = 0; i2 < nu; ++i2) {
      const double fu = pw.f[mu][i1][i2];
      for (int j1 = 0; j1 < nv; ++j1)
        for (int j2 = 0; j2 < nv; ++j2) {
          const double c = fu * pw.f[mv][j1][j2];
          const int k1 = i1 * nv + j1, k2 = i2 * nv + j2, at = (i1 + i2) * sv + j1 + j2;
          N[at] += c * H[k1].dot(H[k2]);
          W[at] += c * w[k1] * w[k2];
          A[at] += c * length[k1] * length[k2];
        }
    }
  // Rounding: the sums' (relative to A / W), and H's from the coordinates' size, which moves
  // rho^2 by about 2 rho e + e^2 for an error e in rho.
  const double gamma = (4.0 * count + 16.0) * eps;
  const double e = 16.0 * eps * scale;
  const double spread = 2.0 * reach * e + e * e;
  double lo2 = HUGE_VAL, hi2 = -HUGE_VAL;
  for (int k = 0; k < size; ++k) {
    // A product of weights below the normal range (weights far below 1e-150) or a sum that
    // overflows leaves no accuracy to bound: none (a NaN would drop out of min and max).
    if (!(W[k] >= std::numeric_limits<double>::min())) return false;
    const double ratio = N[k] / W[k];
    const double slack = gamma * (A[k] / W[k] + std::abs(ratio)) + spread;
    if (!std::isfinite(ratio) || !std::isfinite(slack)) return false;
    lo2 = std::min(lo2, ratio - slack);
    hi2 = std::max(hi2, ratio + slack);
  }
  lo = std::sqrt(std::max(0.0, lo2));
  hi = std::sqrt(std::max(0.0, hi2));
  return true;
}

}  // namespace extremal
