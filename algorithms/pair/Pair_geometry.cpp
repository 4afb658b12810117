#include "algorithms/pair/Pair_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace extremal {

namespace {

// The unit normal n = m / |m| of a surface feature whose outward m = sign (t_u x t_v) is
// given, and its derivatives along the two parameters (the normal forms need both).
void unit_normal_and_derivatives(const Feature_point& f, int sign, const Vec3& m, Vec3& n,
                                 Vec3 (&dn)[2]) {
  const double len = m.norm();
  if (!(len > 0.0)) {
    n.setZero();
    dn[0].setZero();
    dn[1].setZero();
    return;
  }
  n = m / len;
  for (int k = 0; k < 2; ++k) {
    const Vec3 dm = sign * (f.dd[0][k].cross(f.d[1]) + f.d[0].cross(f.dd[1][k]));
    dn[k] = (dm - n * n.dot(dm)) / len;
  }
}

// Phi, the projection errors and M of any form and feature dimensions.
// `n`, `dn`: the reference surface's unit normal and its derivatives (the normal forms).
void build_general_rows(Pair_system& s, const Vec3& d, Formulation form, const Vec3& n,
                        const Vec3 (&dn)[2]);
// The motion term b of the system's form (zero unless `with_motion` and a body moves).
void add_motion(const Posed_feature& A, const Posed_feature& B, Pair_system& s,
                bool with_motion, const Vec3& n);
// Normal forms: divides the rows of the non-reference surface's vanishing tangents near its
// poles by the distance to the pole (see the definition).
void desingularise_pole_rows(const Feature& f, const double* q, int offset, Pair_system& s);

}  // namespace

void build_pair_system(const Posed_feature& A, const Posed_feature& B, const Vec4& params,
                       Pair_system& s, bool with_motion, Formulation form) {
  const int na = A.feature->dimension(), nb = B.feature->dimension();
  s.na = na;
  s.nb = nb;
  evaluate_feature(*A.feature, *A.pose, params.data(), s.a, 2, &s.spans_a);
  evaluate_feature(*B.feature, *B.pose, params.data() + na, s.b, 2, &s.spans_b);
  const Vec3 d = s.a.p - s.b.p;
  s.d = d;
  s.distance = d.norm();
  const bool surf_a = na == 2, surf_b = nb == 2;
  if ((form == Formulation::Normal_of_a && (!surf_a || nb == 0)) ||
      (form == Formulation::Normal_of_b && (!surf_b || na == 0)))
    form = Formulation::Projection;
  s.form = form;
  const int sign_a = surf_a ? A.feature->outward_sign() : 0;
  const int sign_b = surf_b ? B.feature->outward_sign() : 0;
  s.outward_a = surf_a ? Vec3(sign_a * s.a.d[0].cross(s.a.d[1])) : Vec3::Zero();
  s.outward_b = surf_b ? Vec3(sign_b * s.b.d[0].cross(s.b.d[1])) : Vec3::Zero();
  // Only the normal forms need the unit normal (of their reference surface).
  Vec3 n = Vec3::Zero(), dn[2];
  if (form == Formulation::Normal_of_a)
    unit_normal_and_derivatives(s.a, sign_a, s.outward_a, n, dn);
  else if (form == Formulation::Normal_of_b)
    unit_normal_and_derivatives(s.b, sign_b, s.outward_b, n, dn);

  if (na == 2 && nb == 2 && form == Formulation::Projection) {
    // Surface-surface in the projection form, the tracker's hot case: the loops below written
    // out, each distinct product once (x.y == y.x exactly; dd[0][1] == dd[1][0]), so the
    // entries round exactly as the loops' do.
    const Vec3 *fa = s.a.d, *fb = s.b.d;
    s.projection = Vec4(d.dot(fa[0]), d.dot(fa[1]), d.dot(fb[0]), d.dot(fb[1]));
    s.phi = s.projection;
    Vec4& len2 = s.tangent_length2;
    len2 = Vec4(fa[0].squaredNorm(), fa[1].squaredNorm(), fb[0].squaredNorm(),
                fb[1].squaredNorm());
    Mat4& M = s.M;
    const double aa01 = fa[1].dot(fa[0]), bb01 = fb[1].dot(fb[0]);
    M(0, 0) = len2[0] + d.dot(s.a.dd[0][0]);
    M(1, 1) = len2[1] + d.dot(s.a.dd[1][1]);
    M(0, 1) = M(1, 0) = aa01 + d.dot(s.a.dd[0][1]);
    M(2, 2) = -len2[2] + d.dot(s.b.dd[0][0]);
    M(3, 3) = -len2[3] + d.dot(s.b.dd[1][1]);
    M(2, 3) = M(3, 2) = -bb01 + d.dot(s.b.dd[0][1]);
    s.symmetric_hessian = true;
    for (int i = 0; i < 2; ++i)
      for (int k = 0; k < 2; ++k) {
        const double ab = fa[i].dot(fb[k]);
        M(i, 2 + k) = -ab;
        M(2 + k, i) = ab;
      }
  } else {
    build_general_rows(s, d, form, n, dn);
  }
  add_motion(A, B, s, with_motion, n);
  if (form == Formulation::Normal_of_a && surf_b && B.feature->collapsed_edges())
    desingularise_pole_rows(*B.feature, params.data() + na, na, s);
  else if (form == Formulation::Normal_of_b && surf_a && A.feature->collapsed_edges())
    desingularise_pole_rows(*A.feature, params.data(), 0, s);
}

namespace {

void build_general_rows(Pair_system& s, const Vec3& d, Formulation form, const Vec3& n,
                        const Vec3 (&dn)[2]) {
  const int na = s.na, nb = s.nb;
  s.phi.setZero();
  s.projection.setZero();
  s.M.setIdentity();
  s.symmetric_hessian = false;
  s.tangent_length2.setZero();
  for (int k = 0; k < na + nb; ++k) s.tangent_length2[k] = s.tangent(k).squaredNorm();
  for (int i = 0; i < na; ++i) {
    s.projection[i] = d.dot(s.a.d[i]);
    if (form == Formulation::Normal_of_b) {
      s.phi[i] = n.dot(s.a.d[i]);
      for (int k = 0; k < na; ++k) s.M(i, k) = n.dot(s.a.dd[i][k]);
      for (int l = 0; l < nb; ++l) s.M(i, na + l) = dn[l].dot(s.a.d[i]);
      continue;
    }
    s.phi[i] = s.projection[i];
    for (int k = 0; k < na; ++k) s.M(i, k) = s.a.d[k].dot(s.a.d[i]) + d.dot(s.a.dd[i][k]);
    for (int l = 0; l < nb; ++l) s.M(i, na + l) = -s.b.d[l].dot(s.a.d[i]);
  }
  for (int j = 0; j < nb; ++j) {
    s.projection[na + j] = d.dot(s.b.d[j]);
    if (form == Formulation::Normal_of_a) {
      s.phi[na + j] = n.dot(s.b.d[j]);
      for (int k = 0; k < na; ++k) s.M(na + j, k) = dn[k].dot(s.b.d[j]);
      for (int l = 0; l < nb; ++l) s.M(na + j, na + l) = n.dot(s.b.dd[j][l]);
      continue;
    }
    s.phi[na + j] = s.projection[na + j];
    for (int k = 0; k < na; ++k) s.M(na + j, k) = s.a.d[k].dot(s.b.d[j]);
    for (int l = 0; l < nb; ++l)
      s.M(na + j, na + l) = -s.b.d[l].dot(s.b.d[j]) + d.dot(s.b.dd[j][l]);
  }
}

void add_motion(const Posed_feature& A, const Posed_feature& B, Pair_system& s,
                bool with_motion, const Vec3& n) {
  const int na = s.na, nb = s.nb;
  const Formulation form = s.form;
  const Vec3& d = s.d;
  s.motion.setZero();
  if (!with_motion) return;
  const bool moving_a = A.twist && !A.twist->is_zero();
  const bool moving_b = B.twist && !B.twist->is_zero();
  if (!moving_a && !moving_b) return;
  // Relative velocity of the two material points; tangents and normals turn with their body.
  Vec3 w = Vec3::Zero();
  if (moving_a) w += A.twist->velocity_at(s.a.p, *A.pose);
  if (moving_b) w -= B.twist->velocity_at(s.b.p, *B.pose);
  const Vec3 wa = moving_a ? A.twist->angular : Vec3::Zero();
  const Vec3 wb = moving_b ? B.twist->angular : Vec3::Zero();
  // Projection rows: w.t + d.(omega x t) = (w + d x omega).t, one vector per side.
  const Vec3 va = w + d.cross(wa), vb = w + d.cross(wb);
  for (int i = 0; i < na; ++i) {
    if (form == Formulation::Normal_of_b)
      s.motion[i] = n.dot(wa.cross(s.a.d[i])) + wb.cross(n).dot(s.a.d[i]);
    else
      s.motion[i] = va.dot(s.a.d[i]);
  }
  for (int j = 0; j < nb; ++j) {
    if (form == Formulation::Normal_of_a)
      s.motion[na + j] = wa.cross(n).dot(s.b.d[j]) + n.dot(wb.cross(s.b.d[j]));
    else
      s.motion[na + j] = vb.dot(s.b.d[j]);
  }
}

// In a normal form the rows of the side opposite the reference surface R are n_R . t_j. At a
// pole of that side (a collapsed patch edge) the tangent along the edge vanishes like rho, the
// parameter distance to the edge, so its row is rho g(params) with g regular. Newton on
// rho g = 0 is drawn to the spurious branch rho = 0: the pair stays on the pole while the contact
// point moves off it (a ball rolling on a plane from its pole). Divided by rho the row is g, whose
// zero is the meridian pointing down the slope, with a regular Jacobian:
//   (phi / rho)' = M_row / rho - phi / rho^2 drho,   b / rho likewise (rho has no time term).
// The projection rows need none of this: they are a gradient, and the minimum-seeking solve
// shifts the indefinite Hessian there into a descent step that leaves the pole.
void desingularise_pole_rows(const Feature& f, const double* q, int offset, Pair_system& s) {
  const unsigned collapsed = f.collapsed_edges();
  for (int along = 0; along < 2; ++along) {  // along: the parameter whose tangent vanishes
    const int across = 1 - along;            // the parameter that measures rho
    // Bits of Feature::collapsed_edges: 1 u_min, 2 u_max (t_v vanishes), 4 v_min, 8 v_max.
    const unsigned low_bit = across == 0 ? 1u : 4u, high_bit = across == 0 ? 2u : 8u;
    const double lo = f.lower(across), hi = f.upper(across), x = q[across];
    double rho = std::numeric_limits<double>::infinity(), drho = 0.0;
    if ((collapsed & low_bit) && x - lo < rho) {
      rho = x - lo;
      drho = 1.0;
    }
    if ((collapsed & high_bit) && hi - x < rho) {
      rho = hi - x;
      drho = -1.0;
    }
    // On the pole itself the row is rounding noise over zero: the tracker keeps its parameters
    // off it (Extremal_tracker::leave_poles); infinity: no pole on this parameter.
    if (!(rho > 0.0) || !std::isfinite(rho)) continue;
    const int row = offset + along, col = offset + across;
    const double inv = 1.0 / rho, phi = s.phi[row];
    s.M.row(row) *= inv;
    s.M(row, col) -= drho * phi * inv * inv;
    s.phi[row] = phi * inv;
    s.motion[row] *= inv;
  }
}

}  // namespace

Vec3 unit_normal(const Vec3& outward) {
  const double len = outward.norm();
  return len > 0.0 ? Vec3(outward / len) : Vec3::Zero();
}

Vec4 normalised_projection_errors(const Pair_system& s) {
  // All four lanes at once (two packed square roots and divisions on SSE2: this runs every
  // tracker step), then the undefined ones set to zero. Padding lanes have zero tangents.
  const Vec4& len2 = s.tangent_length2;
  const Vec4 denom = s.distance * len2.cwiseSqrt();
  Vec4 e = s.projection.cwiseQuotient(denom);
  const int n = s.size();
  for (int k = 0; k < 4; ++k) {
    // A tangent that vanishes (a pole) carries no condition: its error is rounding noise.
    // It is compared with the other tangent of its side (itself on a curve).
    const int other = k < s.na ? s.na - 1 - k : s.na + (s.nb - 1 - (k - s.na));
    const bool defined = k < n && len2[k] > 1e-16 * len2[other] && denom[k] > 0.0;
    if (!defined) e[k] = 0.0;  // |t_k| <= 1e-8 |t_other|, |d| = 0, or padding
  }
  return e;
}

Parameter_domain Parameter_domain::of(const Feature& A, const Feature& B) {
  Parameter_domain d;
  for (const Feature* f : {&A, &B})
    for (int i = 0; i < f->dimension(); ++i, ++d.n) {
      d.lower[d.n] = f->lower(i);
      d.upper[d.n] = f->upper(i);
      if (f->is_closed(i)) d.closed |= 1u << d.n;
    }
  return d;
}

unsigned Parameter_domain::clamp(Vec4& params) const {
  // The usual case, every parameter strictly inside (NaN fails the test): nothing to do.
  if (strictly_inside(params)) return 0;
  unsigned mask = 0;
  for (int k = 0; k < n; ++k) {
    const double lo = lower[k], hi = upper[k];
    double& x = params[k];
    if (!std::isfinite(x)) x = 0.5 * (lo + hi);
    if (closed & (1u << k)) {
      if (x < lo || x > hi) {
        const double period = hi - lo;
        x = std::min(std::max(x - period * std::floor((x - lo) / period), lo), hi);
      }
    } else if (x <= lo) {
      x = lo;
      mask |= 1u << k;
    } else if (x >= hi) {
      x = hi;
      mask |= 1u << k;
    }
  }
  return mask;
}

bool Parameter_domain::strictly_inside(const Vec4& params) const {
  // Runs twice per tracker step: four lanes compared at once, unused lanes masked off.
#if defined(__SSE2__)
  const __m128d p01 = _mm_loadu_pd(params.data()), p23 = _mm_loadu_pd(params.data() + 2);
  const __m128d in01 = _mm_and_pd(_mm_cmpgt_pd(p01, _mm_loadu_pd(lower.data())),
                                  _mm_cmplt_pd(p01, _mm_loadu_pd(upper.data())));
  const __m128d in23 = _mm_and_pd(_mm_cmpgt_pd(p23, _mm_loadu_pd(lower.data() + 2)),
                                  _mm_cmplt_pd(p23, _mm_loadu_pd(upper.data() + 2)));
  const unsigned in = static_cast<unsigned>(_mm_movemask_pd(in01)) |
                      (static_cast<unsigned>(_mm_movemask_pd(in23)) << 2);
  const unsigned used = (1u << n) - 1u;
  return (in & used) == used;
#else
  bool inside = true;
  for (int k = 0; k < n; ++k) inside &= (params[k] > lower[k]) & (params[k] < upper[k]);
  return inside;
#endif
}

unsigned Parameter_domain::lower_mask(const Vec4& params) const {
  unsigned mask = 0;
  for (int k = 0; k < n; ++k)
    if (!(closed & (1u << k)) && params[k] <= lower[k]) mask |= 1u << k;
  return mask;
}

unsigned keep_in_domain(const Feature& A, const Feature& B, Vec4& params) {
  return Parameter_domain::of(A, B).clamp(params);
}

namespace internal {

// The common case of solve_masked, written out: nothing frozen, seeking a minimum, H = S M
// symmetrised and positive definite with every pivot above the singularity threshold. Returns
// false (x untouched) whenever the general path has to decide (shift, singular, non-finite), so
// both give the same answer where this one answers.
bool solve_minimum_pd(const Mat4& M, const Vec4& rhs, int na, int n, double scale, bool symmetric,
                      Vec4& x) {
  double S[4], h[4][4], r[4];
  for (int k = 0; k < 4; ++k) S[k] = k >= na && k < n ? -1.0 : 1.0;
  for (int i = 0; i < 4; ++i) {
    r[i] = S[i] * rhs[i];
    // Where S M is exactly symmetric the mean below is the entry itself: skip it.
    if (symmetric)
      for (int j = 0; j <= i; ++j) h[i][j] = S[i] * M(i, j);
    else
      for (int j = 0; j <= i; ++j) h[i][j] = 0.5 * (S[i] * M(i, j) + S[j] * M(j, i));
  }
  const double tiny = 1e-12 * scale;
  if (n == 4) {
    // Two surfaces, H = [P Q; Q^T R] in 2 x 2 blocks: block LDL^T by the blocks' adjugates,
    // two divisions in series where the Cholesky below has four square roots and four
    // divisions (the step's critical path). Its pivots are P00, det P / P00, S00 and
    // det S / S00, S = R - Q^T P^-1 Q: the Cholesky's, tested against the same threshold.
    const double p00 = h[0][0], p10 = h[1][0], p11 = h[1][1];
    const double q00 = h[2][0], q10 = h[2][1], q01 = h[3][0], q11 = h[3][1];  // Q(i, k) = h[2 + k][i]
    const double det_p = p00 * p11 - p10 * p10;
    if (!(p00 > tiny) || !(det_p > tiny * p00)) return false;
    const double ip = 1.0 / det_p;
    // W = P^-1 Q and y = P^-1 r_top.
    const double w00 = ip * (p11 * q00 - p10 * q10), w10 = ip * (p00 * q10 - p10 * q00);
    const double w01 = ip * (p11 * q01 - p10 * q11), w11 = ip * (p00 * q11 - p10 * q01);
    const double y0 = ip * (p11 * r[0] - p10 * r[1]), y1 = ip * (p00 * r[1] - p10 * r[0]);
    const double s00 = h[2][2] - (q00 * w00 + q10 * w10);
    const double s10 = h[3][2] - (q01 * w00 + q11 * w10);
    const double s11 = h[3][3] - (q01 * w01 + q11 * w11);
    const double det_s = s00 * s11 - s10 * s10;
    if (!(s00 > tiny) || !(det_s > tiny * s00)) return false;
    const double is = 1.0 / det_s;
    const double b0 = r[2] - (q00 * y0 + q10 * y1), b1 = r[3] - (q01 * y0 + q11 * y1);
    Vec4 z;
    z[2] = is * (s11 * b0 - s10 * b1);
    z[3] = is * (s00 * b1 - s10 * b0);
    z[0] = y0 - (w00 * z[2] + w01 * z[3]);
    z[1] = y1 - (w10 * z[2] + w11 * z[3]);
    if (!z.allFinite()) return false;
    x = z;
    return true;
  }
  // Cholesky H = L L^T, L in the lower triangle of h; pivots are L_kk^2.
  double inv[4];
  for (int j = 0; j < 4; ++j) {
    double p = h[j][j];
    for (int k = 0; k < j; ++k) p -= h[j][k] * h[j][k];
    if (!(p > tiny)) return false;
    const double l = std::sqrt(p);
    inv[j] = 1.0 / l;
    for (int i = j + 1; i < 4; ++i) {
      double v = h[i][j];
      for (int k = 0; k < j; ++k) v -= h[i][k] * h[j][k];
      h[i][j] = v * inv[j];
    }
  }
  double y[4];
  for (int i = 0; i < 4; ++i) {
    double v = r[i];
    for (int k = 0; k < i; ++k) v -= h[i][k] * y[k];
    y[i] = v * inv[i];
  }
  Vec4 z;
  for (int i = 3; i >= 0; --i) {
    double v = y[i];
    for (int k = i + 1; k < 4; ++k) v -= h[k][i] * z[k];
    z[i] = v * inv[i];
  }
  if (!z.allFinite()) return false;
  x = z;
  return true;
}

}  // namespace internal

namespace {

bool solve_masked(const Mat4& M, const Vec4& rhs, int n, unsigned frozen, const Solve_mode& mode,
                  Vec4& x) {
  if (mode.minimum && !mode.damped && frozen == 0 && mode.scale > 0.0 &&
      internal::solve_minimum_pd(M, rhs, mode.na, n, mode.scale, mode.symmetric, x))
    return true;
  Mat4 A = M;
  Vec4 r = rhs;
  for (int k = 0; k < 4; ++k) {
    if (!(frozen & (1u << k))) continue;
    A.row(k).setZero();
    A.col(k).setZero();
    A(k, k) = 1.0;
    r[k] = 0.0;
  }
  const double scale = mode.scale > 0.0 ? mode.scale : A.cwiseAbs().maxCoeff();
  if (mode.damped) {
    // x = sum_i s_i / (s_i^2 + lambda^2) v_i (u_i . r): Newton along well-determined directions,
    // nothing along the null space.
    const Eigen::JacobiSVD<Mat4> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const double lambda = 1e-4 * scale;
    const Vec4 sv = svd.singularValues();
    const Vec4 coeff = svd.matrixU().transpose() * r;
    Vec4 scaled;
    for (int i = 0; i < 4; ++i) scaled[i] = sv[i] / (sv[i] * sv[i] + lambda * lambda) * coeff[i];
    x = svd.matrixV() * scaled;
    if (!x.allFinite()) {
      x.setZero();
      return false;
    }
    return true;
  }
  if (mode.minimum) {
    // H = S A is the Hessian of |d|^2 / 2 (symmetric up to rounding). A frozen row is the
    // identity padding, not one of B's rows. Negated, it makes H indefinite, and the shift
    // that follows about doubles the free block: half steps, linear convergence, which cost
    // the tracker all its corrections on most steps of edge pairs held at an end of B's
    // parameter. Newton at rest (the global solver's polish) keeps that damping
    // (damp_when_b_held): it is what settles its polish on a pole held on a bound (a sphere's
    // pole over a plane: 4.5e-10 from the pole with it, 1.1e-6 without). Damping made for
    // poles at rest would let it go.
    for (int k = mode.na; k < n; ++k) {
      if (!mode.damp_when_b_held && (frozen & (1u << k))) continue;
      A.row(k) = -A.row(k);
      r[k] = -r[k];
    }
    A = (0.5 * (A + A.transpose())).eval();
    Eigen::LLT<Mat4> llt(A);
    if (llt.info() != Eigen::Success) {
      // Not a minimum here: shift H to positive definite.
      if (mode.scaled_shift) {
        // Jacobi-scaled, so a direction of small curvature (near a pole) keeps its Newton step
        // instead of being swamped by the stiff ones. Padding rows are identity and stay so.
        Vec4 D;
        for (int k = 0; k < 4; ++k) D[k] = std::sqrt(std::max(std::abs(A(k, k)), 1e-12 * scale));
        for (int k = n; k < 4; ++k) D[k] = 1.0;
        const Mat4 Hs = D.cwiseInverse().asDiagonal() * A * D.cwiseInverse().asDiagonal();
        const Eigen::SelfAdjointEigenSolver<Mat4> eig(Hs);
        const double shift = std::max(0.0, -eig.eigenvalues().minCoeff()) + 1e-2;
        A.diagonal().array() += shift * D.cwiseAbs2().array();
      } else {
        // Uniform, by a margin relative to the active block (the identity padding must not
        // make a vanishing M look regular).
        const Eigen::SelfAdjointEigenSolver<Mat4> eig(A);
        const double top = A.topLeftCorner(n, n).cwiseAbs().maxCoeff();
        A.diagonal().array() += std::max(0.0, -eig.eigenvalues().minCoeff()) + 1e-2 * top;
      }
      llt.compute(A);
    }
    // Pivots of H = L L^T are the squared diagonal of L.
    const Vec4 diag = llt.matrixLLT().diagonal().cwiseAbs2();
    if (llt.info() != Eigen::Success || !(diag.minCoeff() > 1e-12 * scale)) {
      x.setZero();
      return false;
    }
    x = llt.solve(r);
    if (!x.allFinite()) {
      x.setZero();
      return false;
    }
    return true;
  }
  const Eigen::PartialPivLU<Mat4> lu(A);
  const Vec4 diag = lu.matrixLU().diagonal().cwiseAbs();
  if (!(diag.minCoeff() > 1e-12 * scale)) {
    x.setZero();
    return false;
  }
  x = lu.solve(r);
  if (!x.allFinite()) {
    x.setZero();
    return false;
  }
  return true;
}

}  // namespace

Solve_mode solve_mode_for(const Pair_system& s, bool minimum) {
  Solve_mode mode;
  mode.minimum = minimum;
  mode.na = s.na;
  for (int k = 0; k < s.size(); ++k) mode.scale = std::max(mode.scale, s.tangent_length2[k]);
  mode.symmetric = s.symmetric_hessian;
  return mode;
}

bool solve_constrained(const Mat4& M, const Vec4& rhs, int n, unsigned on_bound,
                       unsigned lower_side, Vec4& x, const Solve_mode& mode, unsigned frozen) {
  frozen &= on_bound;
  for (int pass = 0; pass <= n; ++pass) {
    if (!solve_masked(M, rhs, n, frozen, mode, x)) return false;
    unsigned push_out = 0;
    for (int k = 0; k < n; ++k) {
      if (!(on_bound & (1u << k)) || (frozen & (1u << k))) continue;
      const bool lower = lower_side & (1u << k);
      if ((lower && x[k] < 0.0) || (!lower && x[k] > 0.0)) push_out |= 1u << k;
    }
    if (!push_out) return true;
    frozen |= push_out;
  }
  return true;
}

Newton_result solve_pair_at_rest(const Posed_feature& A, const Posed_feature& B,
                                 const Vec4& start, const Newton_options& options) {
  Newton_result r;
  r.params = start;
  const Parameter_domain domain = Parameter_domain::of(*A.feature, *B.feature);
  unsigned on_bound = domain.clamp(r.params);
  const Posed_feature a{A.feature, A.pose, nullptr}, b{B.feature, B.pose, nullptr};
  Pair_system s;
  const int n = A.feature->dimension() + B.feature->dimension();
  if (n == 0) {
    r.converged = true;
    return r;
  }
  const Vec4 max_step = 0.25 * (domain.upper - domain.lower);
  for (r.iterations = 0; r.iterations < options.max_iterations; ++r.iterations) {
    build_pair_system(a, b, r.params, s, false);
    const Vec4 e = normalised_projection_errors(s);
    // Converged: errors at rounding level, or every free parameter is pinned by a bound.
    bool done = true;
    for (int k = 0; k < n; ++k)
      if (std::abs(e[k]) > options.tolerance && !(on_bound & (1u << k))) done = false;
    if (done && r.iterations > 0) {
      r.converged = true;
      break;
    }
    Vec4 step;
    if (!solve_constrained(s.M, -s.phi, n, on_bound, domain.lower_mask(r.params), step,
                           solve_mode_for(s)))
      break;
    double scale = 1.0;
    for (int k = 0; k < n; ++k)
      if (std::abs(step[k]) > max_step[k]) scale = std::min(scale, max_step[k] / std::abs(step[k]));
    const Vec4 before = r.params;
    r.params += scale * step;
    on_bound = domain.clamp(r.params);
    if ((r.params - before).cwiseAbs().maxCoeff() == 0.0) {
      r.converged = true;
      break;
    }
  }
  return r;
}

}  // namespace extremal
