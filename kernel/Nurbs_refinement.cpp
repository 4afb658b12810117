#include "kernel/Nurbs_refinement.h"

#include <algorithm>

#include "kernel/Error.h"
#include "kernel/internal/Bspline_basis.h"
#include "kernel/internal/Knot_vector.h"

namespace extremal {

namespace {

using Hom = Eigen::Vector4d;
using Hom_vector = Nurbs_curve_3::Homogeneous;

void check_insertion(const std::vector<double>& knots, int n, int p, double t, int times) {
  EXTREMAL_PRECONDITION_MSG(t >= knots[p] && t <= knots[n],
                            "knot " << t << " outside the domain [" << knots[p] << ", "
                                    << knots[n] << "]");
  EXTREMAL_PRECONDITION(times >= 0);
  const int s = internal::knot_multiplicity(knots, t);
  EXTREMAL_PRECONDITION_MSG(s + times <= p + 1 && (s + times <= p || t == knots[p] ||
                                                   t == knots[n]),
                            "inserting knot " << t << " " << times
                                              << " times exceeds the allowed multiplicity");
}

// Boehm's algorithm (The NURBS Book A5.1) on a row of n homogeneous points: inserts t
// `times` times. Needs a span k <= n - 1 with knots[k] <= t; at an unclamped right end there is
// none, so that case runs on the reversed row.
void insert_row(const std::vector<double>& knots, int p, const Hom* in, int n, double t,
                int times, std::vector<double>& knots_out, Hom* out) {
  if (times == 0) {
    knots_out = knots;
    std::copy(in, in + n, out);
    return;
  }
  int k = static_cast<int>(std::upper_bound(knots.begin(), knots.end(), t) - knots.begin()) - 1;
  if (k > n - 1) {
    std::vector<double> reversed(knots.rbegin(), knots.rend());
    for (double& x : reversed) x = -x;
    Hom_vector in_rev(in, in + n);
    std::reverse(in_rev.begin(), in_rev.end());
    Hom_vector out_rev(n + times);
    std::vector<double> knots_rev;
    insert_row(reversed, p, in_rev.data(), n, -t, times, knots_rev, out_rev.data());
    knots_out.assign(knots_rev.rbegin(), knots_rev.rend());
    for (double& x : knots_out) x = -x;
    std::reverse_copy(out_rev.begin(), out_rev.end(), out);
    return;
  }
  const int s = internal::knot_multiplicity(knots, t);
  knots_out.resize(knots.size() + times);
  for (int i = 0; i <= k; ++i) knots_out[i] = knots[i];
  for (int i = 1; i <= times; ++i) knots_out[k + i] = t;
  for (std::size_t i = k + 1; i < knots.size(); ++i) knots_out[i + times] = knots[i];
  for (int i = 0; i <= k - p; ++i) out[i] = in[i];
  for (int i = k - s; i < n; ++i) out[i + times] = in[i];
  Hom R[k_max_degree + 1];
  for (int i = 0; i <= p - s; ++i) R[i] = in[k - p + i];
  int L = k - p;
  for (int j = 1; j <= times; ++j) {
    L = k - p + j;
    for (int i = 0; i <= p - j - s; ++i) {
      const double alpha = (t - knots[L + i]) / (knots[i + k + 1] - knots[L + i]);
      R[i] = alpha * R[i + 1] + (1.0 - alpha) * R[i];
    }
    out[L] = R[0];
    // At a domain end the multiplicity may reach p + 1 (s + times = p + 1), beyond A5.1's
    // s + times <= p: the last step then only duplicates R[0], and R[p - j - s] would be R[-1].
    if (p - j - s >= 0) out[k + times - j - s] = R[p - j - s];
  }
  for (int i = L + 1; i < k - s; ++i) out[i] = R[i - L];
}

}  // namespace

Nurbs_curve_3 insert_knot(const Nurbs_curve_3& c, double t, int times) {
  const int n = c.number_of_poles(), p = c.degree();
  check_insertion(c.knots(), n, p, t, times);
  std::vector<double> knots;
  Hom_vector out(n + times);
  insert_row(c.knots(), p, c.homogeneous_poles().data(), n, t, times, knots, out.data());
  return Nurbs_curve_3::from_homogeneous(p, out, std::move(knots));
}

Nurbs_surface_3 insert_knot(const Nurbs_surface_3& s, Parameter_direction dir, double t,
                            int times) {
  const int nu = s.number_of_poles_u(), nv = s.number_of_poles_v();
  const auto& hom = s.homogeneous_poles();
  std::vector<double> knots;
  if (dir == Parameter_direction::U) {
    const int p = s.degree_u();
    check_insertion(s.knots_u(), nu, p, t, times);
    Hom_vector column(nu), refined(nu + times), out(static_cast<std::size_t>(nu + times) * nv);
    for (int j = 0; j < nv; ++j) {
      for (int i = 0; i < nu; ++i) column[i] = hom[static_cast<std::size_t>(i) * nv + j];
      insert_row(s.knots_u(), p, column.data(), nu, t, times, knots, refined.data());
      for (int i = 0; i < nu + times; ++i) out[static_cast<std::size_t>(i) * nv + j] = refined[i];
    }
    Nurbs_surface_3 r = Nurbs_surface_3::from_homogeneous(s.degree_u(), s.degree_v(), nu + times,
                                                          nv, out, knots, s.knots_v());
    r.set_outward_sign(s.outward_sign());
    return r;
  }
  const int q = s.degree_v();
  check_insertion(s.knots_v(), nv, q, t, times);
  Hom_vector out(static_cast<std::size_t>(nu) * (nv + times));
  for (int i = 0; i < nu; ++i)
    insert_row(s.knots_v(), q, hom.data() + static_cast<std::size_t>(i) * nv, nv, t, times, knots,
               out.data() + static_cast<std::size_t>(i) * (nv + times));
  Nurbs_surface_3 r = Nurbs_surface_3::from_homogeneous(s.degree_u(), s.degree_v(), nu,
                                                        nv + times, out, s.knots_u(), knots);
  r.set_outward_sign(s.outward_sign());
  return r;
}

namespace {

// Distinct knot values inside the domain, ends included.
std::vector<double> domain_breakpoints(const std::vector<double>& knots, int n, int p) {
  std::vector<double> b;
  for (int i = p; i <= n; ++i)
    if (b.empty() || knots[i] != b.back()) b.push_back(knots[i]);
  return b;
}

}  // namespace

std::vector<Nurbs_curve_3> extract_bezier(const Nurbs_curve_3& c) {
  const int p = c.degree();
  const auto breaks = domain_breakpoints(c.knots(), c.number_of_poles(), p);
  Nurbs_curve_3 r = c;
  for (double t : breaks) {
    const int s = internal::knot_multiplicity(r.knots(), t);
    if (s < p) r = insert_knot(r, t, p - s);
  }
  std::vector<Nurbs_curve_3> pieces;
  const auto& K = r.knots();
  const auto& H = r.homogeneous_poles();
  for (std::size_t b = 0; b + 1 < breaks.size(); ++b) {
    // Last index of breaks[b] in K: the span [breaks[b], breaks[b+1]).
    const int k = static_cast<int>(std::upper_bound(K.begin(), K.end(), breaks[b]) - K.begin()) - 1;
    Hom_vector seg(H.begin() + (k - p), H.begin() + (k + 1));
    std::vector<double> knots(p + 1, breaks[b]);
    knots.insert(knots.end(), p + 1, breaks[b + 1]);
    pieces.push_back(Nurbs_curve_3::from_homogeneous(p, seg, std::move(knots)));
  }
  return pieces;
}

Bezier_patches extract_bezier(const Nurbs_surface_3& s) {
  const int p = s.degree_u(), q = s.degree_v();
  const auto bu = domain_breakpoints(s.knots_u(), s.number_of_poles_u(), p);
  const auto bv = domain_breakpoints(s.knots_v(), s.number_of_poles_v(), q);
  Nurbs_surface_3 r = s;
  for (double t : bu) {
    const int m = internal::knot_multiplicity(r.knots_u(), t);
    if (m < p) r = insert_knot(r, Parameter_direction::U, t, p - m);
  }
  for (double t : bv) {
    const int m = internal::knot_multiplicity(r.knots_v(), t);
    if (m < q) r = insert_knot(r, Parameter_direction::V, t, q - m);
  }
  const auto& KU = r.knots_u();
  const auto& KV = r.knots_v();
  const auto& H = r.homogeneous_poles();
  const int nv = r.number_of_poles_v();
  Bezier_patches out;
  out.count_u = static_cast<int>(bu.size()) - 1;
  out.count_v = static_cast<int>(bv.size()) - 1;
  for (int a = 0; a < out.count_u; ++a) {
    const int ku = static_cast<int>(std::upper_bound(KU.begin(), KU.end(), bu[a]) - KU.begin()) - 1;
    for (int b = 0; b < out.count_v; ++b) {
      const int kv =
          static_cast<int>(std::upper_bound(KV.begin(), KV.end(), bv[b]) - KV.begin()) - 1;
      Hom_vector patch;
      patch.reserve(static_cast<std::size_t>(p + 1) * (q + 1));
      for (int i = ku - p; i <= ku; ++i)
        for (int j = kv - q; j <= kv; ++j) patch.push_back(H[static_cast<std::size_t>(i) * nv + j]);
      std::vector<double> knots_u(p + 1, bu[a]);
      knots_u.insert(knots_u.end(), p + 1, bu[a + 1]);
      std::vector<double> knots_v(q + 1, bv[b]);
      knots_v.insert(knots_v.end(), q + 1, bv[b + 1]);
      Nurbs_surface_3 piece = Nurbs_surface_3::from_homogeneous(p, q, p + 1, q + 1, patch,
                                                                std::move(knots_u),
                                                                std::move(knots_v));
      piece.set_outward_sign(s.outward_sign());
      out.patches.push_back(std::move(piece));
    }
  }
  return out;
}

std::pair<Nurbs_curve_3, Nurbs_curve_3> split(const Nurbs_curve_3& c, double t) {
  EXTREMAL_PRECONDITION_MSG(t > c.domain_min() && t < c.domain_max(),
                            "split parameter " << t << " not strictly inside the domain");
  const int p = c.degree();
  const int s = internal::knot_multiplicity(c.knots(), t);
  const Nurbs_curve_3 r = s < p ? insert_knot(c, t, p - s) : c;
  const auto& K = r.knots();
  const auto& H = r.homogeneous_poles();
  // Last index of t; the curve passes through pole k - p there.
  const int k = static_cast<int>(std::upper_bound(K.begin(), K.end(), t) - K.begin()) - 1;
  std::vector<double> left_knots(K.begin(), K.begin() + k + 1);
  left_knots.push_back(t);
  Hom_vector left(H.begin(), H.begin() + (k - p + 1));
  std::vector<double> right_knots(1, t);
  right_knots.insert(right_knots.end(), K.begin() + (k - p + 1), K.end());
  Hom_vector right(H.begin() + (k - p), H.end());
  return {Nurbs_curve_3::from_homogeneous(p, left, std::move(left_knots)),
          Nurbs_curve_3::from_homogeneous(p, right, std::move(right_knots))};
}

std::pair<Nurbs_surface_3, Nurbs_surface_3> split(const Nurbs_surface_3& s,
                                                  Parameter_direction dir, double t) {
  const bool in_u = dir == Parameter_direction::U;
  const double lo = in_u ? s.u_min() : s.v_min(), hi = in_u ? s.u_max() : s.v_max();
  EXTREMAL_PRECONDITION_MSG(t > lo && t < hi,
                            "split parameter " << t << " not strictly inside the domain");
  const int p = in_u ? s.degree_u() : s.degree_v();
  const int m = internal::knot_multiplicity(in_u ? s.knots_u() : s.knots_v(), t);
  const Nurbs_surface_3 r = m < p ? insert_knot(s, dir, t, p - m) : s;
  const auto& K = in_u ? r.knots_u() : r.knots_v();
  const auto& H = r.homogeneous_poles();
  const int nu = r.number_of_poles_u(), nv = r.number_of_poles_v();
  const int k = static_cast<int>(std::upper_bound(K.begin(), K.end(), t) - K.begin()) - 1;
  const int n_left = k - p + 1;
  const int n_dir = in_u ? nu : nv;
  const int n_right = n_dir - (k - p);
  std::vector<double> left_knots(K.begin(), K.begin() + k + 1);
  left_knots.push_back(t);
  std::vector<double> right_knots(1, t);
  right_knots.insert(right_knots.end(), K.begin() + (k - p + 1), K.end());

  auto pick = [&](int first, int count) {
    Hom_vector out;
    if (in_u) {
      out.assign(H.begin() + static_cast<std::ptrdiff_t>(first) * nv,
                 H.begin() + static_cast<std::ptrdiff_t>(first + count) * nv);
    } else {
      out.reserve(static_cast<std::size_t>(nu) * count);
      for (int i = 0; i < nu; ++i)
        for (int j = first; j < first + count; ++j)
          out.push_back(H[static_cast<std::size_t>(i) * nv + j]);
    }
    return out;
  };
  const Hom_vector left = pick(0, n_left), right = pick(k - p, n_right);
  auto make = [&](const Hom_vector& poles, int count, std::vector<double> knots) {
    Nurbs_surface_3 piece =
        in_u ? Nurbs_surface_3::from_homogeneous(r.degree_u(), r.degree_v(), count, nv, poles,
                                                 std::move(knots), r.knots_v())
             : Nurbs_surface_3::from_homogeneous(r.degree_u(), r.degree_v(), nu, count, poles,
                                                 r.knots_u(), std::move(knots));
    piece.set_outward_sign(s.outward_sign());
    return piece;
  };
  return {make(left, n_left, std::move(left_knots)), make(right, n_right, std::move(right_knots))};
}

}  // namespace extremal
