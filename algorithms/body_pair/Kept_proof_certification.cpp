// The kept-proof candidate stage's certification (Kept_proof_stage.h): candidate pairs without
// a tracker checked each step against a carried certified lower bound, kept up to date from
// the proofs of their restricted solves, solved again (whole or only where the proofs fail)
// when it runs out, and given a tracker when a solve finds them closer than the tracked
// minimum; in contact, seeded.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <new>

#include "algorithms/body_pair/internal/Body_pair_support.h"
#include "algorithms/body_pair/internal/Kept_proof_stage.h"

namespace extremal::internal {

namespace {

// The line B turns about relative to A (world, kind Axis; none when they do not turn
// relatively): the screw axis of the relative twist, through w x v(0) / |w|^2 along w.
Symmetry turn_axis(const Twist_3& V_A, const Rigid_pose_3& X_WA, const Twist_3& V_B,
                   const Rigid_pose_3& X_WB) {
  const Vec3 w = V_B.angular - V_A.angular;
  const double w2 = w.squaredNorm();
  const Vec3 v0 = V_B.velocity_at(Vec3::Zero(), X_WB) - V_A.velocity_at(Vec3::Zero(), X_WA);
  Symmetry s;
  if (!(w2 > 0.0) || !std::isfinite(w2)) return s;
  s.kind = Symmetry::Kind::Axis;
  s.direction = w / std::sqrt(w2);
  s.point = w.cross(v0) / w2;
  return s;
}

// Whether bound proof p's sub-patch pair lies inside the parameter box of its element pair,
// whose first element has na parameters.
bool inside(const Parameter_box& box, int na, int nb, const Bound_proof& p) {
  if (p.a_element != box.element_a || p.b_element != box.element_b) return false;
  for (int k = 0; k < na; ++k)
    if (!(p.a_lo[k] >= box.lo[k] && p.a_hi[k] <= box.hi[k])) return false;
  for (int k = 0; k < nb; ++k)
    if (!(p.b_lo[k] >= box.lo[na + k] && p.b_hi[k] <= box.hi[na + k])) return false;
  return true;
}

// A lower bound on the distance between primitives A and B (bodies placed by X_WA, X_WB) from
// a point pair of theirs (r's witnesses), any shapes: |q - p| is convex, so over the pair it is
// at least r's distance less how far each box reaches past its witness against the direction
// n between them (first-order bound; zero reach where the witnesses are the boxes' extremes
// along n). Test BodyScenes.NearParallelPlatesRowsBoundStaysBelowTheirLowestCorner.
double first_order_lower(const Track_result& r, const Primitive& A, const Primitive& B,
                         const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) {
  const Vec3 diff = r.point_b - r.point_a;
  const double d = diff.norm();
  if (!(d > 0.0) || !std::isfinite(d)) return -HUGE_VAL;
  const Vec3 n = diff / d;
  const Vec3 na = X_WA.rotation().transpose() * n, nb = X_WB.rotation().transpose() * n;
  const Vec3 pa = X_WA.inverse().apply_point(r.point_a), pb = X_WB.inverse().apply_point(r.point_b);
  const double reach_a = std::max(box_support(A.box, na) - na.dot(pa), 0.0);
  const double reach_b = std::max(box_support(B.box, -nb) + nb.dot(pb), 0.0);
  // (Less the rounding of the terms, at the scale of the coordinates.)
  const double scale = d + r.point_a.norm() + r.point_b.norm() + pa.norm() + pb.norm() +
                       box_diagonal(A.box) + box_diagonal(B.box);
  return std::min(d, std::abs(r.distance)) - reach_a - reach_b -
         8.0 * std::numeric_limits<double>::epsilon() * scale;
}

}  // namespace

unsigned Kept_proof_stage::carried_sides(int side, int p, int other, double tol) const {
  const Primitive& P = (side == 0 ? *m_context.model_a : *m_context.model_b).primitives()[p];
  if (!P.is_surface()) return 0u;
  unsigned mask = 0u;
  for (int s = 0; s < 4; ++s) {
    const int n = P.side_neighbour[s];
    if (n < 0 || !(P.side_gap[s] <= k_crease_gap * tol)) continue;
    if (side == 0 ? m_live.tracks_converged(n, other) : m_live.tracks_converged(other, n)) mask |= 1u << s;
  }
  return mask;
}

bool Kept_proof_stage::carriers_tracked(const Candidate& C) const {
  const int pa = key_a(C.key), pb = key_b(C.key);
  for (int side = 0; side < 2; ++side) {
    const unsigned mask = C.carried[side];
    if (!mask) continue;
    const Primitive& P = (side == 0 ? *m_context.model_a : *m_context.model_b).primitives()[side == 0 ? pa : pb];
    for (int s = 0; s < 4; ++s) {
      if (!(mask & (1u << s))) continue;
      const int n = P.side_neighbour[s];
      if (!(side == 0 ? m_live.tracks_converged(n, pb) : m_live.tracks_converged(pa, n))) return false;
    }
  }
  return true;
}

bool Kept_proof_stage::certifiable(int pa, int pb) const {
  const Primitive& A = m_context.model_a->primitives()[pa];
  const Primitive& B = m_context.model_b->primitives()[pb];
  return A.global_element >= 0 && B.global_element >= 0 && !closed_form_pair(A, B);
}

void Kept_proof_stage::mark_tracked() {
  for (Candidate& c : m_candidates) {
    c.tracked = false;
    c.tracked_distance = HUGE_VAL;
    c.tracked_slot = -1;
  }
  for (std::size_t k = 0; k < m_live.slots().size(); ++k) {
    const Live& L = m_live[k];
    if (!L.alive) continue;
    const int i = find_candidate(pair_key(L.pa, L.pb));
    if (i < 0) continue;
    Candidate& C = m_candidates[i];
    C.tracked = true;
    if (L.valid && L.result.distance < C.tracked_distance) {
      C.tracked_distance = L.result.distance;
      C.tracked_slot = static_cast<int>(k);
    }
  }
}

bool Kept_proof_stage::seed_in_contact(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) {
  if (m_over) return false;
  mark_tracked();
  m_queues.dirty = m_queues.all_due = true;  // (every candidate is checked at the next step apart)
  bool seeded = false;
  for (Candidate& C : m_candidates) {
    if (C.tracked) continue;
    const int pa = key_a(C.key), pb = key_b(C.key);
    // A pair seeded apart whose tracker left it (onto a neighbour's pair, or off the bodies) is
    // seeded again once the motion may have brought it into contact: a peg 1 deep in a box's
    // top, slid off its corner, had no tracker on its side against the box's vertical edge,
    // seeded 7 apart, and read the cap's 1 where the corner's depth was 0.4.
    if (C.contact_seeded) {
      if (!(C.seeded_lower < HUGE_VAL)) continue;
      const Approach moved = approach_bound(m_context.model_a->primitives()[pa].box,
                                            m_context.model_b->primitives()[pb].box, C.seeded_at,
                                            m_context.now.relative);
      if (C.seeded_lower - moved.closer > m_context.options.contact_tolerance) continue;
    }
    // (Trackers past the memory limit: the candidates go, the global solver certifies.)
    if (!fits(m_live.bytes_to_add())) {
      go_over_limit();
      return seeded;
    }
    C.contact_seeded = true;
    const double lower = m_seeding.seed_pair(pa, pb, X_WA, X_WB);
    // (Seeded in contact, or without a certificate: not again until the broad phase renews it.)
    C.seeded_lower = lower > m_context.options.contact_tolerance ? lower : HUGE_VAL;
    C.seeded_at = m_context.now.relative;
    seeded = true;
  }
  return seeded;
}

void Kept_proof_stage::forget_proofs(Candidate& C, double lower) {
  C.lower = lower;
  C.at = m_context.now.relative;
  C.reach = {HUGE_VAL, HUGE_VAL};
  C.reach_at = m_context.now.relative;
  C.carried = {0u, 0u};
  m_kept.proof_total -= C.proof_count;
  m_kept.bound_total -= C.bound_count;
  C.proof_count = C.bound_count = C.solve_count = 0;
}

void Kept_proof_stage::queue(Candidate& C, double lower) {
  ++C.generation;
  const int index = static_cast<int>(&C - m_candidates.data());
  // Stale entries (a candidate queued again) go once they outnumber the candidates, in place:
  // the queues keep their capacity.
  const std::size_t most = queue_capacity();
  for (std::vector<Queue_entry>* heap : {&m_queues.bound, &m_queues.reach}) {
    if (heap->size() < most) continue;
    heap->erase(std::remove_if(heap->begin(), heap->end(),
                               [&](const Queue_entry& e) {
                                 return e.generation != m_candidates[static_cast<std::size_t>(e.index)].generation;
                               }),
                heap->end());
    std::make_heap(heap->begin(), heap->end(), Queue_order());
  }
  // (A bound that holds this step only, a pair located off its primitives, whose sides carry it:
  // queued at its boxes, so that it is located again once the motion may have used them up.
  // Test BodyScenes.APairLocatedOffItsPrimitivesIsCheckedAgain.)
  if (!(lower < HUGE_VAL))
    lower = box_distance(m_context.model_a->primitives()[key_a(C.key)].box,
                         transformed(m_context.model_b->primitives()[key_b(C.key)].box, m_context.now.relative));
  C.bound_key = lower + m_queues.moved;
  C.reach_key = HUGE_VAL;
  m_queues.bound.push_back({C.bound_key, index, C.generation});
  std::push_heap(m_queues.bound.begin(), m_queues.bound.end(), Queue_order());
  if (!(C.reach[0] < HUGE_VAL || C.reach[1] < HUGE_VAL)) return;
  const Approach since = approach_bound(m_context.model_a->primitives()[key_a(C.key)].box,
                                        m_context.model_b->primitives()[key_b(C.key)].box,
                                        C.reach_at, m_context.now.relative);
  const double left = std::min(C.reach[0] - since.move_b, C.reach[1] - since.move_a);
  C.reach_key = m_queues.moved + std::max(left, 0.0);
  m_queues.reach.push_back({C.reach_key, index, C.generation});
  std::push_heap(m_queues.reach.begin(), m_queues.reach.end(), Queue_order());
}

void Kept_proof_stage::requeue_all(bool all_due) {
  m_queues.bound.clear();
  m_queues.reach.clear();
  // (At most queue_capacity() entries each: a steady step never grows them.)
  m_queues.bound.reserve(queue_capacity() + 1);
  m_queues.reach.reserve(queue_capacity() + 1);
  m_scratch.queue_kept.reserve(queue_capacity() + 1);
  for (std::size_t i = 0; i < m_candidates.size(); ++i) {
    Candidate& C = m_candidates[i];
    if (all_due) C.bound_key = -HUGE_VAL, C.reach_key = HUGE_VAL;
    const int index = static_cast<int>(i);
    m_queues.bound.push_back({C.bound_key, index, ++C.generation});
    if (C.reach_key < HUGE_VAL) m_queues.reach.push_back({C.reach_key, index, C.generation});
  }
  std::make_heap(m_queues.bound.begin(), m_queues.bound.end(), Queue_order());
  std::make_heap(m_queues.reach.begin(), m_queues.reach.end(), Queue_order());
  m_queues.dirty = m_queues.all_due = false;
}

Apart_certificate Kept_proof_stage::certify_apart(const Rigid_pose_3& X_WA,
                                                  const Rigid_pose_3& X_WB, double best) {
  if (m_over) return {};
  mark_tracked();
  bool meet = false;
  // What the rows may miss (the error budget), and the restricted solves' tolerance: the
  // seeding request's, at most a quarter of the budget so that every cutoff has room above
  // `need` (k_seeding_slack).
  const Body_pair_options& o = m_context.options;
  const Error_budget& b = m_context.now.budget;
  const double budget = b.at(best);
  Distance_request request = o.seeding;
  request.absolute_tolerance = std::min(request.absolute_tolerance, b.absolute / k_seeding_slack);
  request.relative_tolerance = std::min(request.relative_tolerance, b.relative / k_seeding_slack);
  const double tol = std::max(request.absolute_tolerance, request.relative_tolerance * best);
  const double need_apart = best - budget;  // a pair certified at or above this holds nothing closer
  // The certified lower bound on the bodies' distance this step: the least of every candidate
  // pair's certified bound, and of the pairs beyond the broad phase's reach (all of them at
  // least the reach less the relative motion since it ran). Test
  // Certificate.EveryApartRowsLowerBoundHoldsAgainstTheOneShotSolver.
  double certified = m_broad.reach - approach_bound(m_context.model_a->box(), m_context.model_b->box(),
                                                    m_broad.relative, m_context.now.relative).closer;
  const Symmetry turning = m_context.now.V_A != nullptr && m_context.now.V_B != nullptr
                               ? turn_axis(*m_context.now.V_A, X_WA, *m_context.now.V_B, X_WB)
                               : Symmetry();
  // Tracked pairs are watched for a second basin of their own, except between two certified
  // convex bodies: apart, a local minimum of their distance is the global one. (Near contact
  // the watch is costly: its gap shrinks with the distance. Two balls 1e-3 apart rolling on
  // each other were solved every step, 100 times the time.)
  const bool watch = m_context.options.own_basin_gap > 0.0 && !m_context.convex();
  // The check of one candidate: its certified lower bound at this step (seeding it where it
  // holds something closer).
  auto check = [&](Candidate& C) -> double {
    // A pair holds its tracked distance only through a valid tracker: one whose trackers all
    // hold nothing (wandering, or sat on a false solution where its surfaces cross: a ball
    // cutting a shell's face read 'tracking' at +0.025 on another face) is certified as an
    // untracked one.
    const bool held = std::isfinite(C.tracked_distance);
    const int pa = key_a(C.key), pb = key_b(C.key);
    const Primitive& A = m_context.model_a->primitives()[pa];
    const Primitive& B = m_context.model_b->primitives()[pb];
    // Pairs not watched or not certifiable: a tracked reading at a minimum of its pair over the
    // domains (converged, and not held on a patch edge while the distance descends into the
    // domain: Live_set::at_minimum) is the pair's minimum between convex bodies, and a closed
    // form's is exact; otherwise the last certified bound, decayed, or the boxes.
    // (A flat pair, or a flat primitive against a convex body, has one basin: its tracker at a
    // minimum reads it. Tests BodyScenes.FlatAgainstConvexPairsNeedNoWatch,
    // ProbeScenes.ASheetsEdgeHeldOnAPlanesCornerIsNoCertificate.)
    const bool at_minimum = held && m_live.at_minimum(m_live[C.tracked_slot], k_converged_error);
    bool one_basin = at_minimum && watch && m_context.flat_single_basin(pa, pb, C.tracked_distance);
    double tracked_lower = C.tracked_distance;
    // Two flat primitives neither a point (near parallel: the distance nearly constant, a
    // converged reading anywhere up to the faces' extent times their angle above the minimum):
    // the reading's first-order bound, which must clear the budget, else the pair is watched.
    // Test BodyScenes.NearParallelPlatesRowsBoundStaysBelowTheirLowestCorner.
    if (one_basin && !m_live[C.tracked_slot].closed_form &&
        !m_context.single_basin_locatable(pa, pb, C.tracked_distance)) {
      tracked_lower = first_order_lower(m_live[C.tracked_slot].result, A, B, X_WA, X_WB);
      one_basin = tracked_lower >= need_apart;
    }
    if ((at_minimum && (!watch || one_basin)) || !certifiable(pa, pb)) {
      const bool exact =
          held && (m_live[C.tracked_slot].closed_form || (at_minimum && (!watch || one_basin)));
      double lower = exact ? (one_basin ? tracked_lower : C.tracked_distance)
                           : C.lower - approach_bound(A.box, B.box, C.at, m_context.now.relative).closer;
      if (!exact) lower = std::max(lower, box_distance(transformed(A.box, X_WA), transformed(B.box, X_WB)));
      return lower;
    }
    // A tracked pair is watched for another basin of its own: what must clear is its tracked
    // distance less the gap (or the tracked minimum, if lower), and every cutoff stays below
    // the tracked basin (half the gap), so the solves settle it rather than converge on it.
    double need = need_apart;
    double ceiling = HUGE_VAL;
    if (held) {
      const double gap =
          std::max(k_seeding_slack * tol,
                   std::min(o.own_basin_gap * C.tracked_distance, b.at(C.tracked_distance)));
      need = std::min(need_apart, C.tracked_distance - gap);
      ceiling = C.tracked_distance - k_watch_ceiling * gap;
    }
    auto below_ceiling = [&](double cutoff) { return std::max(need + tol, std::min(cutoff, ceiling)); };
    ++m_stats.vacated_checks;
    // The bound carried from an earlier step, less how much closer the pair can have come;
    // pairs that solve set aside (their minimum on a carried boundary: a trim edge, or a
    // side shared with a face whose pair is tracked) stay so while the relative motion is
    // below their gradient's reach and the carrying pairs are still tracked (see below).
    const Approach moved = approach_bound(A.box, B.box, C.at, m_context.now.relative);
    double lower_now = C.lower - moved.closer;
    bool clear = lower_now >= need;
    if (!clear && C.bound_count > 0) {
      // The decay assumed the worst direction of motion for the whole pair: its last solve's
      // bounded sub-patch pairs, re-bounded at this pose, often still clear it.
      const double now = bounds_now(C, need);
      if (now >= need) {
        clear = true;
        ++m_stats.vacated_bound_checks;
        C.lower = lower_now = now;
        C.at = m_context.now.relative;
      }
    }
    if (clear && carriers_tracked(C)) {
      const bool finite = C.reach[0] < HUGE_VAL || C.reach[1] < HUGE_VAL;
      const Approach since = finite ? approach_bound(A.box, B.box, C.reach_at, m_context.now.relative) : moved;
      bool holds = since.move_b < C.reach[0] && since.move_a < C.reach[1];
      // Past the reach, which assumed the worst direction of motion: the set-aside pairs
      // checked again at this pose (the other box moved rigidly) usually still hold.
      std::array<double, 2> reach;
      if (!holds && proofs_hold(C, reach)) {
        holds = true;
        ++m_stats.vacated_proof_checks;
        C.reach = reach;
        C.reach_at = m_context.now.relative;
      }
      if (holds) {
        return lower_now;
      }
    }
    const double boxes = box_distance(transformed(A.box, X_WA), transformed(B.box, X_WB));
    if (boxes >= need) {
      forget_proofs(C, boxes);
      return boxes;
    }
    // A pair with one basin: its stationary point by Newton's method, not the branch and bound.
    // Test BodyScenes.FlatAgainstConvexPairsNeedNoWatch.
    if (!held && m_context.single_basin_locatable(pa, pb, best)) {
      Vec4 params;
      if (const std::optional<double> located = locate_single_basin(C, pa, pb, params)) {
        ++m_stats.located;
        // (Off the primitives: the pair is located again at its next check, from the boxes.)
        forget_proofs(C, *located < HUGE_VAL ? *located : boxes);
        if (*located >= need) return *located;
        // A closer basin: tracked from here on (on the primitives: a point held on a patch
        // side that is no edge of a face is solved instead).
        const int na = A.feature.dimension();
        if (m_context.model_a->contains(pa, params.data()) &&
            m_context.model_b->contains(pb, params.data() + na)) {
          if (*located <= m_context.options.contact_tolerance) meet = true;
          const int slot = m_live.add(pa, pb, params);
          mark_seeded_apart(m_live[slot]);
          ++m_stats.seeds;
          ++m_stats.vacated_seeds;
          C.tracked = true;
          return *located;
        }
        C.lower = -HUGE_VAL;
      }
    }
    // The certified solver on the pair, cut off some steps' motion above `need`: it seeds the
    // pair when it holds something closer than the tracked minimum, and otherwise leaves a
    // lower bound that stays clear of `need` for the next steps.
    ++m_stats.vacated_solves;
    if (clear) ++m_stats.vacated_reach_solves;
    const double step_motion = approach_bound(A.box, B.box, m_context.now.previous_relative, m_context.now.relative).closer;
    // At most the broad phase's margin: a cutoff far above the minimum would have the solver
    // settle every pair below it. When one step's motion exceeds that margin (low rates) the
    // bound cannot outlast the step anyway: cut off at `need` itself.
    const double cap = m_context.reach_margin();
    const double slack =
        step_motion >= cap
            ? k_seeding_slack * tol
            : std::max(k_seeding_slack * tol,
                       std::min(std::max(k_slack_steps * step_motion, k_slack_growth * C.slack), cap));
    internal::Proof_request proof;
    proof.keep_proofs = true;
    // The watch: the tracked basin's own neighbourhood is settled by a convexity certificate
    // about the tracker's point, not by hull bounds (Distance_request::stationary).
    if (held && !m_live[C.tracked_slot].closed_form &&
        A.kind != Primitive_kind::Triangle && B.kind != Primitive_kind::Triangle) {
      const Vec4& q = m_live[C.tracked_slot].result.params;
      proof.stationary = std::array<double, 4>{{q[0], q[1], q[2], q[3]}};
    }
    proof.motion_axis = turning;
    request.cutoff = below_ceiling(need + slack);
    // Trim-edge set-asides of trimmed faces: their proofs outlast a few steps' motion.
    proof.carried_min_reach = std::min(slack, k_reach_steps * step_motion);
    // Crease ties. A face sharing a patch side with a face whose pair with the same other
    // primitive is tracked (a C0 join of a multi-patch body) has its minimum on that side when
    // the tracked point sits there: it ties the tracked minimum and no bound of the pair can
    // clear it. Such sides are declared carried: sub-patch pairs over which the gradient of the
    // squared distance along this face's parameters provably does not vanish, touching no other
    // side, are set aside, and the others are settled at the cutoff (the floor: a witness at or
    // above `need`, such as the tie itself, does not stop the solve). Why that is exact: were
    // the pair's minimum x* below `need`, it would lie in a set-aside sub-patch pair (the others
    // are bounded above it), where a non-vanishing gradient component puts a minimiser on the
    // domain boundary, i.e. on a carried side (no other side is touched); that side is the
    // tracked neighbour's too (within side_gap <= tol / 4), so the tracked pair would hold a
    // point below its tracked minimum by more than the tolerance - what every tracked pair is
    // taken not to do (up to the watch's own_basin_gap, below), required here of a converged
    // tracker only (tracks_converged: a lagging one may sit above the crease). After motion,
    // the gradient keeps its sign while the other primitive has moved less than the reach the
    // solve reports, and the other pairs' bound decays as before; a deeper minimum of the face
    // away from the side is found as any other basin (its pairs are neither set aside nor
    // above it).
    // The pair's elements whole, or only the sub-patch pairs in m_scratch.restarts (`partial`).
    auto solve = [&](const Distance_request& r, const internal::Proof_request& p, bool partial) {
      const Distance_hierarchy& ha = m_context.model_a->hierarchy();
      const Distance_hierarchy& hb = m_context.model_b->hierarchy();
      Distance_result result =
          partial ? internal::extremal_distance_between(ha, X_WA, A.global_element, hb, X_WB,
                                                        B.global_element, m_scratch.restarts, r, p,
                                                        m_solver.workspace())
                  : internal::extremal_distance_between(ha, X_WA, A.global_element, hb, X_WB,
                                                        B.global_element, r, p, m_solver.workspace());
      m_stats.vacated_nodes += result.nodes_created;
      return result;
    };
    // (Not for a tracked pair's watch: two tracked pairs on one crease would each leave the
    // shared side to the other, and a closer point on it to neither.)
    unsigned carried_a = held ? 0u : carried_sides(0, pa, pb, tol);
    unsigned carried_b = held ? 0u : carried_sides(1, pb, pa, tol);
    const bool carrying = (carried_a | carried_b) != 0u;
    // A trimmed pair tied with the tracked minimum on a trim edge (the tracked pair holds that
    // edge) would likewise be solved to its witness there every time: it is proved against a
    // cutoff too (floor `need`), its pairs at the edge set aside by their gradient. Untrimmed
    // pairs without carried sides have no such ties and nothing to set aside: the usual solve.
    const bool trimmed = m_context.model_a->hierarchy().elements()[A.global_element].trimmed ||
                         m_context.model_b->hierarchy().elements()[B.global_element].trimmed;
    // An edge's pair whose last solve found its own minimum just above the tracked one (an edge
    // of a face beside the tracked point) would exhaust the proving budget at every check
    // against that minimum before the usual solve: it goes to the usual solve at once. (Faces'
    // pairs keep the proof: settling them to their witness costs more than it saves.)
    const bool prove = (carrying || trimmed) &&
                       !(C.holds_own_minimum && !carrying &&
                         (A.kind == Primitive_kind::Edge || B.kind == Primitive_kind::Edge));
    Distance_request first = request;
    internal::Proof_request first_proof = proof;
    if (prove) {
      first_proof.cutoff_floor = need;
      first.max_nodes = k_crease_nodes;
      if (carrying) {
        first_proof.carried_sides = {carried_a, carried_b};
        // Cutoff and gradient reach alike (the motion either proof outlasts).
        const double crease_slack =
            step_motion >= cap ? k_seeding_slack * tol : std::max(k_seeding_slack * tol, k_crease_fraction * cap);
        first.cutoff = below_ceiling(need + crease_slack);
        first_proof.carried_min_reach = crease_slack;
        ++m_stats.vacated_crease_solves;
      } else {
        first.cutoff =
            below_ceiling(need + std::max(k_seeding_slack * tol, std::min(slack, k_proving_steps * step_motion)));
        first_proof.carried_min_reach = std::min(first.cutoff - need, k_reach_steps * step_motion);
      }
    }
    // Where the pair's kept proofs still clear the cutoff at this pose, only the sub-patch
    // pairs whose proofs fail are solved again: the kept ones cover the rest of the domain.
    // (Proofs kept for other carried sides rest on other trackers: not kept.) Pruned at the
    // cutoff less the tolerance, as the solver prunes.
    double kept_lower = HUGE_VAL;
    std::array<double, 2> kept_reach{{HUGE_VAL, HUGE_VAL}};
    const bool partial =
        C.carried[0] == carried_a && C.carried[1] == carried_b &&
        plan_partial_solve(C, A.global_element, B.global_element, first.cutoff - tol,
                           first_proof.carried_min_reach, first.max_nodes, kept_lower,
                           kept_reach);
    Distance_result g = solve(first, first_proof, partial);
    bool kept = partial;
    // A proving solve not settled within its budget (a stationary point of the pair between
    // the tracked minimum and the cutoff): the usual solve, to the witness. (Kept proofs are
    // at or above the cutoff.)
    if (prove && !(g.upper_bound < need) && !(g.uncarried_lower_bound >= need)) {
      g = solve(request, proof, false);
      carried_a = carried_b = 0u;
      kept = false;
    }
    if (kept) ++m_stats.vacated_partial_solves;
    // The watch's convex region about the tracked point, for the next steps' checks (a partial
    // solve that did not reach the region keeps the one before: its box is re-certified at
    // every use).
    if (proof.stationary) {
      if (const std::optional<Parameter_box> region = stationary_region(m_solver.workspace())) {
        C.region = *region;
        C.has_region = true;
        grow_region(C, A, B);
      } else if (!kept) {
        C.has_region = false;
      }
    } else {
      C.has_region = false;
    }
    C.lower = kept ? std::min(g.uncarried_lower_bound, kept_lower) : g.uncarried_lower_bound;
    C.at = m_context.now.relative;
    C.reach = g.carried_reach;
    if (kept)
      for (int side = 0; side < 2; ++side) C.reach[side] = std::min(C.reach[side], kept_reach[side]);
    C.reach_at = m_context.now.relative;
    C.carried = {carried_a, carried_b};
    keep_proofs(C, Solve_pose{X_WA, m_context.now.relative}, kept);
    C.slack = g.element_a < 0 ? slack : 0.0;
    C.holds_own_minimum = g.element_a >= 0 && g.upper_bound >= need;
    if (g.element_a < 0 || g.element_b < 0 || !(g.upper_bound < need)) {
      return C.lower;
    }
    if (g.upper_bound <= m_context.options.contact_tolerance) meet = true;
    // A closer basin found by a solve that stopped short of the budget (proving, or partial):
    // the pair solved whole, for a bound within the budget of the new minimum.
    double lower = C.lower;
    if (lower < certified_floor(g.upper_bound, o.tolerance))
      lower = std::max(lower, solve(request, proof, false).uncarried_lower_bound);
    Vec4 params = Vec4::Zero();
    params_from_global(A, g.params_a, params.data());
    params_from_global(B, g.params_b, params.data() + A.feature.dimension());
    // (A tracked pair's tracker moves to its closer basin.)
    const int slot = C.tracked ? m_seeding.place(pa, pb, params, X_WA, X_WB) : m_live.add(pa, pb, params);
    mark_seeded_apart(m_live[slot]);
    ++m_stats.seeds;
    ++m_stats.vacated_seeds;
    C.tracked = true;
    return lower;
  };
  // Tracked and creased candidates are checked at every step (their readings and carriers
  // change without motion); the others when their queue entries say the motion may have used
  // up their bound or their set-aside proofs' reach (m_queues.bound, m_queues.reach).
  // (Rounded up: the sum never falls below the motion it adds up.)
  m_queues.moved = (m_queues.moved + approach_bound(m_context.model_a->box(), m_context.model_b->box(),
                                      m_queues.moved_at, m_context.now.relative).most) *
            (1.0 + 4.0 * std::numeric_limits<double>::epsilon());
  m_queues.moved_at = m_context.now.relative;
  // (Keys carry m_queues.moved: started again before its rounding could matter against the budget.)
  if (m_queues.moved > k_requeue_motion * m_context.length()) {
    m_queues.moved = 0.0;
    m_queues.dirty = m_queues.all_due = true;
  }
  if (m_queues.dirty) requeue_all(m_queues.all_due);
  const long step = m_context.now.steps;
  long checks = 0;
  // A candidate checked while tracked is checked again at its next step whether or not it is
  // still tracked: its key was the tracker's reading, which holds while the tracker does.
  // (Rows' bounds against the one-shot solver: Certificate.EveryApartRowsLowerBoundHoldsAgainstTheOneShotSolver.)
  auto checked = [&](Candidate& C) {
    const bool tracked = C.tracked;
    const double lower = check(C);
    C.checked_step = step;
    C.checked_tracked = tracked || C.tracked;
    certified = std::min(certified, lower);
    queue(C, lower);
    ++checks;
  };
  for (Candidate& C : m_candidates)
    if (C.tracked || C.checked_tracked || C.carried[0] != 0u || C.carried[1] != 0u) checked(C);
  // An entry's key less m_queues.moved, less the rounding of both (what its candidate's bound, or its
  // proofs' reach, is at least now).
  auto left = [&](const Queue_entry& e) {
    return e.key - m_queues.moved - 4.0 * std::numeric_limits<double>::epsilon() * (std::abs(e.key) + m_queues.moved);
  };
  auto push_kept = [&](std::vector<Queue_entry>& heap) {
    for (const Queue_entry& e : m_scratch.queue_kept) {
      heap.push_back(e);
      std::push_heap(heap.begin(), heap.end(), Queue_order());
    }
  };
  // Entries of candidates checked at this step whose new key is due all the same (their bound is
  // short of `need`) stay queued: a candidate's current entries are its only record until the
  // queues are made again. Test
  // BodyScenes.AnUncertifiedCandidateStaysQueuedAndBoundsTheRows.
  auto pop_due = [&](std::vector<Queue_entry>& heap, double level) {
    m_scratch.queue_kept.clear();
    while (!heap.empty() && left(heap.front()) < level) {
      std::pop_heap(heap.begin(), heap.end(), Queue_order());
      const Queue_entry e = heap.back();
      heap.pop_back();
      Candidate& C = m_candidates[static_cast<std::size_t>(e.index)];
      if (e.generation != C.generation) continue;  // (stale)
      if (C.checked_step == step) {
        m_scratch.queue_kept.push_back(e);
        continue;
      }
      checked(C);
    }
    push_kept(heap);
  };
  pop_due(m_queues.bound, need_apart);
  pop_due(m_queues.reach, 0.0);
  // The candidates not checked: their queued bounds, less the motion since (those checked
  // gave their bound above; their keys say only when to look again).
  m_scratch.queue_kept.clear();
  while (!m_queues.bound.empty()) {
    const Queue_entry& e = m_queues.bound.front();
    const Candidate& C = m_candidates[static_cast<std::size_t>(e.index)];
    if (e.generation == C.generation && C.checked_step != step) break;
    if (e.generation == C.generation) m_scratch.queue_kept.push_back(e);
    std::pop_heap(m_queues.bound.begin(), m_queues.bound.end(), Queue_order());
    m_queues.bound.pop_back();
  }
  if (!m_queues.bound.empty()) certified = std::min(certified, left(m_queues.bound.front()));
  push_kept(m_queues.bound);
  m_stats.vacated_queued += static_cast<long>(m_candidates.size()) - checks;
  return {meet, certified};
}

const Rigid_pose_3& Kept_proof_stage::Motions::b(int k) {
  if (!(m_made_b & (1u << k))) {
    // X_WA0 X_AB X_AB0^-1 X_WA0^-1 (A's points move by its inverse with B held).
    const Solve_pose& s = m_solves[k];
    m_length[k] = s.a.translation().cwiseAbs().maxCoeff() +
                  m_relative.translation().cwiseAbs().maxCoeff() +
                  s.relative.translation().cwiseAbs().maxCoeff();
    new (&m_b[k].pose) Rigid_pose_3(s.a * m_relative * s.relative.inverse() * s.a.inverse());
    m_made_b |= 1u << k;
  }
  return m_b[k].pose;
}

const Rigid_pose_3& Kept_proof_stage::Motions::a(int k) {
  if (!(m_made_a & (1u << k))) {
    new (&m_a[k].pose) Rigid_pose_3(b(k).inverse());
    m_made_a |= 1u << k;
  }
  return m_a[k].pose;
}

bool Kept_proof_stage::proofs_hold(const Candidate& C, std::array<double, 2>& reach) const {
  if (C.proof_count == 0) return false;
  Motions m(solves_of(C), m_context.now.relative);
  reach = {HUGE_VAL, HUGE_VAL};
  for (int i = C.proof_begin; i < C.proof_begin + C.proof_count; ++i) {
    const Gradient_proof& p = m_kept.proofs[i].proof;
    const int k = m_kept.proofs[i].solve;
    double r = 0.0;
    if (!gradient_proof_holds(p, p.side == 0 ? m.b(k) : m.a(k), m.length(k), r)) return false;
    reach[p.side] = std::min(reach[p.side], r);
  }
  return true;
}

void Kept_proof_stage::grow_region(Candidate& C, const Primitive& A, const Primitive& B) {
  // The solve certified the region only as large as the sub-patches about the tracked point
  // when it got there; a smooth basin is often convex much farther (a wide, flat one most of
  // all, whose sub-patches beside the region stay within the budget of its minimum): doubled
  // about the point while convexity still holds, so that kept bounds inside it outlast the
  // motion. Test Certificate.EveryApartRowsLowerBoundHoldsAgainstTheOneShotSolver.
  if (C.tracked_slot < 0) return;
  const Vec4& q = m_live[C.tracked_slot].result.params;
  const std::array<double, 4> x{{q[0], q[1], q[2], q[3]}};
  const int na = A.feature.dimension(), nb = B.feature.dimension();
  const Distance_hierarchy& ha = m_context.model_a->hierarchy();
  const Distance_hierarchy& hb = m_context.model_b->hierarchy();
  for (int k = 0; k < k_region_doublings; ++k) {
    Parameter_box wider = C.region;
    for (int i = 0; i < na + nb; ++i) {
      const Feature& f = i < na ? ha.elements()[C.region.element_a].feature
                                : hb.elements()[C.region.element_b].feature;
      const int j = i < na ? i : i - na;
      const double half = C.region.hi[i] - C.region.lo[i];  // (twice the half-width)
      wider.lo[i] = std::max(f.lower(j), x[i] - half);
      wider.hi[i] = std::min(f.upper(j), x[i] + half);
    }
    if (!convex_region_lower(ha, *m_context.now.X_WA, hb, *m_context.now.X_WB, wider, x,
                             m_solver.workspace()))
      return;
    C.region = wider;
  }
}

std::optional<double> Kept_proof_stage::locate_single_basin(Candidate& C, int pa, int pb,
                                                            Vec4& params) {
  const Primitive& A = m_context.primitive(0, pa);
  const Primitive& B = m_context.primitive(1, pb);
  const int na = A.feature.dimension(), n = na + B.feature.dimension();
  if (C.has_located) {
    params = C.located;
  } else {
    params.setZero();
    for (int k = 0; k < n; ++k) {
      const Feature& f = k < na ? A.feature : B.feature;
      const int i = k < na ? k : k - na;
      params[k] = 0.5 * (f.lower(i) + f.upper(i));
    }
  }
  Tracker_options o = m_context.options.tracker;
  o.corrections = k_locate_corrections;
  o.correction_tolerance = k_locate_tolerance;
  Extremal_tracker tracker(A.feature, B.feature, params, o);
  const Twist_3 rest;
  const Track_result& r =
      tracker.step(m_context.now.t, *m_context.now.X_WA, rest, *m_context.now.X_WB, rest, m_context.now.dt);
  params = r.params;
  // (Held on a patch edge while the distance descends into the domain: no stationary point.)
  if (r.degeneracy != Degeneracy::None || !(r.distance > m_context.options.contact_tolerance) ||
      descends_from_edge(A.feature, B.feature, r, k_locate_converged))
    return std::nullopt;
  for (int k = 0; k < n; ++k)
    if (!(r.on_edge & (1u << k)) && !(std::abs(r.normalised_errors[k]) <= k_locate_converged))
      return std::nullopt;
  C.located = params;
  C.has_located = true;
  // Off the primitives (held on a patch side, or outside a trim): the least over the patches
  // lies on a side or the pair's least on the body lies on its border; either way on edges
  // that carry it, when every side and trim of both is carried.
  const Distance_hierarchy::Element& ea = m_context.model_a->hierarchy().elements()[A.global_element];
  const Distance_hierarchy::Element& eb = m_context.model_b->hierarchy().elements()[B.global_element];
  const unsigned mask_a = (1u << na) - 1u;
  const bool off_a = (r.on_edge & mask_a) != 0u || !m_context.model_a->contains(pa, params.data());
  const bool off_b = (r.on_edge & ~mask_a) != 0u || !m_context.model_b->contains(pb, params.data() + na);
  const bool off = off_a || off_b;
  const bool carried = (!off_a || ea.open_sides == 0u) && (!off_b || eb.open_sides == 0u);
  if (off) {
    if (carried) return HUGE_VAL;
    // (Held on a side, the least over the patch, which bounds the pair but is no seed.)
    if (r.on_edge == 0u) return std::nullopt;
  }
  return r.distance;
}

double Kept_proof_stage::bounds_now(const Candidate& C, double need) const {
  if (C.bound_count == 0) return -HUGE_VAL;
  Motions m(solves_of(C), m_context.now.relative);
  // A pair's bound less how far the primitives can have come closer since its solve (as the
  // carried bound decays) often clears `need` already: then it is not re-bounded. (A tracked
  // pair's own check re-bounds only the few pairs about its tracked basin.)
  const Bbox_3& box_a = m_context.model_a->primitives()[key_a(C.key)].box;
  const Bbox_3& box_b = m_context.model_b->primitives()[key_b(C.key)].box;
  double closer[k_kept_solves];
  unsigned made = 0u;
  double lowest = HUGE_VAL;
  // The carried region's bound at this pose, made on first need (NaN: not yet; -infinity: the
  // region does not hold here, or the pair's tracker is not on it).
  double region = std::numeric_limits<double>::quiet_NaN();
  const int na = m_context.model_a->primitives()[key_a(C.key)].feature.dimension();
  const int nb = m_context.model_b->primitives()[key_b(C.key)].feature.dimension();
  auto region_now = [&] {
    if (region == region) return region;
    region = -HUGE_VAL;
    if (!C.has_region || C.tracked_slot < 0) return region;
    const Live& L = m_live[C.tracked_slot];
    if (!L.valid || L.closed_form || !m_live.is_converged(L, k_converged_error)) return region;
    const std::array<double, 4> x{{L.result.params[0], L.result.params[1], L.result.params[2],
                                   L.result.params[3]}};
    if (const std::optional<double> r =
            convex_region_lower(m_context.model_a->hierarchy(), *m_context.now.X_WA,
                                m_context.model_b->hierarchy(), *m_context.now.X_WB, C.region, x,
                                m_solver.workspace()))
      region = *r;
    return region;
  };
  for (int i = C.bound_begin; i < C.bound_begin + C.bound_count; ++i) {
    const int k = m_kept.bounds[i].solve;
    if (!(made & (1u << k))) {
      closer[k] = approach_bound(box_a, box_b, solves_of(C)[k].relative, m_context.now.relative).closer;
      made |= 1u << k;
    }
    const Bound_proof& p = m_kept.bounds[i].proof;
    double b = p.lower - closer[k];
    if (!(b >= need)) b = std::max(b, bound_after_motion(p, m.b(k), m.length(k)));
    if (!(b >= need) && C.has_region && inside(C.region, na, nb, p)) b = std::max(b, region_now());
    lowest = std::min(lowest, b);
    if (lowest < need) break;
  }
  return lowest;
}

bool Kept_proof_stage::plan_partial_solve(const Candidate& C, int element_a, int element_b,
                                           double cutoff, double min_reach, int max_nodes,
                                           double& lower, std::array<double, 2>& reach) {
  if (C.solve_count == 0 || C.solve_count >= k_kept_solves || C.bound_count + C.proof_count == 0)
    return false;
  Motions m(solves_of(C), m_context.now.relative);
  m_scratch.restarts.clear();
  m_scratch.keep_bound.assign(static_cast<std::size_t>(C.bound_count), 0);
  m_scratch.keep_proof.assign(static_cast<std::size_t>(C.proof_count), 0);
  lower = HUGE_VAL;
  reach = {HUGE_VAL, HUGE_VAL};
  for (int i = 0; i < C.bound_count; ++i) {
    const Kept_bound& kb = m_kept.bounds[C.bound_begin + i];
    const Bound_proof& p = kb.proof;
    if (p.a_element != element_a || p.b_element != element_b) return false;
    const double now = bound_after_motion(p, m.b(kb.solve), m.length(kb.solve));
    if (now >= cutoff) {
      m_scratch.keep_bound[i] = 1;
      lower = std::min(lower, now);
    } else {
      m_scratch.restarts.push_back({p.a_lo, p.a_hi, p.b_lo, p.b_hi});
    }
  }
  for (int i = 0; i < C.proof_count; ++i) {
    const Kept_proof& kp = m_kept.proofs[C.proof_begin + i];
    const Gradient_proof& p = kp.proof;
    double r = 0.0;
    const int k = kp.solve;
    if (gradient_proof_holds(p, p.side == 0 ? m.b(k) : m.a(k), m.length(k), r) &&
        r >= min_reach) {
      m_scratch.keep_proof[i] = 1;
      reach[p.side] = std::min(reach[p.side], r);
    } else if (p.side == 0) {
      m_scratch.restarts.push_back({p.own_lo, p.own_hi, p.other_lo, p.other_hi});
    } else {
      m_scratch.restarts.push_back({p.other_lo, p.other_hi, p.own_lo, p.own_hi});
    }
  }
  // (Measured on compare (c) at 1 kHz, nodes of the restricted solves: at most twice the
  // budget 293k, at most the budget 307k, at most half 374k; no limit 306k, and as1's scene
  // (BodyScenes) then ran away: a fallback's tens of thousands of kept pairs restarted at once,
  // over budget, falling back again.)
  return m_scratch.restarts.size() <= k_partial_restarts * static_cast<std::size_t>(max_nodes);
}

Kept_proof_stage::Solve_pose* Kept_proof_stage::solves_of(Candidate& C) {
  if (C.solve_block < 0) {
    if (!m_kept.free_solve_blocks.empty()) {
      C.solve_block = m_kept.free_solve_blocks.back();
      m_kept.free_solve_blocks.pop_back();
    } else {
      C.solve_block = static_cast<int>(m_kept.solve_poses.size());
      m_kept.solve_poses.resize(m_kept.solve_poses.size() + k_kept_solves);
    }
  }
  return m_kept.solve_poses.data() + C.solve_block;
}

void Kept_proof_stage::release_solves(Candidate& C) {
  if (C.solve_block >= 0) m_kept.free_solve_blocks.push_back(C.solve_block);
  C.solve_block = -1;
  C.solve_count = 0;
}

void Kept_proof_stage::keep_proofs(Candidate& C, const Solve_pose& at, bool partial) {
  const std::vector<Gradient_proof>& proofs = m_solver.workspace().gradient_proofs();
  const std::vector<Bound_proof>& bounds = m_solver.workspace().bound_proofs();
  // Proofs past the memory limit are not kept (the candidate keeps its bound and reach, and is
  // solved again when they run out): what the pools' growth would take, at its most.
  auto growth = [](const auto& pool, std::size_t incoming) -> std::size_t {
    const std::size_t need = pool.size() + incoming;
    if (need <= pool.capacity()) return 0;
    return (std::max(need, 2 * pool.capacity()) - pool.capacity()) * sizeof(pool[0]);
  };
  const std::size_t more =
      growth(m_kept.proofs, proofs.size() + static_cast<std::size_t>(C.proof_count)) +
      growth(m_kept.bounds, bounds.size() + static_cast<std::size_t>(C.bound_count)) +
      (C.solve_block < 0 && m_kept.free_solve_blocks.empty() ? growth(m_kept.solve_poses, k_kept_solves) : 0);
  if (!fits(more)) {
    m_kept.proof_total -= C.proof_count;
    m_kept.bound_total -= C.bound_count;
    C.proof_count = C.bound_count = 0;
    release_solves(C);
    return;
  }
  // C's earlier proofs, kept (partial) or dropped: their range is read after the compaction
  // below, which keeps the order within each range.
  if (!partial) {
    m_kept.proof_total -= C.proof_count;
    m_kept.bound_total -= C.bound_count;
    C.proof_count = C.bound_count = 0;
  }
  // (Totals kept as counts change: summed over the candidates at every solve, they were a
  // fifth of a step's time against a mesh of thousands of candidate pairs.)
  const std::size_t live_proofs = proofs.size() + static_cast<std::size_t>(m_kept.proof_total);
  const std::size_t live_bounds = bounds.size() + static_cast<std::size_t>(m_kept.bound_total);
  const int counted_proofs = C.proof_count, counted_bounds = C.bound_count;
  // Ranges of re-solved or dropped candidates are stale: compact when they dominate, in place
  // (ranges slid down in the order they were written), so the pools keep their capacity.
  auto outgrows = [](const auto& pool, std::size_t incoming, long kept) {
    const std::size_t stale = pool.size() - std::min(pool.size(), static_cast<std::size_t>(kept));
    return pool.size() + incoming > pool.capacity() &&
           static_cast<double>(stale) >= k_compact_stale_share * static_cast<double>(pool.capacity());
  };
  if (m_kept.proofs.size() > k_compact_factor * live_proofs + k_compact_proofs ||
      m_kept.bounds.size() > k_compact_factor * live_bounds + k_compact_bounds ||
      outgrows(m_kept.proofs, proofs.size() + static_cast<std::size_t>(C.proof_count), m_kept.proof_total) ||
      outgrows(m_kept.bounds, bounds.size() + static_cast<std::size_t>(C.bound_count), m_kept.bound_total)) {
    m_kept.order.clear();
    for (int i = 0; i < static_cast<int>(m_candidates.size()); ++i) m_kept.order.push_back(i);
    auto compact = [&](auto& pool, int Candidate::*begin, int Candidate::*count) {
      std::sort(m_kept.order.begin(), m_kept.order.end(),
                [&](int x, int y) { return m_candidates[x].*begin < m_candidates[y].*begin; });
      int next = 0;
      for (const int i : m_kept.order) {
        Candidate& c = m_candidates[i];
        if (next < c.*begin)  // (copying to the left may overlap)
          std::copy(pool.begin() + c.*begin, pool.begin() + c.*begin + c.*count, pool.begin() + next);
        c.*begin = next;
        next += c.*count;
      }
      pool.resize(next);
    };
    compact(m_kept.proofs, &Candidate::proof_begin, &Candidate::proof_count);
    compact(m_kept.bounds, &Candidate::bound_begin, &Candidate::bound_count);
  }
  // The solves the kept proofs still refer to, renumbered in order, then this one.
  Solve_pose* kept = solves_of(C);
  std::array<int, k_kept_solves> renumber;
  renumber.fill(-1);
  int solves = 0;
  if (partial) {
    std::array<bool, k_kept_solves> used{};
    for (int i = 0; i < C.bound_count; ++i)
      if (m_scratch.keep_bound[i]) used[m_kept.bounds[C.bound_begin + i].solve] = true;
    for (int i = 0; i < C.proof_count; ++i)
      if (m_scratch.keep_proof[i]) used[m_kept.proofs[C.proof_begin + i].solve] = true;
    for (int k = 0; k < C.solve_count; ++k)
      if (used[k]) {
        renumber[k] = solves;
        kept[solves++] = kept[k];
      }
  }
  const int current = solves;
  kept[solves++] = at;
  C.solve_count = solves;
  const int old_proofs = C.proof_begin, old_bounds = C.bound_begin;
  C.proof_begin = static_cast<int>(m_kept.proofs.size());
  if (partial)
    for (int i = 0; i < C.proof_count; ++i)
      if (m_scratch.keep_proof[i]) {
        Kept_proof p = m_kept.proofs[old_proofs + i];  // (a copy: the pool may grow)
        p.solve = renumber[p.solve];
        m_kept.proofs.push_back(p);
      }
  for (const Gradient_proof& p : proofs) m_kept.proofs.push_back({p, current});
  C.proof_count = static_cast<int>(m_kept.proofs.size()) - C.proof_begin;
  C.bound_begin = static_cast<int>(m_kept.bounds.size());
  if (partial)
    for (int i = 0; i < C.bound_count; ++i)
      if (m_scratch.keep_bound[i]) {
        Kept_bound b = m_kept.bounds[old_bounds + i];
        b.solve = renumber[b.solve];
        m_kept.bounds.push_back(b);
      }
  for (const Bound_proof& b : bounds) m_kept.bounds.push_back({b, current});
  C.bound_count = static_cast<int>(m_kept.bounds.size()) - C.bound_begin;
  m_kept.proof_total += C.proof_count - counted_proofs;
  m_kept.bound_total += C.bound_count - counted_bounds;
  note_bytes();
}

}  // namespace extremal::internal
