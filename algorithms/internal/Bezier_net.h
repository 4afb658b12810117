// Control nets of rational Bezier pieces in homogeneous coordinates: halving by de Casteljau and
// the bounds the global distance solver takes from the convex-hull property. Not API.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Core>

#include "kernel/Types.h"

namespace extremal::internal {

using Hom = Eigen::Vector4d;

// Largest number of poles per direction of a Bezier piece (degree 31).
constexpr int k_max_net_side = 32;

// Halves `n` poles spaced `stride` apart at t = 1/2 into left and right (same spacing).
inline void de_casteljau_half(const Hom* in, int n, int stride, Hom* left, Hom* right) {
  Hom q[k_max_net_side];
  for (int k = 0; k < n; ++k) q[k] = in[k * stride];
  left[0] = q[0];
  right[(n - 1) * stride] = q[n - 1];
  for (int r = 1; r < n; ++r) {
    for (int k = 0; k < n - r; ++k) q[k] = 0.5 * (q[k] + q[k + 1]);
    left[r * stride] = q[0];
    right[(n - 1 - r) * stride] = q[n - 1 - r];
  }
}

// Halves a net of nu x nv poles (row-major, i along u: pole (i, j) at i * nv + j) in direction
// `dir` (0 = u, 1 = v). `left` holds the half with the smaller parameter.
inline void split_net_half(const Hom* net, int nu, int nv, int dir, Hom* left, Hom* right) {
  if (dir == 0) {
    for (int j = 0; j < nv; ++j) de_casteljau_half(net + j, nu, nv, left + j, right + j);
  } else {
    for (int i = 0; i < nu; ++i)
      de_casteljau_half(net + i * nv, nv, 1, left + i * nv, right + i * nv);
  }
}

// Cartesian points, their box, centroid and the radius of the ball about the centroid that holds
// them.
inline void net_bounds(const Hom* net, int n, Vec3* cart, Vec3& bmin, Vec3& bmax, Vec3& centre,
                       double& radius) {
  bmin.setConstant(HUGE_VAL);
  bmax.setConstant(-HUGE_VAL);
  centre.setZero();
  for (int k = 0; k < n; ++k) {
    const double inv_w = 1.0 / net[k][3];
    cart[k] = net[k].head<3>() * inv_w;
    bmin = bmin.cwiseMin(cart[k]);
    bmax = bmax.cwiseMax(cart[k]);
    centre += cart[k];
  }
  centre /= n;
  double r2 = 0.0;
  for (int k = 0; k < n; ++k) r2 = std::max(r2, (cart[k] - centre).squaredNorm());
  radius = std::sqrt(r2);
}

// Euclidean distance between two axis-aligned boxes (0 if they overlap).
inline double box_distance(const Vec3& amin, const Vec3& amax, const Vec3& bmin,
                           const Vec3& bmax) {
  double s = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double g = std::max({0.0, amin[k] - bmax[k], bmin[k] - amax[k]});
    s += g * g;
  }
  return std::sqrt(s);
}

// Gap between the projections of two point sets on the unit axis n: a lower bound on the
// distance between their convex hulls (0 if the projections overlap).
inline double axis_gap(const Vec3* a, int na, const Vec3* b, int nb, const Vec3& n) {
  double amin = HUGE_VAL, amax = -HUGE_VAL, bmin = HUGE_VAL, bmax = -HUGE_VAL;
  for (int k = 0; k < na; ++k) {
    const double s = n.dot(a[k]);
    amin = std::min(amin, s);
    amax = std::max(amax, s);
  }
  for (int k = 0; k < nb; ++k) {
    const double s = n.dot(b[k]);
    bmin = std::min(bmin, s);
    bmax = std::max(bmax, s);
  }
  return std::max({0.0, bmin - amax, amin - bmax});
}

// Like axis_gap, and also the points that attain A's largest and B's smallest projection (the
// support points along n), from which a better axis can be taken.
inline double axis_gap_support(const Vec3* a, int na, const Vec3* b, int nb, const Vec3& n,
                               int& a_top, int& b_bottom) {
  double amin = HUGE_VAL, amax = -HUGE_VAL, bmin = HUGE_VAL, bmax = -HUGE_VAL;
  a_top = b_bottom = 0;
  for (int k = 0; k < na; ++k) {
    const double s = n.dot(a[k]);
    amin = std::min(amin, s);
    if (s > amax) {
      amax = s;
      a_top = k;
    }
  }
  for (int k = 0; k < nb; ++k) {
    const double s = n.dot(b[k]);
    bmax = std::max(bmax, s);
    if (s < bmin) {
      bmin = s;
      b_bottom = k;
    }
  }
  return std::max({0.0, bmin - amax, amin - bmax});
}

// Extracts the piece of a Bezier net over the local parameter box [s0, s1] x [t0, t1] (of
// [0, 1]^2): de Casteljau at s1, then at s0 / s1 on the left part, along each direction.
inline void de_casteljau_at(const Hom* in, int n, int stride, double t, Hom* left, Hom* right) {
  Hom q[k_max_net_side];
  for (int k = 0; k < n; ++k) q[k] = in[k * stride];
  if (left) left[0] = q[0];
  if (right) right[(n - 1) * stride] = q[n - 1];
  for (int r = 1; r < n; ++r) {
    for (int k = 0; k < n - r; ++k) q[k] = (1.0 - t) * q[k] + t * q[k + 1];
    if (left) left[r * stride] = q[0];
    if (right) right[(n - 1 - r) * stride] = q[n - 1 - r];
  }
}

inline void restrict_row(Hom* row, int n, int stride, double a, double b) {
  if (n < 2) return;
  if (b < 1.0) de_casteljau_at(row, n, stride, b, row, nullptr);
  if (a > 0.0) de_casteljau_at(row, n, stride, a / b, nullptr, row);
}

// In place: net (nu x nv, row-major, i along u) restricted to [s0, s1] x [t0, t1].
inline void restrict_net(Hom* net, int nu, int nv, double s0, double s1, double t0, double t1) {
  for (int j = 0; j < nv; ++j) restrict_row(net + j, nu, nv, s0, s1);
  for (int i = 0; i < nu; ++i) restrict_row(net + i * nv, nv, 1, t0, t1);
}

// Closed intervals for enclosures of a piece's derivatives. Not outward-rounded: users keep a
// relative margin far above rounding.
struct Interval {
  double lo = 0.0, hi = 0.0;
};
inline Interval operator+(Interval a, Interval b) { return {a.lo + b.lo, a.hi + b.hi}; }
inline Interval operator-(Interval a, Interval b) { return {a.lo - b.hi, a.hi - b.lo}; }
inline Interval operator*(double s, Interval a) {
  return s >= 0.0 ? Interval{s * a.lo, s * a.hi} : Interval{s * a.hi, s * a.lo};
}
inline Interval operator*(Interval a, Interval b) {
  const double p[4] = {a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi};
  return {std::min({p[0], p[1], p[2], p[3]}), std::max({p[0], p[1], p[2], p[3]})};
}
inline Interval square(Interval a) {
  if (a.lo >= 0.0) return {a.lo * a.lo, a.hi * a.hi};
  if (a.hi <= 0.0) return {a.hi * a.hi, a.lo * a.lo};
  return {0.0, std::max(a.lo * a.lo, a.hi * a.hi)};
}
inline Interval hull(Interval a, Interval b) { return {std::min(a.lo, b.lo), std::max(a.hi, b.hi)}; }
// a / w for w > 0.
inline Interval divide_positive(Interval a, Interval w) {
  return a * Interval{1.0 / w.hi, 1.0 / w.lo};
}

using Interval3 = std::array<Interval, 3>;
inline Interval dot(const Interval3& a, const Interval3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
inline Interval self_dot(const Interval3& a) {
  return square(a[0]) + square(a[1]) + square(a[2]);
}

// Enclosures over a parameter box of a feature's point and its first and second derivatives
// along its (element) parameters.
struct Derivative_enclosure {
  int dim = 0;
  Interval3 p, d[2], dd[2][2];
};

inline void hull_into(Derivative_enclosure& into, const Derivative_enclosure& e, bool first) {
  auto h3 = [&](Interval3& a, const Interval3& b) {
    for (int c = 0; c < 3; ++c) a[c] = first ? b[c] : hull(a[c], b[c]);
  };
  into.dim = e.dim;
  h3(into.p, e.p);
  for (int k = 0; k < e.dim; ++k) {
    h3(into.d[k], e.d[k]);
    for (int l = 0; l < e.dim; ++l) h3(into.dd[k][l], e.dd[k][l]);
  }
}

// Enclosures of a rational Bezier piece with `dim` parameters (nu x nv homogeneous poles, world
// frame) over its whole box, whose element-parameter widths are `width`. From the convex-hull
// property of the homogeneous derivative nets (hodographs) and interval arithmetic on the
// quotient rule; `order` 1 leaves the second derivatives out. False if a weight is not positive.
inline bool enclose_piece(const Hom* P, int nu, int nv, int dim, const double* width,
                          Derivative_enclosure& out, int order = 2) {
  out.dim = dim;
  // Range of a linear combination of poles, all four homogeneous coordinates.
  using Range4 = std::array<Interval, 4>;
  auto range = [&](int ni, int nj, auto&& coeff) {
    Range4 r;
    bool first = true;
    for (int i = 0; i < ni; ++i)
      for (int j = 0; j < nj; ++j) {
        const Hom v = coeff(i, j);
        for (int c = 0; c < 4; ++c)
          r[c] = first ? Interval{v[c], v[c]} : hull(r[c], Interval{v[c], v[c]});
        first = false;
      }
    if (first)
      for (auto& x : r) x = Interval{0.0, 0.0};
    return r;
  };
  auto at = [&](int i, int j) -> const Hom& { return P[i * nv + j]; };
  const Range4 X = range(nu, nv, [&](int i, int j) { return at(i, j); });
  const Interval w = X[3];
  if (!(w.lo > 0.0)) return false;
  for (int c = 0; c < 3; ++c) out.p[c] = Interval{HUGE_VAL, -HUGE_VAL};
  for (int k = 0; k < nu * nv; ++k)
    for (int c = 0; c < 3; ++c) {
      const double x = P[k][c] / P[k][3];
      out.p[c] = Interval{std::min(out.p[c].lo, x), std::max(out.p[c].hi, x)};
    }
  if (dim == 0) return true;
  const double p = nu - 1, q = nv - 1;
  const Range4 Xs = range(nu - 1, nv, [&](int i, int j) { return Hom(p * (at(i + 1, j) - at(i, j))); });
  const Range4 Xss = nu >= 3 && order >= 2 ? range(nu - 2, nv, [&](int i, int j) {
    return Hom(p * (p - 1) * (at(i + 2, j) - 2.0 * at(i + 1, j) + at(i, j)));
  }) : Range4{};
  Interval3 fs, fss;
  for (int c = 0; c < 3; ++c) {
    fs[c] = divide_positive(Xs[c] - out.p[c] * Xs[3], w);
    fss[c] = divide_positive(Xss[c] - 2.0 * (fs[c] * Xs[3]) - out.p[c] * Xss[3], w);
  }
  const double iu = 1.0 / width[0];
  for (int c = 0; c < 3; ++c) {
    out.d[0][c] = iu * fs[c];
    out.dd[0][0][c] = (iu * iu) * fss[c];
  }
  if (dim == 1) return true;
  const Range4 Xt = range(nu, nv - 1, [&](int i, int j) { return Hom(q * (at(i, j + 1) - at(i, j))); });
  if (order < 2) {
    const Range4 Xt = range(nu, nv - 1, [&](int i, int j) { return Hom(q * (at(i, j + 1) - at(i, j))); });
    for (int c = 0; c < 3; ++c)
      out.d[1][c] = (1.0 / width[1]) * divide_positive(Xt[c] - out.p[c] * Xt[3], w);
    return true;
  }
  const Range4 Xtt = nv >= 3 ? range(nu, nv - 2, [&](int i, int j) {
    return Hom(q * (q - 1) * (at(i, j + 2) - 2.0 * at(i, j + 1) + at(i, j)));
  }) : Range4{};
  const Range4 Xst = range(nu - 1, nv - 1, [&](int i, int j) {
    return Hom(p * q * (at(i + 1, j + 1) - at(i + 1, j) - at(i, j + 1) + at(i, j)));
  });
  const double iv = 1.0 / width[1];
  for (int c = 0; c < 3; ++c) {
    const Interval ft = divide_positive(Xt[c] - out.p[c] * Xt[3], w);
    const Interval ftt =
        divide_positive(Xtt[c] - 2.0 * (ft * Xt[3]) - out.p[c] * Xtt[3], w);
    const Interval fst = divide_positive(
        Xst[c] - fs[c] * Xt[3] - ft * Xs[3] - out.p[c] * Xst[3], w);
    out.d[1][c] = iv * ft;
    out.dd[1][1][c] = (iv * iv) * ftt;
    out.dd[0][1][c] = out.dd[1][0][c] = (iu * iv) * fst;
  }
  return true;
}

}  // namespace extremal::internal
