#include "algorithms/body_pair/internal/Depth_monitor.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "algorithms/body_pair/internal/Body_pair_support.h"
#include "algorithms/body_pair/internal/Tuning.h"
#include "algorithms/pair/Pair_geometry.h"

namespace extremal::internal {

void Depth_monitor::centre_depth_seed(int& pa, int& pb, const Rigid_pose_3& X_WA,
                                          const Rigid_pose_3& X_WB, const Vec3& n, double depth,
                                          Vec4& params) const {
  // The hull's witnesses of a continuum of equal penetration pairs (a shaft in a bore, flat on
  // flat, two cylinders side by side) may sit on the faces' rims, even on a cap beside the
  // side that holds the continuum, where a tracker's first step leaves it. Points of a face
  // at a witness whose outward normal is the depth's direction, moved by the depth, that lie
  // on a face at the other witness (with the opposite normal) are pairs of the same depth:
  // the most central is kept. Loose tolerances: a depth whose budget ran out is a little off,
  // and this is a seed.
  // A witness on a B-rep edge (the hulls' support at a box's rim, of a peg's side against its
  // side face: the generator's end at the top edge) starts from the faces at it instead.
  const Tracking_model& MA = *m_context.model_a;
  const Tracking_model& MB = *m_context.model_b;
  const Primitive& PA = MA.primitives()[pa];
  const Primitive& PB = MB.primitives()[pb];
  const auto face_or_edge = [](const Primitive& P) {
    return P.is_surface() || P.kind == Primitive_kind::Edge;
  };
  if (!face_or_edge(PA) || !face_or_edge(PB) || (!PA.is_surface() && !PB.is_surface())) return;
  const bool both_faces = PA.is_surface() && PB.is_surface();
  const int nb = PA.feature.dimension();  // (B's parameters follow A's)
  Feature_point wa, wb;
  evaluate_feature(PA.feature, X_WA, params.data(), wa, 0);
  evaluate_feature(PB.feature, X_WB, params.data() + nb, wb, 0);
  const double tol = k_depth_seed_tolerance * std::max({1.0, std::abs(depth), box_diagonal(MA.box()),
                                      box_diagonal(MB.box())});
  // The faces whose boxes hold a witness (its own, and those across the rim it sits on).
  auto faces_at = [tol](const Tracking_model& M, const Rigid_pose_3& X, const Vec3& w, int own,
                        std::vector<int>& out) {
    out.clear();
    if (M.primitives()[own].is_surface()) out.push_back(own);
    const Bbox_3 b = to_point(X.inverse().apply_point(w)).bbox();
    for (int p = 0; p < static_cast<int>(M.primitives().size()); ++p) {
      const Primitive& P = M.primitives()[p];
      if (p != own && P.is_surface() && CGAL::do_overlap(b, inflate(P.box, tol))) out.push_back(p);
    }
  };
  std::vector<int> faces_a, faces_b;
  faces_at(MA, X_WA, wa.p, pa, faces_a);
  faces_at(MB, X_WB, wb.p, pb, faces_b);
  constexpr double k_aligned = 1.0 - k_depth_seed_aligned;
  constexpr int n_samples = k_depth_seed_grid;
  const Rigid_pose_3 identity;
  double best = both_faces ? off_centre(PA.feature, params.data()) +
                                 off_centre(PB.feature, params.data() + nb)
                           : HUGE_VAL;
  int best_a = pa, best_b = pb;
  Vec4 chosen = params;
  for (int fa : faces_a)
    for (int fb : faces_b)
      for (int side = 0; side < 2; ++side) {
        const Feature& A = MA.primitives()[fa].feature;
        const Feature& B = MB.primitives()[fb].feature;
        const Feature& F = side == 0 ? A : B;
        const Feature& G = side == 0 ? B : A;
        const Rigid_pose_3& XF = side == 0 ? X_WA : X_WB;
        const Rigid_pose_3& XG = side == 0 ? X_WB : X_WA;
        const Vec3 dir = side == 0 ? n : Vec3(-n);  // F's outward normal at its support points
        const Vec3 shift = side == 0 ? Vec3(depth * n) : Vec3(-depth * n);
        // Parameter lines through the witness where F is its face (a cylinder's generator),
        // and Newton's projection on G from the witness where G is its face.
        const bool own_f = side == 0 ? fa == pa : fb == pb;
        const bool own_g = side == 0 ? fb == pb : fa == pa;
        const double* f0 = params.data() + (side == 0 ? 0 : nb);
        const double* w0 = params.data() + (side == 0 ? nb : 0);
        const Vec4 g0 = own_g ? Vec4(w0[0], w0[1], 0.0, 0.0)
                              : Vec4(0.5 * (G.lower(0) + G.upper(0)), 0.5 * (G.lower(1) + G.upper(1)),
                                     0.0, 0.0);
        auto try_point = [&](const double* q) {
          Feature_point fp;
          evaluate_feature(F, XF, q, fp, 1);
          if (!(F.outward_sign() * unit_normal(fp.d[0].cross(fp.d[1])).dot(dir) >= k_aligned))
            return;
          const Vec3 x = fp.p + shift;
          const Feature target = Feature::point(x);
          const Newton_result r =
              solve_pair_at_rest({&G, &XG, nullptr}, {&target, &identity, nullptr}, g0);
          Feature_point gp;
          evaluate_feature(G, XG, r.params.data(), gp, 1);
          if (!((gp.p - x).norm() <= tol) ||
              !(-G.outward_sign() * unit_normal(gp.d[0].cross(gp.d[1])).dot(dir) >= k_aligned))
            return;
          Vec4 cand;
          if (side == 0) cand << q[0], q[1], r.params[0], r.params[1];
          else cand << r.params[0], r.params[1], q[0], q[1];
          if (!MA.contains(fa, cand.data()) || !MB.contains(fb, cand.data() + 2)) return;
          const double c = off_centre(A, cand.data()) + off_centre(B, cand.data() + 2);
          if (c < best) best = c, chosen = cand, best_a = fa, best_b = fb;
        };
        for (int i = 0; i < n_samples; ++i) {
          const double u = F.lower(0) + (F.upper(0) - F.lower(0)) * (i + 0.5) / n_samples;
          for (int j = 0; j < n_samples; ++j) {
            const double v = F.lower(1) + (F.upper(1) - F.lower(1)) * (j + 0.5) / n_samples;
            const double grid[2] = {u, v}, along_v[2] = {f0[0], v}, along_u[2] = {u, f0[1]};
            try_point(grid);
            if (own_f && i == 0) try_point(along_v);
            if (own_f && j == 0) try_point(along_u);
          }
        }
      }
  pa = best_a;
  pb = best_b;
  params = chosen;
}

template <class Result>
void Depth_monitor::keep_solved(const Result& r, double sign) {
  Solved& s = m_solved;
  s.step = m_context.now.steps;
  s.distance = sign * r.distance;
  s.lower_bound = -HUGE_VAL;
  s.point_a = r.point_a;
  s.point_b = r.point_b;
  s.normal = sign * r.normal;
  s.pa = r.element_a >= 0 ? m_context.model_a->primitive_of(r.kind_a, r.element_a) : -1;
  s.pb = r.element_b >= 0 ? m_context.model_b->primitive_of(r.kind_b, r.element_b) : -1;
  s.params.setZero();
  if (s.pa >= 0 && s.pb >= 0) {
    const Primitive& A = m_context.model_a->primitives()[s.pa];
    params_from_global(A, r.params_a, s.params.data());
    params_from_global(m_context.model_b->primitives()[s.pb], r.params_b,
                       s.params.data() + A.feature.dimension());
  }
}

bool Depth_monitor::seed_overlap(const Distance_result& g, const Rigid_pose_3& X_WA,
                                     const Rigid_pose_3& X_WB, bool local_seeds_failed,
                                     double deeper, const Overlap_test* known) {
  keep_solved(g);
  const Distance_hierarchy& HA = m_context.model_a->hierarchy();
  const Distance_hierarchy& HB = m_context.model_b->hierarchy();
  const Overlap_test overlap =
      known != nullptr ? *known : overlap_of(g, HA, X_WA, m_context.kind.closed(0), HB, X_WB, m_context.kind.closed(1));
  // g's bound is on the surfaces' distance: the bodies' only where neither holds the other.
  if (overlap.kind == Overlap_kind::None && !overlap.unknown) {
    m_solved.lower_bound = g.lower_bound;
    m_outside = {true, m_context.now.relative, std::max(g.lower_bound, 0.0)};
  }
  if (overlap.kind == Overlap_kind::None) return false;
  // Where the surfaces meet, the hulls' depth is the bodies' own when both are convex, or
  // when each witness lies inside the other body (two cylinders side by side); not so for a
  // nut on a bolt, whose hulls overlap by the bolt's length with the bolt's end outside the
  // nut. There the trackers seeded at the common points find the local pair first.
  const bool meet = overlap.kind == Overlap_kind::Surfaces_meet;
  if (meet && !m_context.convex() && !local_seeds_failed) return false;
  if (!meet) {
    // One inside the other: at least as deep as the gap between the surfaces (the answer
    // should no depth be found), exactly so for a point, whose depth is its distance from the
    // surface.
    keep_solved(g, -1.0);
    if (m_context.model_a->body().is_point || m_context.model_b->body().is_point) {
      const double tol = std::max(m_context.options.global.absolute_tolerance,
                                  m_context.options.global.relative_tolerance * g.distance);
      // (Any witness shallower than the tracked depth shows that depth stale, certified or
      // not: it is seeded. Test Contact.APointRisingInACylinderReadsItsDepth.)
      if (!(-g.distance > deeper + tol) || m_solved.pa < 0 || m_solved.pb < 0)
        return false;
      m_seeding.add_inside(m_solved.pa, m_solved.pb, m_solved.params, X_WA, X_WB);
      return true;
    }
  }
  // Otherwise the hulls' depth (as `extremal distance --signed` reports it). Against a
  // tracked depth, only whether a pair is shallower than it matters: a coarse search, whose
  // certified bound decides (the tracker's corrections converge the seed).
  const bool against = deeper > -HUGE_VAL;
  Signed_distance_request request = m_context.options.overlap;
  if (against) request.relative_tolerance = std::max(request.relative_tolerance, k_coarse_depth_tolerance);
  Signed_distance_result h = hull_signed_distance(HA, X_WA, HB, X_WB, request);
  if (!(h.distance <= 0.0) || h.element_a < 0 || h.element_b < 0) return false;
  // A solid through an open sheet keeps the depth of the side it entered by (m_sheet_side).
  const bool entry_side = meet && keep_entry_side(HA, X_WA, HB, X_WB, m_sheet_side, request, h);
  // Hulls deeper than every tracked pair, where the surfaces meet: its pair, when each witness
  // lies inside the other body (below), may be a depth no tracker saw arise (a cylinder
  // tumbling on a box, its far rim now the deeper: it read -9.1 against -25.7). Its tracker
  // shows whether it is: inside non-convex bodies the test passes pairs that are none, whose
  // seeds converge elsewhere or merge away.
  const bool missed =
      against && meet && h.upper_bound < deeper - m_context.depth_tolerance(h.distance);
  if (!missed && !((against ? h.lower_bound : h.distance) > deeper + m_context.depth_tolerance(h.distance)))
    return false;  // a tracker holds it already
  // Should no tracker hold a pair, the hulls' depth is the answer reported (as `extremal
  // distance --signed` gives it), not the meeting surfaces' zero ('contact' for a ball deep in
  // a part's plate). Against a tracked depth the search is coarse, and the answer stays.
  if (!against)
    keep_solved(h);
  int pa = -1, pb = -1;
  Vec4 params = Vec4::Zero();
  if (!depth_pair(h, X_WA, X_WB, pa, pb, params)) {
    pa = m_context.model_a->primitive_of(h.kind_a, h.element_a);
    pb = m_context.model_b->primitive_of(h.kind_b, h.element_b);
    if (pa < 0 || pb < 0) return false;
    params_from_global(m_context.model_a->primitives()[pa], h.params_a, params.data());
    params_from_global(m_context.model_b->primitives()[pb], h.params_b,
                       params.data() + m_context.model_a->primitives()[pa].feature.dimension());
  }
  centre_depth_seed(pa, pb, X_WA, X_WB, h.normal, h.distance, params);
  if (meet && !m_context.convex() && !entry_side) {  // (the entry side's foot may lie outside)
    const Primitive& A = m_context.model_a->primitives()[pa];
    const Primitive& B = m_context.model_b->primitives()[pb];
    Feature_point fa, fb;
    evaluate_feature(A.feature, X_WA, params.data(), fa, 0);
    evaluate_feature(B.feature, X_WB, params.data() + A.feature.dimension(), fb, 0);
    // Against a tracked depth deeper than the hulls' (which bound the bodies' translation
    // distance: a stale pair), one witness inside the other body makes the pair one of the
    // bodies' own (two crossing rods: the thinner rod's witness only). Otherwise, and for hulls
    // deeper than the tracked depth, both must be.
    // An open sheet has no inside: only the witness on it is tested, inside the solid (a ball
    // cutting a plane: the plane's point under the ball's lowest), and two sheets that cross
    // keep the hulls' depth, as `extremal distance --signed` reports it. (Against a tracked
    // depth both are solids: check_deep leaves sheets before it.)
    // A witness on the other body's surface, to the seed's tolerance (centre_depth_seed's), is
    // in it: a ball inside a cylinder, touching its cap from within, has its depth's pair there.
    const double on = k_depth_seed_tolerance * std::max({1.0, std::abs(h.distance), box_diagonal(m_context.model_a->box()),
                                       box_diagonal(m_context.model_b->box())});
    const bool test_a = m_context.kind.closed(1), test_b = m_context.kind.closed(0);
    bool a_on_b = false, b_on_a = false;
    const bool a_in_b = test_a && (inside_body(HB, X_WB, fa.p, on, &a_on_b) || a_on_b);
    const bool b_in_a = test_b && (inside_body(HA, X_WA, fb.p, on, &b_on_a) || b_on_a);
    const bool all_in = (a_in_b || !test_a) && (b_in_a || !test_b);
    if (against && !missed ? !(a_in_b || b_in_a) : !all_in) return false;
  }
  keep_solved(h);
  // A converged tracker on the same faces holds another local pair: the hulls' pair gets a
  // tracker beside it, not that one moved there (a ball in the cornetta's plate: its local
  // -0.38 was lost to a seed that never converged, and the rows read the hulls' -0.81; a
  // cylinder's side tumbling on a box: its far rim is the deeper).
  if (missed && m_live.tracks_converged(pa, pb)) {
    m_live[m_live.add(pa, pb, params)].provenance = Provenance::Through_contact;
    ++m_seeds;
  } else {
    m_seeding.add_inside(pa, pb, params, X_WA, X_WB);
  }
  return true;
}

bool Depth_monitor::depth_pair(const Signed_distance_result& h, const Rigid_pose_3& X_WA,
                                   const Rigid_pose_3& X_WB, int& pa, int& pb, Vec4& params) {
  // The hulls' witnesses are support points, each anywhere on its support set: two crossing
  // rods' are a generator each, and the search may return a rim of one and an end of the other,
  // which do not face each other. B moved along the normal by the depth touches A at the
  // depth's pair, so the certified closest pair there is that pair (on a continuum of them, one
  // of it; centre_depth_seed picks the most central). Moved by the certified bound on the
  // depth, the hulls are apart (by at most the depth's tolerance). False also when the
  // witnesses face each other already (no solve needed).
  const double shift = -h.lower_bound + m_context.depth_tolerance(h.distance);
  if (!(shift > 0.0) || !std::isfinite(shift)) return false;
  // Witnesses that face each other across the depth are its pair already (a ball's).
  if ((h.point_b - h.point_a - h.distance * h.normal).norm() <= k_facing_pair * shift) return false;
  const Rigid_pose_3 X_WB_apart(X_WB.rotation(), X_WB.translation() + shift * h.normal);
  Distance_request request = m_context.options.global;
  request.relative_tolerance = std::max(request.relative_tolerance, k_depth_pair_tolerance);
  m_solver.count();
  const Distance_result g = extremal_distance(m_context.model_a->hierarchy(), X_WA, m_context.model_b->hierarchy(),
                                              X_WB_apart, request, m_solver.workspace());
  if ((g.status != Distance_status::Converged && g.status != Distance_status::Touching) ||
      g.element_a < 0 || g.element_b < 0)
    return false;
  pa = m_context.model_a->primitive_of(g.kind_a, g.element_a);
  pb = m_context.model_b->primitive_of(g.kind_b, g.element_b);
  if (pa < 0 || pb < 0) return false;
  params_from_global(m_context.model_a->primitives()[pa], g.params_a, params.data());
  params_from_global(m_context.model_b->primitives()[pb], g.params_b,
                     params.data() + m_context.model_a->primitives()[pa].feature.dimension());
  return true;
}

void Depth_monitor::drop_inside(double above) {
  for (std::size_t k = 0; k < m_live.slots().size(); ++k) {
    const Live& L = m_live[static_cast<int>(k)];
    if (L.alive && L.stepped != -1 && is_inside(L.regime) && L.result.distance < above)
      m_live.kill(static_cast<int>(k));
  }
}

namespace {

// Gauss-Newton on f_A = f_B over primitives A and B from x (least-norm steps, clamped to their
// domains): whether it ends on a point of both, within `tol` of each other.
// x is left at the common point where there is one.
bool common_point(const Tracking_model& MA, int pa, const Rigid_pose_3& X_WA,
                  const Tracking_model& MB, int pb, const Rigid_pose_3& X_WB, Vec4& x, double tol) {
  const Feature& fa = MA.primitives()[pa].feature;
  const Feature& fb = MB.primitives()[pb].feature;
  const int na = fa.dimension(), n = na + fb.dimension();
  const Parameter_domain domain = Parameter_domain::of(fa, fb);
  Feature_point a, b;
  for (int it = 0; it < k_common_point_steps; ++it) {
    domain.clamp(x);
    evaluate_feature(fa, X_WA, x.data(), a, 1);
    evaluate_feature(fb, X_WB, x.data() + na, b, 1);
    const Vec3 r = a.p - b.p;
    if (r.norm() <= tol) return MA.contains(pa, x.data()) && MB.contains(pb, x.data() + na);
    Eigen::Matrix<double, 3, 4> J = Eigen::Matrix<double, 3, 4>::Zero();
    for (int k = 0; k < n; ++k) J.col(k) = k < na ? a.d[k] : Vec3(-b.d[k - na]);
    const Vec4 step = J.completeOrthogonalDecomposition().solve(-r);
    if (!step.allFinite()) return false;
    x += step;
  }
  return false;
}

}  // namespace

bool Depth_monitor::open_pair_overlaps(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB,
                                       bool& seeded) {
  seeded = false;
  const Pair_context& c = m_context;
  if (m_meet.at_valid && c.now.relative.rotation() == m_meet.at.rotation() &&
      c.now.relative.translation() == m_meet.at.translation())
    return m_meet.meets;
  m_meet.at = c.now.relative;
  m_meet.at_valid = m_meet.meets = true;
  const double tol = c.options.contact_tolerance;
  if (m_meet.pa >= 0 && common_point(*c.model_a, m_meet.pa, X_WA, *c.model_b, m_meet.pb, X_WB,
                                     m_meet.params, tol))
    return true;
  m_meet.pa = -1;
  const Distance_result g = m_solver.global(X_WA, X_WB);
  if (g.status == Distance_status::Intersecting || g.status == Distance_status::Touching) {
    m_meet.pa = c.model_a->primitive_of(g.kind_a, g.element_a);
    m_meet.pb = c.model_b->primitive_of(g.kind_b, g.element_b);
    if (m_meet.pa >= 0 && m_meet.pb >= 0) {
      m_meet.params.setZero();
      params_from_global(c.model_a->primitives()[m_meet.pa], g.params_a, m_meet.params.data());
      params_from_global(c.model_b->primitives()[m_meet.pb], g.params_b,
                         m_meet.params.data() +
                             c.model_a->primitives()[m_meet.pa].feature.dimension());
    } else {
      m_meet.pa = -1;
    }
    return true;
  }
  const Overlap_test overlap = overlap_of(g, c.model_a->hierarchy(), X_WA, c.kind.closed(0),
                                          c.model_b->hierarchy(), X_WB, c.kind.closed(1));
  if (overlap.kind != Overlap_kind::None || overlap.unknown || !g.is_certified() ||
      !(g.lower_bound > 0.0))
    return true;  // (not shown apart: the trackers stand)
  m_meet.meets = false;
  drop_inside(HUGE_VAL);
  m_seeding.seed_from(g, X_WA, X_WB, std::numeric_limits<double>::infinity());
  m_checked.value = HUGE_VAL;
  seeded = true;
  return false;
}

bool Depth_monitor::nested(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB, double lower) {
  const Pair_context& c = m_context;
  const bool closed_a = c.kind.closed(0), closed_b = c.kind.closed(1);
  if (!closed_a && !closed_b) return false;
  // Every point moved by less than the surfaces' distance at a pose found outside: still so.
  if (m_outside.valid &&
      approach_bound(c.model_a->box(), c.model_b->box(), m_outside.at, c.now.relative).most <
          m_outside.lower)
    return false;
  const Live* held = nullptr;
  for (const Live& L : m_live.slots())
    if (L.alive && L.valid && (held == nullptr || L.result.distance < held->result.distance)) held = &L;
  if (held == nullptr) return false;
  // A body inside the other has each of its points inside the other's box, then inside it.
  const auto inside = [&](int holder, const Rigid_pose_3& X_W, const Vec3& x_W) {
    const Tracking_model& m = c.model(holder);
    return box_contains(m.box(), X_W.inverse().apply_point(x_W)) &&
           inside_body(m.hierarchy(), X_W, x_W, c.options.contact_tolerance);
  };
  if ((closed_b && inside(1, X_WB, held->result.point_a)) ||
      (closed_a && inside(0, X_WA, held->result.point_b))) {
    m_outside.valid = false;
    return true;
  }
  m_outside = {true, c.now.relative, std::max(lower, 0.0)};
  return false;
}

bool Depth_monitor::meeting_point(const Rigid_pose_3& X_WA, Vec3& x) const {
  const Pair_context& c = m_context;
  if (!m_meet.at_valid || !m_meet.meets || m_meet.pa < 0 ||
      c.now.relative.rotation() != m_meet.at.rotation() ||
      c.now.relative.translation() != m_meet.at.translation())
    return false;
  Feature_point p;
  evaluate_feature(c.model_a->primitives()[m_meet.pa].feature, X_WA, m_meet.params.data(), p, 0);
  x = p.p;
  return x.allFinite();
}

bool Depth_monitor::shallower_pair(double best) {
  // (A step the pair holds nothing leaves its flag as it was: a pair flickering in and out of
  // holding does not trigger a check each time.)
  bool shallower_pair = false;
  const double tol = m_context.options.contact_tolerance;
  for (Live& L : m_live.slots()) {
    if (!L.alive || !(L.valid || holds_unreached(L))) continue;
    const bool shallower =
        L.result.distance < -tol && L.result.distance > best + m_context.depth_tolerance(best);
    if (shallower && !L.was_shallower) shallower_pair = true;
    L.was_shallower = shallower;
  }
  return shallower_pair;
}

bool Depth_monitor::check(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB, double best,
                          bool force) {
  const Pair_context& c = m_context;
  const double tol = c.options.contact_tolerance;
  if (!(best < -tol)) {
    m_checked.value = HUGE_VAL;
    return false;
  }
  // A penetrating row of bodies not both closed needs their surfaces meeting (or a closed one
  // holding part of the other) at its step: two sheets passed through each other, or a solid
  // past a sheet's border, are apart (tests Contact.TwoOpenSheetsPassedThroughEachOtherAreApartOnceOut,
  // ProbeScenes.ASolidThroughASheetAndOutPastItsBorderIsApart).
  if (!c.kind.solid_or_point(0) || !c.kind.solid_or_point(1)) {
    bool seeded = false;
    if (!open_pair_overlaps(X_WA, X_WB, seeded)) return seeded;
  }
  // Inside the normal form's band the tracked pair is the one the bodies met at; deeper, a
  // saddle of the distance that outlives its being the depth (a ball through a larger one keeps
  // its entry pair, negative once out: Contact.DeepPassagesReportTheDepthAndLeaveApart). Two
  // open sheets have no depth to check (whether they still cross is decided above); a solid or
  // a point against an open body is checked for coming apart only.
  const Live* deepest = nullptr;
  for (const Live& L : m_live.slots())
    if (L.alive && L.valid && L.result.distance == best) deepest = &L;
  const bool solid_a = c.kind.solid_or_point(0), solid_b = c.kind.solid_or_point(1);
  const bool point = c.kind.any_point();
  const double da = box_diagonal(c.model_a->box()), db = box_diagonal(c.model_b->box());
  const double size = point ? std::max(da, db) : std::min(da, db);  // the other's, for a point
  const bool against_sheet = !solid_a || !solid_b;
  // A solid against an open body whose witness lies outside the solid's box: either a pair the
  // solid left (past a sheet's border) or the foot of a turned solid's deepest point on its
  // entry side; the certified solve says which at each such step (tests
  // ProbeScenes.ABoxLeavingPastASheetsBorderIsApart,
  // SheetDepth.ATurnedEllipsoidThroughAPlaneKeepsItsEntrySideOnceItsFootLeavesItsBox).
  bool witness_out = false;
  if (against_sheet && !point && deepest != nullptr) {
    const Bbox_3& box = c.model(solid_a ? 0 : 1).box();
    const Vec3& w = solid_a ? deepest->result.point_b : deepest->result.point_a;
    const Vec3 x = (solid_a ? X_WA : X_WB).inverse().apply_point(w);
    const double margin = tol + k_box_margin * box_diagonal(box);
    for (int k = 0; k < 3; ++k)
      if (x[k] < box.min(k) - margin || x[k] > box.max(k) + margin) witness_out = true;
  }
  // (The normal form holds for the step that reached a depth in one stride: fast motion.)
  // A point in a closed body reads minus its distance to the nearest surface point: a minimum
  // over the surface, solved at each step it moved, whatever its depth (test
  // Contact.ABallTouchingACylindersCapFromWithinReadsItsDepth, the ball as its centre).
  const bool point_in_closed = point && (c.kind.closed(0) || c.kind.closed(1));
  if ((!solid_a && !solid_b) || deepest == nullptr || deepest->closed_form ||
      (deepest->result.normal_form && -best <= k_deep_band * size && !force && !witness_out &&
       !point_in_closed)) {
    m_checked.value = HUGE_VAL;
    return false;
  }
  const double step = k_deep_growth * size;
  // Against a sheet, growth counts from the shallowest depth since the last check (a shallower
  // pair that took over must not wait to pass the deeper one's level: test
  // ProbeScenes.AScrewPushedThroughAPlaneIsApartOnceOut).
  if (against_sheet && std::isfinite(m_checked.value))
    m_checked.value = std::max(m_checked.value, best);
  // A point inside a body is checked again as it moves (its depth's nearest face changes
  // without the depth growing); two solids once either box centre moved k_deep_motion_steps
  // growth steps relative to the other (test Contact.ABallRisingInACylinderLeavesThroughItsCap;
  // the centres, not the boxes' bound, so a shaft turning in its bore is not checked again).
  const double moved_by =
      std::isfinite(m_checked.value)
          ? approach_bound(c.model_a->box(), c.model_b->box(), m_checked.at, c.now.relative).closer
          : HUGE_VAL;
  bool moved = point && std::isfinite(m_checked.value) && moved_by > step;
  if (point_in_closed)
    moved = !std::isfinite(m_checked.value) || c.now.relative.rotation() != m_checked.at.rotation() ||
            c.now.relative.translation() != m_checked.at.translation();
  if (!point && !against_sheet && std::isfinite(m_checked.value)) {
    const Vec3 cb = box_centre(c.model_b->box()), ca = box_centre(c.model_a->box());
    const double b_moved = (c.now.relative.apply_point(cb) - m_checked.at.apply_point(cb)).norm();
    const double a_moved =
        (c.now.relative.inverse().apply_point(ca) - m_checked.at.inverse().apply_point(ca)).norm();
    moved = std::max(a_moved, b_moved) > k_deep_motion_steps * step;
  }
  // A solid against a sheet comes apart in one step with a jump of the local depth: checked
  // whenever the depth reaches the solid's width along the pair's normal, by its box once the
  // bodies moved k_sheet_motion of the size, and by real support points (a lower bound on the
  // width, so never late; a turned solid is narrower than its box) at each step that moved
  // (test SheetDepth.ATurnedEllipsoidThroughAPlaneSpinningKeepsItsEntrySideUntilOut).
  bool past_sheet = false;
  if (against_sheet && moved_by > k_sheet_motion * size) {
    const Bbox_3& box = c.model(solid_a ? 0 : 1).box();
    const Vec3 n = (solid_a ? X_WA : X_WB).rotation().transpose() * deepest->result.normal;
    past_sheet = -best >= box_support(box, n) + box_support(box, -n);
  }
  const bool moved_since = !std::isfinite(m_checked.value) ||
                           c.now.relative.rotation() != m_checked.at.rotation() ||
                           c.now.relative.translation() != m_checked.at.translation();
  if (against_sheet && !point && !past_sheet && moved_since) {
    const Distance_hierarchy& S = c.model(solid_a ? 0 : 1).hierarchy();
    const Rigid_pose_3& X = solid_a ? X_WA : X_WB;
    const Vec3& n = deepest->result.normal;
    Support_request request;
    request.tolerance = c.depth_tolerance(best);
    request.max_nets = k_width_nets;
    past_sheet = -best >= support_bound(S, X, n, request).lower +
                              support_bound(S, X, -n, request).lower - c.depth_tolerance(best);
  }
  if (!(best < m_checked.value - step) && !moved && !past_sheet && !force && !witness_out) return false;
  m_checked.value = best;
  m_checked.at = c.now.relative;
  const Distance_result g = m_solver.global(X_WA, X_WB);
  const Overlap_test overlap = overlap_of(g, c.model_a->hierarchy(), X_WA, c.kind.closed(0),
                                          c.model_b->hierarchy(), X_WB, c.kind.closed(1));
  if (overlap.kind == Overlap_kind::None) {
    if (overlap.unknown || !g.is_certified() || !(g.lower_bound > 0.0)) return false;
    drop_inside(HUGE_VAL);  // apart after all: the certified pair
    m_seeding.seed_from(g, X_WA, X_WB, std::numeric_limits<double>::infinity());
    m_checked.value = HUGE_VAL;
    return true;
  }
  // A sheet keeps the depth of the side the solid entered by while their surfaces meet; a
  // sheet wholly inside, or a curve (no sides), reads the hulls' depth like a solid (tests
  // Overlap.ACurveInASolidReadsTheDepthReachedThroughContact,
  // Overlap.AnOpenMeshInASolidReadsTheDepthReachedThroughContact).
  if (against_sheet && !c.kind.curve_against_closed() && overlap.kind == Overlap_kind::Surfaces_meet)
    return false;
  if (overlap.kind != Overlap_kind::Surfaces_meet) m_sheet_side = Vec3::Zero();  // (inside: no side)
  // Still overlapping: where the hulls' depth is the bodies' (one inside the other, both
  // convex, or one of its witnesses inside the other body: the hulls' depth bounds the
  // translation distance), trackers deeper than it go and its pair is tracked (seed_overlap).
  if (!seed_overlap(g, X_WA, X_WB, true, best, &overlap)) return false;
  const double d = m_solved.distance;
  m_checked.value = d;
  drop_inside(d - c.depth_tolerance(d));
  return true;
}

void Depth_monitor::note_answer(const Pair_answer& r, const Rigid_pose_3& X_WA) {
  const Pair_context& c = m_context;
  if (c.kind.closed_against_sheet() && r.distance >= -c.options.contact_tolerance &&
      r.normal.norm() > 0.5)
    m_sheet_side = X_WA.rotation().transpose() * r.normal;
}

}  // namespace extremal::internal
