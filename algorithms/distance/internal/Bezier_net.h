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

// The projections of two point sets on the unit axis n: their extents, and the points that
// attain A's largest and B's smallest projection (the support points along n, from which a
// better axis can be taken).
struct Axis_extents {
  double a_min = HUGE_VAL, a_max = -HUGE_VAL, b_min = HUGE_VAL, b_max = -HUGE_VAL;
  int a_top = 0, b_bottom = 0;
  // Gap between the projections: a lower bound on the distance between the convex hulls (0 if
  // the projections overlap).
  double gap() const { return std::max({0.0, b_min - a_max, a_min - b_max}); }
  // The gap by which B lies beyond A along n (negative if they overlap along it).
  double separation() const { return b_min - a_max; }
};
inline Axis_extents axis_extents(const Vec3* a, int na, const Vec3* b, int nb, const Vec3& n) {
  Axis_extents x;
  for (int k = 0; k < na; ++k) {
    const double s = n.dot(a[k]);
    x.a_min = std::min(x.a_min, s);
    if (s > x.a_max) {
      x.a_max = s;
      x.a_top = k;
    }
  }
  for (int k = 0; k < nb; ++k) {
    const double s = n.dot(b[k]);
    x.b_max = std::max(x.b_max, s);
    if (s < x.b_min) {
      x.b_min = s;
      x.b_bottom = k;
    }
  }
  return x;
}

// From the direction e (B's side of A), `steps` support-point steps towards the hulls'
// separating axis (the axis through A's highest and B's lowest point along the current one),
// as in GJK: tried(n, extents) for each unit axis n taken, until it returns true.
template <class Tried>
void separating_axis_steps(const Vec3* a, int na, const Vec3* b, int nb, Vec3 e, int steps,
                           Tried&& tried) {
  for (int it = 0; it < steps; ++it) {
    const double len = e.norm();
    if (!(len > 0.0)) return;
    const Vec3 n = e / len;
    const Axis_extents x = axis_extents(a, na, b, nb, n);
    if (tried(n, x)) return;
    e = b[x.b_bottom] - a[x.a_top];
  }
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

// Enclosures over a parameter box of a feature's point and its first, second and (on request)
// third derivatives along its (element) parameters.
struct Derivative_enclosure {
  int dim = 0;
  int order = 2;
  Interval3 p, d[2], dd[2][2], ddd[2][2][2];
};

inline void hull_into(Derivative_enclosure& into, const Derivative_enclosure& e, bool first) {
  auto h3 = [&](Interval3& a, const Interval3& b) {
    for (int c = 0; c < 3; ++c) a[c] = first ? b[c] : hull(a[c], b[c]);
  };
  into.dim = e.dim;
  into.order = first ? e.order : std::min(into.order, e.order);
  h3(into.p, e.p);
  for (int k = 0; k < e.dim; ++k) {
    h3(into.d[k], e.d[k]);
    for (int l = 0; l < e.dim; ++l) {
      h3(into.dd[k][l], e.dd[k][l]);
      if (e.order >= 3)
        for (int m = 0; m < e.dim; ++m) h3(into.ddd[k][l][m], e.ddd[k][l][m]);
    }
  }
}

// Enclosures of a rational Bezier piece with `dim` parameters (nu x nv homogeneous poles, world
// frame) over its whole box, whose element-parameter widths are `width`, up to derivatives of
// `order` (1 to 3). From the convex-hull property of the homogeneous derivative nets
// (hodographs) and interval arithmetic on the quotient rule, X = w f differentiated by Leibniz:
// f_ab = (X_ab - sum over (c, d) != (0, 0) of C(a, c) C(b, d) w_cd f_(a-c)(b-d)) / w.
// False if a weight is not positive.
inline bool enclose_piece(const Hom* P, int nu, int nv, int dim, const double* width,
                          Derivative_enclosure& out, int order = 2) {
  out.dim = dim;
  out.order = order;
  using Range4 = std::array<Interval, 4>;
  auto at = [&](int i, int j) -> const Hom& { return P[i * nv + j]; };
  // Range of the (a, b) hodograph net: falling(p, a) falling(q, b) times the (a, b)-th forward
  // difference of the poles; zero where the degree is below the order.
  auto hodograph = [&](int a, int b) {
    Range4 r;
    for (auto& x : r) x = Interval{0.0, 0.0};
    if (a > nu - 1 || b > nv - 1) return r;
    static constexpr double k_binom[4][4] = {{1, 0, 0, 0}, {1, 1, 0, 0}, {1, 2, 1, 0}, {1, 3, 3, 1}};
    double scale = 1.0;
    for (int k = 0; k < a; ++k) scale *= nu - 1 - k;
    for (int k = 0; k < b; ++k) scale *= nv - 1 - k;
    bool first = true;
    for (int i = 0; i + a < nu; ++i)
      for (int j = 0; j + b < nv; ++j) {
        Hom v = Hom::Zero();
        for (int s = 0; s <= a; ++s)
          for (int t = 0; t <= b; ++t) {
            const double c = ((a - s + b - t) % 2 ? -1.0 : 1.0) * k_binom[a][s] * k_binom[b][t];
            v += c * at(i + s, j + t);
          }
        v *= scale;
        for (int c = 0; c < 4; ++c)
          r[c] = first ? Interval{v[c], v[c]} : hull(r[c], Interval{v[c], v[c]});
        first = false;
      }
    return r;
  };
  const Range4 X00 = hodograph(0, 0);
  const Interval w = X00[3];
  if (!(w.lo > 0.0)) return false;
  for (int c = 0; c < 3; ++c) out.p[c] = Interval{HUGE_VAL, -HUGE_VAL};
  for (int k = 0; k < nu * nv; ++k)
    for (int c = 0; c < 3; ++c) {
      const double x = P[k][c] / P[k][3];
      out.p[c] = Interval{std::min(out.p[c].lo, x), std::max(out.p[c].hi, x)};
    }
  if (dim == 0) return true;
  // f[a][b]: derivative a times along s and b times along t (local parameters of the net).
  static constexpr int k_binom[4][4] = {{1, 0, 0, 0}, {1, 1, 0, 0}, {1, 2, 1, 0}, {1, 3, 3, 1}};
  const int top = std::clamp(order, 1, 3);
  Range4 X[4][4];
  Interval3 f[4][4];
  X[0][0] = X00;
  f[0][0] = out.p;
  for (int total = 1; total <= top; ++total)
    for (int b = 0; b <= (dim >= 2 ? total : 0); ++b) {
      const int a = total - b;
      X[a][b] = hodograph(a, b);
      for (int c = 0; c < 3; ++c) {
        Interval acc = X[a][b][c];
        for (int i = 0; i <= a; ++i)
          for (int j = 0; j <= b; ++j) {
            if (i == 0 && j == 0) continue;
            acc = acc - double(k_binom[a][i] * k_binom[b][j]) * (X[i][j][3] * f[a - i][b - j][c]);
          }
        f[a][b][c] = divide_positive(acc, w);
      }
    }
  const double iw[2] = {1.0 / width[0], dim >= 2 ? 1.0 / width[1] : 1.0};
  auto scaled = [&](int a, int b) {
    double s = 1.0;
    for (int k = 0; k < a; ++k) s *= iw[0];
    for (int k = 0; k < b; ++k) s *= iw[1];
    Interval3 v;
    for (int c = 0; c < 3; ++c) v[c] = s * f[a][b][c];
    return v;
  };
  for (int k = 0; k < dim; ++k) out.d[k] = scaled(k == 0, k == 1);
  if (top < 2) return true;
  for (int k = 0; k < dim; ++k)
    for (int l = 0; l < dim; ++l) out.dd[k][l] = scaled((k == 0) + (l == 0), (k == 1) + (l == 1));
  if (top < 3) return true;
  for (int k = 0; k < dim; ++k)
    for (int l = 0; l < dim; ++l)
      for (int m = 0; m < dim; ++m)
        out.ddd[k][l][m] =
            scaled((k == 0) + (l == 0) + (m == 0), (k == 1) + (l == 1) + (m == 1));
  return true;
}

// Whether Cholesky of the symmetric n x n M (n <= 4) finds positive pivots throughout.
inline bool cholesky_succeeds(const double M[4][4], int n) {
  double L[4][4] = {};
  for (int j = 0; j < n; ++j) {
    double d = M[j][j];
    for (int k = 0; k < j; ++k) d -= L[j][k] * L[j][k];
    if (!(d > 0.0)) return false;
    L[j][j] = std::sqrt(d);
    for (int i = j + 1; i < n; ++i) {
      double t = M[i][j];
      for (int k = 0; k < j; ++k) t -= L[i][k] * L[j][k];
      L[i][j] = t / L[j][j];
    }
  }
  return true;
}

// Parameters of corner k (0..3) of a sub-net over [lo, hi]: bit 0 the first, bit 1 the second.
inline void corner_params(const double* lo, const double* hi, int k, double* q) {
  q[0] = (k & 1) ? hi[0] : lo[0];
  q[1] = (k & 2) ? hi[1] : lo[1];
}

// Pole index of corner k of a nu x nv net (pole (i, j) at i * nv + j, i along the first
// parameter).
inline int corner_pole(int nu, int nv, int k) {
  const int i = (k & 1) ? nu - 1 : 0;
  const int j = (k & 2) ? nv - 1 : 0;
  return i * nv + j;
}

}  // namespace extremal::internal
