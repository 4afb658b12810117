#include "algorithms/body_pair/internal/Pair_seeding.h"

#include <cmath>
#include <limits>

#include "algorithms/body_pair/internal/Body_pair_support.h"
#include "algorithms/body_pair/internal/Tuning.h"

namespace extremal::internal {

namespace {

// Sampled closest pair of two features, polished by Newton at rest (pairs the global solver
// has no element for: mesh edges).
Vec4 sampled_seed(const Feature& A, const Rigid_pose_3& X_WA, const Feature& B,
                  const Rigid_pose_3& X_WB, int n = k_sampled_seed_grid) {
  auto sample = [n](const Feature& f, int i, int j, double* q) {
    for (int k = 0; k < f.dimension(); ++k) {
      const int idx = k == 0 ? i : j;
      q[k] = f.lower(k) + (f.upper(k) - f.lower(k)) * (idx + 0.5) / n;
    }
  };
  const int ia = A.dimension() >= 1 ? n : 1, ja = A.dimension() == 2 ? n : 1;
  const int ib = B.dimension() >= 1 ? n : 1, jb = B.dimension() == 2 ? n : 1;
  double best = std::numeric_limits<double>::infinity();
  Vec4 start = Vec4::Zero();
  Feature_point fa, fb;
  for (int i = 0; i < ia; ++i)
    for (int j = 0; j < ja; ++j) {
      double qa[2] = {0, 0};
      sample(A, i, j, qa);
      evaluate_feature(A, X_WA, qa, fa, 0);
      for (int k = 0; k < ib; ++k)
        for (int l = 0; l < jb; ++l) {
          double qb[2] = {0, 0};
          sample(B, k, l, qb);
          evaluate_feature(B, X_WB, qb, fb, 0);
          const double d = (fa.p - fb.p).squaredNorm();
          if (d < best) {
            best = d;
            for (int c = 0; c < A.dimension(); ++c) start[c] = qa[c];
            for (int c = 0; c < B.dimension(); ++c) start[A.dimension() + c] = qb[c];
          }
        }
    }
  return solve_pair_at_rest({&A, &X_WA, nullptr}, {&B, &X_WB, nullptr}, start).params;
}


}  // namespace

void Pair_seeding::prefer_central(int pa, int pb, const Rigid_pose_3& X_WA,
                                       const Rigid_pose_3& X_WB, Vec4& params) const {
  // A witness on a patch side of a pair of surfaces may be one of a continuum of equal pairs
  // (flat on flat): a start inside, from the closest of a few interior samples, tracks better
  // (beside an edge the sign of the distance says nothing). Kept only when it is as close.
  const Feature& A = m_context.model_a->primitives()[pa].feature;
  const Feature& B = m_context.model_b->primitives()[pb].feature;
  if (A.dimension() != 2 || B.dimension() != 2) return;
  const Parameter_domain domain = Parameter_domain::of(A, B);
  Vec4 probe = params;
  if (!(domain.clamp(probe) & ~domain.closed)) return;
  Pair_system s;
  build_pair_system({&A, &X_WA, nullptr}, {&B, &X_WB, nullptr}, params, s, false);
  const double d0 = s.distance;
  // Interior samples of each side projected on the other: the closest, the most central
  // among ties.
  Vec4 inner = params;
  double d1 = std::numeric_limits<double>::infinity(), c1 = d1;
  constexpr int n = k_central_seed_grid;
  for (int side = 0; side < 2; ++side) {
    const Feature& F = side == 0 ? A : B;
    const Feature& G = side == 0 ? B : A;
    const Rigid_pose_3& XF = side == 0 ? X_WA : X_WB;
    const Rigid_pose_3& XG = side == 0 ? X_WB : X_WA;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const double q[2] = {F.lower(0) + (F.upper(0) - F.lower(0)) * (i + 0.5) / n,
                             F.lower(1) + (F.upper(1) - F.lower(1)) * (j + 0.5) / n};
        Surface_point sp;
        F.surface()->evaluate(q[0], q[1], sp, 0);
        const Feature point = Feature::point(sp.p);
        const Vec4 start(0.5 * (G.lower(0) + G.upper(0)), 0.5 * (G.lower(1) + G.upper(1)), 0, 0);
        const Newton_result nr = solve_pair_at_rest({&G, &XG, nullptr}, {&point, &XF, nullptr}, start);
        Vec4 cand;
        if (side == 0) cand << q[0], q[1], nr.params[0], nr.params[1];
        else cand << nr.params[0], nr.params[1], q[0], q[1];
        build_pair_system({&A, &X_WA, nullptr}, {&B, &X_WB, nullptr}, cand, s, false);
        const double d = s.distance;
        const double c = off_centre(A, cand.data()) + off_centre(B, cand.data() + 2);
        const bool tie = std::abs(d - d1) <= k_distance_tie * (1.0 + d1);
        if ((!tie && d < d1) || (tie && c < c1)) d1 = d, c1 = c, inner = cand;
      }
  }
  if (d1 <= d0 + k_distance_tie * (1.0 + d0) &&
      c1 < off_centre(A, params.data()) + off_centre(B, params.data() + 2))
    params = inner;
}

double Pair_seeding::seed_pair(int pa, int pb, const Rigid_pose_3& X_WA,
                                    const Rigid_pose_3& X_WB) {
  const Primitive& A = m_context.model_a->primitives()[pa];
  const Primitive& B = m_context.model_b->primitives()[pb];
  Vec4 params = Vec4::Zero();
  if (closed_form_pair(A, B)) {
    m_live.add(pa, pb, params);
    return -HUGE_VAL;
  }
  double lower = -HUGE_VAL;
  if (A.global_element >= 0 && B.global_element >= 0) {
    const Distance_result g = extremal_distance_between(
        m_context.model_a->hierarchy(), X_WA, A.global_element, m_context.model_b->hierarchy(), X_WB,
        B.global_element, m_context.options.seeding, m_solver.workspace());
    if (g.is_certified()) lower = g.lower_bound;
    if (g.element_a < 0 || g.element_b < 0) return lower;  // nothing of the pair on the bodies
    params_from_global(A, g.params_a, params.data());
    params_from_global(B, g.params_b, params.data() + A.feature.dimension());
  } else {
    params = sampled_seed(A.feature, X_WA, B.feature, X_WB);
  }
  prefer_central(pa, pb, X_WA, X_WB, params);
  m_live.add(pa, pb, params);
  ++m_seeds;
  return lower;
}

bool Pair_seeding::seed_from(const Distance_result& g, const Rigid_pose_3& X_WA,
                                  const Rigid_pose_3& X_WB, double tracked) {
  if (g.element_a < 0 || g.element_b < 0) return false;
  if (!(g.upper_bound < tracked - std::max(g.tolerance_used, g.upper_bound - g.lower_bound)))
    return false;
  const int pa = m_context.model_a->primitive_of(g.kind_a, g.element_a);
  const int pb = m_context.model_b->primitive_of(g.kind_b, g.element_b);
  if (pa < 0 || pb < 0) return false;
  Vec4 params = Vec4::Zero();
  const Primitive& A = m_context.model_a->primitives()[pa];
  params_from_global(A, g.params_a, params.data());
  params_from_global(m_context.model_b->primitives()[pb], g.params_b, params.data() + A.feature.dimension());
  prefer_central(pa, pb, X_WA, X_WB, params);
  if (g.distance > m_context.options.contact_tolerance)
    mark_seeded_apart(m_live[place(pa, pb, params, X_WA, X_WB)]);
  else
    place(pa, pb, params, X_WA, X_WB);
  return true;
}

int Pair_seeding::place(int pa, int pb, const Vec4& params, const Rigid_pose_3& X_WA,
                        const Rigid_pose_3& X_WB) {
  const int moved = m_live.move(pa, pb, params);
  if (moved >= 0) return moved;
  const int slot = m_live.add(pa, pb, params);
  m_candidates->track(pa, pb, X_WA.inverse() * X_WB);
  return slot;
}

void Pair_seeding::add_inside(int pa, int pb, const Vec4& params, const Rigid_pose_3& X_WA,
                              const Rigid_pose_3& X_WB) {
  m_live[place(pa, pb, params, X_WA, X_WB)].provenance = Provenance::Through_contact;  // (its side)
  ++m_seeds;
}

}  // namespace extremal::internal
