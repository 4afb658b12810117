#include "algorithms/body_pair/internal/Stage_engine.h"

#include <chrono>
#include <cmath>
#include <limits>

#include "algorithms/body_pair/internal/Body_pair_support.h"
#include "algorithms/body_pair/internal/Kept_proof_stage.h"

namespace extremal::internal {

namespace {

// Report ids of a primitive: its Body face index (curves after the faces, triangles after
// them as in the global solver), the B-rep edge, and its parameters on that face (`dim` of
// them).
int report_feature(const Tracking_model& m, int p, const double* q, double* out, int& edge,
                   int& dim) {
  const Primitive& P = m.primitives()[p];
  const int nf = static_cast<int>(m.body().faces.size());
  edge = -1;
  dim = P.feature.dimension();
  for (int c = 0; c < dim; ++c) out[c] = q[c];
  switch (P.kind) {
    case Primitive_kind::Point: return 0;
    case Primitive_kind::Face: return P.index;
    case Primitive_kind::Triangle: return nf + P.index;
    case Primitive_kind::Curve: return nf + P.index;
    case Primitive_kind::Edge:
    case Primitive_kind::Mesh_edge: {
      if (P.kind == Primitive_kind::Edge) edge = P.index;
      int count = 0;
      const Edge_on_face* faces = m.faces_of(p, count);
      if (count == 0) return -1;
      faces[0].map(q[0], out);
      dim = 2;
      const Primitive& F = m.primitives()[faces[0].face];
      return F.kind == Primitive_kind::Triangle ? nf + F.index : F.index;
    }
  }
  return -1;
}

bool same_pose(const Rigid_pose_3& x, const Rigid_pose_3& y) {
  return x.rotation() == y.rotation() && x.translation() == y.translation();
}

}  // namespace

Stage_engine::Stage_engine(std::shared_ptr<const Tracking_model> a,
                           std::shared_ptr<const Tracking_model> b, const Body_pair_options& options)
    : m_context(std::move(a), std::move(b), options), m_solver(m_context), m_live(m_context),
      m_seeding(m_context, m_solver, m_live),
      m_candidates(std::make_unique<Kept_proof_stage>(m_context, m_solver, m_live, m_seeding)),
      m_depth(m_context, m_solver, m_live, m_seeding) {
  m_seeding.attach(*m_candidates);
}

void Stage_engine::add_statistics(Pair_statistics& s) const {
  add_counters(s, m_live.statistics());
  add_counters(s, m_candidates->statistics());
  s.seeds += m_seeding.seeds() + m_depth.seeds();
  s.audits += m_solver.solves();
  s.reseeds += static_cast<int>(m_reseeds);
  s.trackers = m_live.count();
  s.memory_limited_steps += m_memory_limited;
  s.candidates = m_candidates->size();
}

void Stage_engine::start(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) {
  m_live.kill_all();
  m_candidates->clear();
  m_started = true;
  m_depth.reset();
  const Distance_result g = m_solver.global(X_WA, X_WB);
  m_candidates->refresh(X_WA, X_WB, std::max(g.upper_bound, 0.0) + m_context.reach_margin());
  // The certified pair, should the broad phase have missed it (duplicates merge after the
  // first step).
  m_seeding.seed_from(g, X_WA, X_WB, std::numeric_limits<double>::infinity());
  m_start.pending = g.status == Distance_status::Intersecting;
  if (m_start.pending) {
    m_start.solve = g;
    m_start.relative = X_WA.inverse() * X_WB;
  }
  // Inside, the candidates reach across the depth.
  if (m_depth.seed_overlap(g, X_WA, X_WB, false))
    m_candidates->refresh(X_WA, X_WB, -m_depth.solved().distance + m_context.reach_margin());
}

void Stage_engine::step_trackers() {
  m_live.step_pending();
  m_tracked.best = m_live.best();
  m_tracked.seen = m_live.generation();
}

void Stage_engine::monitor_depth() {
  const bool force = m_depth.shallower_pair(m_tracked.best);
  m_depth.check(*m_context.now.X_WA, *m_context.now.X_WB, m_tracked.best, force);
}

void Stage_engine::update_candidates() {
  m_notes.candidates = std::isfinite(m_tracked.best);
  if (!m_notes.candidates) return;  // (solve_if_lost re-seeds)
  m_candidates->update(*m_context.now.X_WA, *m_context.now.X_WB, m_tracked.best);
}

void Stage_engine::certify_apart() {
  // Apart or not is decided here, once, for this step's candidate stages.
  m_notes.apart = m_notes.candidates && m_tracked.best > m_context.options.contact_tolerance;
  if (m_candidates->over_limit()) {
    certify_by_global();
    return;
  }
  if (m_notes.apart)
    m_notes.certificate = m_candidates->certify_apart(*m_context.now.X_WA, *m_context.now.X_WB, m_tracked.best);
}

void Stage_engine::check_nested() {
  // The surfaces' certified distance is the bodies' only while neither holds the other: a
  // body found inside is solved as lost (the hulls' depth where no tracker takes it), and a
  // tracker reading apart is no answer.
  if (!m_notes.apart || !m_depth.nested(*m_context.now.X_WA, *m_context.now.X_WB,
                                        m_notes.certificate.lower))
    return;
  m_notes.certificate = {};
  solve_lost();
  m_notes.meets = true;
}

void Stage_engine::certify_by_global() {
  // (Without a tracked minimum solve_if_lost solves.) Test
  // BodyScenes.APairOverItsMemoryLimitIsCertifiedByTheGlobalSolver.
  if (!m_notes.candidates) return;
  const Rigid_pose_3& X_WA = *m_context.now.X_WA;
  const Rigid_pose_3& X_WB = *m_context.now.X_WB;
  const Distance_result g = m_solver.global(X_WA, X_WB);
  if (m_seeding.seed_from(g, X_WA, X_WB, m_tracked.best)) ++m_reseeds;
  if (!m_notes.apart) return;
  m_notes.certificate.meet =
      g.status == Distance_status::Intersecting || g.status == Distance_status::Touching;
  m_notes.certificate.lower = g.lower_bound;
}

void Stage_engine::solve_where_met() {
  // A pair certified to meet while every tracker read the bodies apart (the trackers on its
  // surfaces hold nothing): they are not apart. The whole pair is solved as one lost (the
  // hulls' depth where no tracker takes it), and a tracker reading apart is no answer.
  if (!m_notes.apart || !m_notes.certificate.meet) return;
  const Distance_result g = m_solver.global(*m_context.now.X_WA, *m_context.now.X_WB);
  if (m_depth.seed_overlap(g, *m_context.now.X_WA, *m_context.now.X_WB, true)) ++m_reseeds;  // (keeps g)
  m_notes.meets = true;
}

void Stage_engine::check_held() {
  if (!m_notes.meets) return;
  m_notes.meets = false;
  if (!(m_tracked.best <= m_context.options.contact_tolerance)) m_notes.unheld = true;
}

void Stage_engine::seed_in_contact() {
  // In contact every candidate pair gets a tracker.
  if (m_notes.apart || !m_notes.candidates) return;
  m_notes.depth_before = m_tracked.best;
  m_notes.seeded_in_contact = m_candidates->seed_in_contact(*m_context.now.X_WA, *m_context.now.X_WB);
}

void Stage_engine::check_contact_depth() {
  // A pair seeded inside that reads deeper than the depth is checked before it is reported
  // (test EdgeSlide.APegSlidOffABoxsCornerReadsTheShallowerDepth).
  if (!m_notes.seeded_in_contact) return;
  const double before = m_notes.depth_before, tol = m_context.options.contact_tolerance;
  if (before < -tol && m_tracked.best < before - m_context.depth_tolerance(before))
    m_depth.check(*m_context.now.X_WA, *m_context.now.X_WB, m_tracked.best, true);
}

void Stage_engine::resolve_start_overlap() {
  // Non-convex bodies whose surfaces crossed at the start: when none of the trackers seeded at
  // the common points (the start's and the candidates') found a penetration pair, the hulls'
  // may be one (Depth_monitor::seed_overlap). At the start's poses only. The surfaces cross
  // there: a tracker reading apart is no answer (test
  // ProbeScenes.ABoxStartedAcrossASheetsBorderIsNotApart).
  if (!m_start.pending) return;
  m_start.pending = false;
  if (!same_pose(m_context.now.relative, m_start.relative)) return;
  if (!(m_tracked.best < -m_context.options.contact_tolerance))
    m_depth.seed_overlap(m_start.solve, *m_context.now.X_WA, *m_context.now.X_WB, true);
  m_notes.meets = true;
}

void Stage_engine::solve_if_lost() {
  if (!std::isfinite(m_tracked.best)) solve_lost();
}

void Stage_engine::solve_lost() {
  // Nothing on the bodies (witnesses left them, or trackers wandering in a deep overlap): the
  // certified solver seeds again, and its answer is reported while no tracker holds. The
  // penetrating trackers that hold nothing go first (they would pile up).
  for (std::size_t k = 0; k < m_live.slots().size(); ++k) {
    const Live& L = m_live[static_cast<int>(k)];
    if (L.alive && !L.valid && is_inside(L.regime)) m_live.kill(static_cast<int>(k));
  }
  const Rigid_pose_3& X_WA = *m_context.now.X_WA;
  const Rigid_pose_3& X_WB = *m_context.now.X_WB;
  const Distance_result g = m_solver.global(X_WA, X_WB);
  if (m_seeding.seed_from(g, X_WA, X_WB, std::numeric_limits<double>::infinity())) ++m_reseeds;
  if (m_depth.seed_overlap(g, X_WA, X_WB, true)) ++m_reseeds;
  // The bodies overlap by this step's solve (the surfaces cross, or it kept a depth: one holds
  // the other): a tracker that reads them apart is no answer (a tracker seeded at the common
  // point, not converged; a nested sheet's pair; test
  // ProbeScenes.ASheetInsideASolidStandingStillReadsPenetrating).
  const Solved& s = m_depth.solved();
  if (g.status == Distance_status::Intersecting ||
      (s.step == m_context.now.steps && s.distance < -m_context.options.contact_tolerance))
    m_notes.meets = true;
}

void Stage_engine::merge_duplicates() { m_live.merge_duplicates(); }

void Stage_engine::audit() {
  const int every = m_context.options.audit_every;
  if (every <= 0 || m_context.now.steps % every != 0) return;
  const auto start = std::chrono::steady_clock::now();
  const Distance_result g = m_solver.global(*m_context.now.X_WA, *m_context.now.X_WB);
  if (m_seeding.seed_from(g, *m_context.now.X_WA, *m_context.now.X_WB, m_tracked.best)) ++m_reseeds;
  m_notes.audit_us +=
      std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
}

void Stage_engine::check_late_depth() {
  // A pair whose surfaces do not meet reads no depth unless a closed body holds the other; a
  // tracker seeded by a later stage (a closer basin behind a sheet) reads one only once
  // Depth_monitor::check confirms it, as monitor_depth does the step's first reading (test
  // ProbeScenes.ASheetThroughAPlaneAndOutReadsItsDistanceNotADepth).
  if (m_context.kind.solid_or_point(0) && m_context.kind.solid_or_point(1)) return;
  if (m_tracked.best < -m_context.options.contact_tolerance)
    m_depth.check(*m_context.now.X_WA, *m_context.now.X_WB, m_tracked.best, false);
}

void Stage_engine::solve_if_unheld() {
  // No tracker holds at the end of the step while the solver's last answer is an earlier
  // step's: solved again, so that no row repeats an earlier step's answer (test
  // ProbeScenes.AScrewPushedThroughAPlaneIsApartOnceOut).
  if (m_depth.solved().step != m_context.now.steps && !m_live.any_valid()) solve_lost();
}

const Pair_answer& Stage_engine::step(const Pair_step& step) {
  Pair_context& c = m_context;
  c.now.t = step.t;
  c.now.dt = step.dt;
  c.now.X_WA = &step.X_WA;
  c.now.X_WB = &step.X_WB;
  c.now.V_A = &step.V_A;
  c.now.V_B = &step.V_B;
  c.now.budget = step.budget;
  ++c.now.steps;
  m_notes = {};
  c.now.relative = step.X_WA.inverse() * step.X_WB;
  if (!m_started) {
    start(step.X_WA, step.X_WB);
    c.now.previous_relative = c.now.relative;
  }
  // The stages of a step, in order; after each, step_trackers() if it changed the live set.
  static constexpr Stage k_stages[] = {
      &Stage_engine::monitor_depth,         &Stage_engine::update_candidates,
      &Stage_engine::certify_apart,         &Stage_engine::check_nested,
      &Stage_engine::solve_where_met,
      &Stage_engine::check_held,            &Stage_engine::seed_in_contact,
      &Stage_engine::check_contact_depth,   &Stage_engine::resolve_start_overlap,
      &Stage_engine::check_held,            &Stage_engine::solve_if_lost,
      &Stage_engine::check_held,            &Stage_engine::merge_duplicates,
      &Stage_engine::audit,                 &Stage_engine::solve_if_unheld,
      &Stage_engine::check_late_depth,      &Stage_engine::check_held,
  };
  step_trackers();
  for (const Stage stage : k_stages) {
    (this->*stage)();
    if (m_live.generation() != m_tracked.seen) step_trackers();
  }
  make_answer();
  if (!c.kind.has_inside()) unsigned_answer();
  m_depth.note_answer(m_answer, step.X_WA);
  c.now.previous_relative = c.now.relative;
  return m_answer;
}

void Stage_engine::make_answer() {
  Pair_answer& r = m_answer;
  int held = -1, rejected = -1;
  double held_d = std::numeric_limits<double>::infinity(), rejected_d = held_d;
  for (std::size_t k = 0; k < m_live.slots().size(); ++k) {
    const Live& L = m_live[static_cast<int>(k)];
    if (!L.alive) continue;
    if (L.valid && L.result.distance < held_d) held_d = L.result.distance, held = static_cast<int>(k);
    if (!L.valid && L.stepped == m_context.now.steps && L.result.distance < rejected_d)
      rejected_d = L.result.distance, rejected = static_cast<int>(k);
  }
  const double tol = m_context.options.contact_tolerance;
  if (m_notes.unheld && held_d > tol) held = -1;
  // No tracker holds: the solver's answer of this step (a step whose trackers hold nothing
  // solves again).
  const bool solved = held < 0;
  r.source = solved ? Reading_source::Solved : Reading_source::Tracked;
  r.rejected_by = solved && rejected >= 0 ? m_live[rejected].rejected_by : Reading_rule::None;
  const Solved& s = m_depth.solved();
  const Track_result* tr = held >= 0 ? &m_live[held].result : nullptr;
  const int pa = tr ? m_live[held].pa : s.pa, pb = tr ? m_live[held].pb : s.pb;
  const Vec4& params = tr ? tr->params : s.params;
  r.distance = tr ? tr->distance : s.distance;
  r.point_a = tr ? tr->point_a : s.point_a;
  r.point_b = tr ? tr->point_b : s.point_b;
  r.normal = tr ? tr->normal : s.normal;
  r.degeneracy = tr ? tr->degeneracy : Degeneracy::None;
  r.shape = tr && tr->status == Track_status::Singular_fallback ? Reading_shape::Fallback
            : tr && tr->status == Track_status::On_boundary     ? Reading_shape::Boundary
                                                                : Reading_shape::Interior;
  r.feature_a = r.feature_b = r.edge_a = r.edge_b = -1;
  r.params.setZero();
  if (pa >= 0 && pb >= 0) {
    const int na = m_context.primitive(0, pa).feature.dimension();
    double qa[2] = {0, 0}, qb[2] = {0, 0};
    int da = 0, db = 0;
    r.feature_a = report_feature(*m_context.model_a, pa, params.data(), qa, r.edge_a, da);
    r.feature_b = report_feature(*m_context.model_b, pb, params.data() + na, qb, r.edge_b, db);
    for (int c = 0; c < da; ++c) r.params[c] = qa[c];
    for (int c = 0; c < db; ++c) r.params[da + c] = qb[c];
  }
  // The certification's bound of this step, or the solver's when it solved at this step (its
  // bound holds whatever reading is reported: a tracker it seeded this step reads no
  // certificate of its own; test Overlap.APointThroughASheetReadsItsUnsignedDistance).
  double lower = m_notes.certificate.lower;
  if (s.step == m_context.now.steps) lower = std::max(lower, s.lower_bound);
  r.lower_bound.reset();
  if (lower > -HUGE_VAL) r.lower_bound = lower;
  r.memory_limited = m_candidates->over_limit();
  if (r.memory_limited) ++m_memory_limited;
}

void Stage_engine::unsigned_answer() {
  // A pair without an inside reads no depth: a tracker behind a surface here means the bodies
  // meet (Depth_monitor::check found them meeting at this step, else dropped the pair), and
  // the row is 0 at a point where they meet (the reading's A witness when none is known).
  // Test Overlap.ACurveThroughASheetIsUnsignedAndZeroWhileItPiercesIt.
  Pair_answer& r = m_answer;
  if (!(r.distance < 0.0)) return;
  Vec3 x = r.point_a;
  m_depth.meeting_point(*m_context.now.X_WA, x);
  r.distance = 0.0;
  r.point_a = r.point_b = x;
}

}  // namespace extremal::internal
