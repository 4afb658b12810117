// Pairs the branch and bound settles without splitting: convex regions about Newton solutions,
// and pairs whose gradient excludes a minimum (Global_distance.h).
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

// Hull bounds approach a minimum only quadratically in the sub-patch size, so certifying a
// smooth minimum to 1e-12 by subdivision alone takes sub-patches of 1e-6. Instead, around a
// Newton solution x* of an element pair: if the Hessian of D = |f_A - f_B|^2, enclosed by
// interval arithmetic on the hodographs of the sub-nets over a parameter box R about x*, is
// positive definite throughout R, then D is convex on R and
//   D(x) >= D(x*) + grad D(x*) . (x - x*)   for every x in R,
// whose minimum over R is D(x*) up to the Newton residual (and exact at a minimum on a domain
// edge, where the gradient points out of R). Every node pair inside R gets that bound.
// Enclosures of element e of `side` over the parameter box [lo, hi], with points relative to
// `origin` (a point near the box: interval arithmetic on the quotient rule loses |f| times the
// weight derivative's width, so f must be small).
bool Distance_solver::enclose_element(int side, int e, const double* lo, const double* hi,
                             const Vec3& origin, internal::Derivative_enclosure& out, int order) {
  const Distance_hierarchy& h = *m_side[side].h;
  const int dim = feature(side, e).dimension();
  const Mat3& R = m_side[side].X->rotation();
  const Vec3& t = m_side[side].X->translation();
  auto& net = m_scratch.region_net;
  bool first = true;
  for (const Distance_hierarchy::Piece& piece : h.pieces()) {
    if (piece.element != e) continue;
    double s0[2] = {0.0, 0.0}, s1[2] = {1.0, 1.0}, width[2] = {1.0, 1.0};
    bool overlap = true;
    for (int k = 0; k < dim && overlap; ++k) {
      const double a = std::max(lo[k], piece.lo[k]), b = std::min(hi[k], piece.hi[k]);
      const double span = piece.hi[k] - piece.lo[k];
      overlap = a < b && span > 0.0;
      s0[k] = (a - piece.lo[k]) / span;
      s1[k] = (b - piece.lo[k]) / span;
      width[k] = b - a;
    }
    if (!overlap) continue;
    const int count = piece.nu * piece.nv;
    net.resize(count);
    const Eigen::Vector4d* src = h.poles() + piece.offset;
    for (int k = 0; k < count; ++k) {
      net[k].head<3>() = R * src[k].head<3>() + src[k][3] * (t - origin);
      net[k][3] = src[k][3];
    }
    if (dim >= 1) internal::restrict_net(net.data(), piece.nu, piece.nv, s0[0], s1[0], s0[1], s1[1]);
    internal::Derivative_enclosure enc;
    if (!internal::enclose_piece(net.data(), piece.nu, piece.nv, dim, width, enc, order))
      return false;
    internal::hull_into(out, enc, first);
    first = false;
  }
  return !first;
}

bool Distance_solver::certify_region(internal::Known_solution& sol, const double* rho) {
  const Feature& fa = feature(0, sol.ea);
  const Feature& fb = feature(1, sol.eb);
  const int na = fa.dimension(), nb = fb.dimension(), n = na + nb;
  if (n == 0) return false;
  internal::Convex_region reg;
  reg.ea = sol.ea;
  reg.eb = sol.eb;
  for (int k = 0; k < n; ++k) {
    const Feature& f = k < na ? fa : fb;
    const int i = k < na ? k : k - na;
    reg.lo[k] = std::max(f.lower(i), sol.params[k] - rho[k]);
    reg.hi[k] = std::min(f.upper(i), sol.params[k] + rho[k]);
  }
  reg.given = sol.given;
  if (!convex_over(sol.params, reg)) return false;
  m_scratch.regions.push_back(reg);
  return true;
}

bool Distance_solver::convex_over(const Vec4& x, internal::Convex_region& reg) {
  using internal::Interval;
  const Feature& fa = feature(0, reg.ea);
  const Feature& fb = feature(1, reg.eb);
  const int na = fa.dimension(), nb = fb.dimension(), n = na + nb;
  if (n == 0) return false;
  Feature_point xa, xb;
  evaluate_feature(fa, *m_side[0].X, x.data(), xa, 2);
  evaluate_feature(fb, *m_side[1].X, x.data() + na, xb, 2);
  internal::Derivative_enclosure A, B;
  if (!enclose_element(0, reg.ea, reg.lo, reg.hi, xa.p, A, 3) ||
      !enclose_element(1, reg.eb, reg.lo + na, reg.hi + na, xb.p, B, 3))
    return false;
  // The Hessian of D over R as intervals: A's rows, then B's.
  Interval H[4][4];
  internal::Interval3 r;
  for (int c = 0; c < 3; ++c) r[c] = Interval{xa.p[c] - xb.p[c], xa.p[c] - xb.p[c]} + (A.p[c] - B.p[c]);
  for (int k = 0; k < na; ++k)
    for (int l = 0; l < na; ++l)
      H[k][l] = 2.0 * ((k == l ? self_dot(A.d[k]) : dot(A.d[k], A.d[l])) + dot(r, A.dd[k][l]));
  for (int k = 0; k < na; ++k)
    for (int l = 0; l < nb; ++l) H[k][na + l] = H[na + l][k] = -2.0 * dot(A.d[k], B.d[l]);
  for (int k = 0; k < nb; ++k)
    for (int l = 0; l < nb; ++l)
      H[na + k][na + l] =
          2.0 * ((k == l ? self_dot(B.d[k]) : dot(B.d[k], B.d[l])) - dot(r, B.dd[k][l]));
  // A second enclosure, much tighter on small regions: the mean-value form about x*,
  // H(x) = H(x*) + sum_k dH/dx_k (eta) (x_k - x*_k), with the third derivatives enclosed over R.
  // The first-order variation of r . r_ij along the tangents (nearly orthogonal to r_ij at a
  // minimum) cancels here, where the plain enclosure counts every component's range in full.
  // H lies in both enclosures, so in their intersection. The form needs H continuous on R: no
  // knot inside R where a second derivative may jump (the plain enclosure, a hull over the
  // pieces, needs only the C1 continuity of D).
  bool smooth = true;
  for (int k = 0; k < n; ++k)
    smooth = smooth && second_derivatives_continuous(k < na ? fa : fb, k < na ? k : k - na,
                                                     reg.lo[k], reg.hi[k]);
  if (smooth) {
    // Derivatives of r = f_A - f_B along all n parameters (zero across the sides): at x*, and
    // enclosed over R.
    auto side_of = [&](int k) { return k < na ? 0 : 1; };
    auto local = [&](int k) { return k < na ? k : k - na; };
    const Vec3 r0 = xa.p - xb.p;
    Vec3 r1[4], r2[4][4];
    internal::Interval3 R1[4], R2[4][4], R3[4][4][4];
    const internal::Interval3 zero{};
    auto negate = [](const internal::Interval3& v) {
      internal::Interval3 m;
      for (int c = 0; c < 3; ++c) m[c] = Interval{-v[c].hi, -v[c].lo};
      return m;
    };
    for (int k = 0; k < n; ++k) {
      const int sk = side_of(k), ik = local(k);
      r1[k] = sk == 0 ? xa.d[ik] : Vec3(-xb.d[ik]);
      R1[k] = sk == 0 ? A.d[ik] : negate(B.d[ik]);
      for (int l = 0; l < n; ++l) {
        const bool same = side_of(l) == sk;
        const int il = local(l);
        r2[k][l] = !same ? Vec3::Zero() : sk == 0 ? xa.dd[ik][il] : Vec3(-xb.dd[ik][il]);
        R2[k][l] = !same ? zero : sk == 0 ? A.dd[ik][il] : negate(B.dd[ik][il]);
        for (int m = 0; m < n; ++m) {
          const bool all = same && side_of(m) == sk;
          R3[k][l][m] = !all ? zero : sk == 0 ? A.ddd[ik][il][local(m)]
                                              : negate(B.ddd[ik][il][local(m)]);
        }
      }
    }
    for (int i = 0; i < n; ++i)
      for (int j = i; j < n; ++j) {
        const double h0 = 2.0 * (r1[i].dot(r1[j]) + r0.dot(r2[i][j]));
        Interval delta{0.0, 0.0};
        for (int k = 0; k < n; ++k) {
          const Interval dH =
              2.0 * (dot(R2[i][k], R1[j]) + dot(R1[i], R2[j][k]) + dot(R1[k], R2[i][j]) +
                     dot(r, R3[i][j][k]));
          delta = delta + dH * Interval{reg.lo[k] - x[k], reg.hi[k] - x[k]};
        }
        const Interval mv{h0 + delta.lo, h0 + delta.hi};
        const Interval both{std::max(H[i][j].lo, mv.lo), std::min(H[i][j].hi, mv.hi)};
        if (!(both.lo <= both.hi)) return false;  // only by rounding: no certificate
        H[i][j] = H[j][i] = both;
      }
  }
  // Positive definite on all of R: after Jacobi scaling (centre C, radius Rad >= 0), for every
  // symmetric H the intervals hold and every unit x, with z = sign(x) and T = diag(z),
  //   x' H x >= x' C x - |x|' Rad |x| = x' (C - T Rad T) x,
  // so it suffices that the 2^(n-1) vertex matrices C - T Rad T (z and -z give the same) are
  // positive definite (Hertz 1992: their smallest eigenvalue is exactly that of the interval
  // matrix; Rohn's lambda_min(C) - rho(Rad) is never larger). Checked by Cholesky with a margin
  // of 1e-6, far above rounding.
  using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 4, 4>;
  Small C(n, n), Rad(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      C(i, j) = 0.5 * (H[i][j].lo + H[i][j].hi);
      Rad(i, j) = 0.5 * (H[i][j].hi - H[i][j].lo);
    }
  double S[4];
  for (int i = 0; i < n; ++i) {
    if (!(C(i, i) > 0.0)) return false;
    S[i] = 1.0 / std::sqrt(C(i, i));
  }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      C(i, j) *= S[i] * S[j];
      Rad(i, j) *= S[i] * S[j];
    }
  if (!C.allFinite() || !Rad.allFinite()) return false;
  for (int z = 0; z < (1 << (n - 1)); ++z) {
    double M[4][4];
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const bool flip = (((z >> i) ^ (z >> j)) & 1) != 0;
        M[i][j] = C(i, j) - (flip ? -Rad(i, j) : Rad(i, j)) - (i == j ? 1e-6 : 0.0);
      }
    if (!internal::cholesky_succeeds(M, n)) return false;
  }
  const Vec3 d = xa.p - xb.p;
  double D = d.squaredNorm();
  for (int k = 0; k < n; ++k) {
    const double g = k < na ? 2.0 * d.dot(xa.d[k]) : -2.0 * d.dot(xb.d[k - na]);
    D += std::min(g * (reg.lo[k] - x[k]), g * (reg.hi[k] - x[k]));
  }
  // Rounding in D(x*) is a few ulps of the coordinates: m_resolution covers it.
  reg.lower = std::sqrt(std::max(0.0, D)) - m_resolution;
  return std::isfinite(reg.lower);
}

std::optional<double> Distance_solver::convex_region_lower(const Parameter_box& box, const Vec4& x) {
  if (box.element_a < 0 || box.element_b < 0) return std::nullopt;
  internal::Convex_region reg;
  reg.ea = box.element_a;
  reg.eb = box.element_b;
  const int n = feature(0, reg.ea).dimension() + feature(1, reg.eb).dimension();
  for (int k = 0; k < n; ++k) {
    if (!(x[k] >= box.lo[k] && x[k] <= box.hi[k])) return std::nullopt;
    reg.lo[k] = box.lo[k];
    reg.hi[k] = box.hi[k];
  }
  set_resolution();
  if (!convex_over(x, reg)) return std::nullopt;
  return reg.lower;
}

// Called for a popped pair of sub-patches: certifies a region about each uncertified solution
// inside the pair that could be the global minimum, with half-widths the pair's parameter
// widths, again each time the pairs around it have halved.
void Distance_solver::try_certify(const Live_node& a, const Live_node& b) {
  for (internal::Known_solution& s : m_scratch.solutions) {
    if (s.certified || s.ea != a.element || s.eb != b.element) continue;
    if (!s.given && s.distance > m_best.distance + 1e-6 * (1.0 + m_best.distance)) continue;
    bool inside = true;
    for (int k = 0; k < a.dim; ++k) inside = inside && s.params[k] >= a.lo[k] && s.params[k] <= a.hi[k];
    for (int k = 0; k < b.dim; ++k)
      inside = inside && s.params[a.dim + k] >= b.lo[k] && s.params[a.dim + k] <= b.hi[k];
    if (!inside) continue;
    double rho[4] = {0, 0, 0, 0};
    double size = 0.0;  // largest half-width relative to its element's domain
    for (int k = 0; k < a.dim + b.dim; ++k) {
      const Live_node& n = k < a.dim ? a : b;
      const int i = k < a.dim ? k : k - a.dim;
      const Feature& f = feature(k < a.dim ? 0 : 1, n.element);
      rho[k] = n.hi[i] - n.lo[i];
      size = std::max(size, rho[k] / std::max(f.upper(i) - f.lower(i), 1e-300));
    }
    if (!(size <= 0.5 * s.tried)) continue;
    s.tried = size;
    s.certified = certify_region(s, rho);
  }
}

double Distance_solver::region_bound(const Live_node& a, const Live_node& b) const {
  double L = 0.0;
  for (const internal::Convex_region& reg : m_scratch.regions) {
    if (reg.ea != a.element || reg.eb != b.element) continue;
    bool inside = true;
    for (int k = 0; k < a.dim; ++k) inside = inside && a.lo[k] >= reg.lo[k] && a.hi[k] <= reg.hi[k];
    for (int k = 0; k < b.dim; ++k)
      inside = inside && b.lo[k] >= reg.lo[a.dim + k] && b.hi[k] <= reg.hi[a.dim + k];
    if (inside) L = std::max(L, reg.lower);
  }
  return L;
}

// A pair of sub-patches holds no minimiser of the distance between the bodies when, on one
// side, the gradient of D = |f_A - f_B|^2 along that side's parameters is nowhere zero over the
// pair (its enclosure excludes zero in some component) and the sub-patch touches no open side
// of its element: a minimiser with that side's point inside the element's domain would make
// the gradient vanish, and one on a carried boundary (a trim edge, a face edge) lies on a curve
// element, whose own pairs hold it (or, with Distance_request::carried_sides, on a side whose
// minima another pair holds). Such a pair is dropped without a bound: the minimum lies in the
// pairs that remain. This is what certifies minima on trim boundaries, where the patch beyond
// the trim comes closer and no hull bound of the straddling sub-patches can rise above the
// minimum, and a face's minimum on a side it shares with a tracked face (a C0 crease) without
// solving it to the tie. Applied to trimmed faces and requested elements only (see below).
bool Distance_solver::holds_no_minimum(int ia, int ib, int side) {
  const int in = side == 0 ? ia : ib;
  const Live_node& n = m_side[side].pools->nodes[in];
  const Live_node& o = m_side[1 - side].pools->nodes[side == 0 ? ib : ia];
  if (!n.is_net() || !o.is_net() || n.dim == 0) return false;
  const Distance_hierarchy::Element& el = m_side[side].h->elements()[n.element];
  // Trimmed faces, and restricted queries' elements with carried sides: elsewhere the hull
  // bounds rise above the minimum away from the stationary points, and near them the gradient
  // vanishes, so the enclosure would not pay.
  unsigned open = el.open_sides;
  // With carried sides requested, both elements of the restricted query: a pair away from the
  // other element's open sides (an ellipsoid's poles) is set aside by its gradient too.
  const bool requested = n.element == m_only[side] &&
                         (m_proof.carried_sides[0] | m_proof.carried_sides[1]) != 0u;
  if (requested) open &= ~m_proof.carried_sides[side];
  if ((!el.trimmed && !requested) || m_side[side].h->reaches_uncarried(n.element, n.lo, n.hi, open))
    return false;
  auto& gradients = m_side[side].pools->gradients;
  if (gradients.size() <= static_cast<std::size_t>(in))
    gradients.resize(m_side[side].pools->nodes.size());
  internal::Gradient_enclosure& e = gradients[in];
  if (e.state == 0) {
    auto& net = m_scratch.region_net;
    const int count = n.count();
    net.resize(count);
    const Hom* src = m_side[side].pools->hom.data() + n.offset;
    for (int k = 0; k < count; ++k) {
      net[k] = src[k];
      net[k].head<3>() -= src[k][3] * n.centre;
    }
    const double width[2] = {n.hi[0] - n.lo[0], n.dim > 1 ? n.hi[1] - n.lo[1] : 1.0};
    internal::Derivative_enclosure full;
    e.state = internal::enclose_piece(net.data(), n.nu, n.nv, n.dim, width, full, 1) ? 1 : -1;
    e.d[0] = full.d[0];
    e.d[1] = full.d[1];
  }
  if (e.state < 0) return false;
  internal::Interval3 r;  // f_side - f_other over the pair, from the world boxes
  double rmax = 0.0;
  for (int c = 0; c < 3; ++c) {
    r[c] = internal::Interval{n.bmin[c] - o.bmax[c], n.bmax[c] - o.bmin[c]};
    rmax = std::max({rmax, std::abs(r[c].lo), std::abs(r[c].hi)});
  }
  for (int k = 0; k < n.dim; ++k) {
    const internal::Interval g = dot(r, e.d[k]);
    // Largest magnitude of each coordinate of the derivative over the node.
    double m[3];
    for (int c = 0; c < 3; ++c) m[c] = std::max(std::abs(e.d[k][c].lo), std::abs(e.d[k][c].hi));
    const double margin = 1e-12 * rmax * std::max({m[0], m[1], m[2]});  // far above rounding
    if (g.lo > margin || g.hi < -margin) {
      // The other side's points moving by s (this side's frame) change the component by at
      // most s |d_k|: it keeps its sign while s stays below this reach. Too short a reach
      // (a component near zero somewhere on the pair): split further instead.
      const double dk = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
      const double reach = ((g.lo > margin ? g.lo : -g.hi) - margin) / dk;
      if (reach < m_proof.carried_min_reach) continue;
      m_reach[side] = std::min(m_reach[side], reach);
      if (!m_proof.keep_proofs) return true;
      Gradient_proof& p = m_scratch.proofs.emplace_back();
      p.side = side;
      p.component = k;
      p.own_min = n.bmin;
      p.own_max = n.bmax;
      p.other_min = o.bmin;
      p.other_max = o.bmax;
      for (int c = 0; c < 3; ++c) {
        p.derivative_min[c] = e.d[k][c].lo;
        p.derivative_max[c] = e.d[k][c].hi;
      }
      for (int j = 0; j < 2; ++j) {
        p.own_lo[j] = n.lo[j];
        p.own_hi[j] = n.hi[j];
        p.other_lo[j] = o.lo[j];
        p.other_hi[j] = o.hi[j];
      }
      return true;
    }
  }
  return false;
}

}  // namespace extremal::internal
