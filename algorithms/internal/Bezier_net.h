// Control nets of rational Bezier pieces in homogeneous coordinates: halving by de Casteljau and
// the bounds the global distance solver takes from the convex-hull property. Not API.
#pragma once

#include <algorithm>
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

}  // namespace extremal::internal
