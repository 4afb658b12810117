#include "algorithms/body_pair/Body_pair_tracker.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "algorithms/body_pair/internal/Ball_offset.h"
#include "algorithms/body_pair/internal/Body_pair_support.h"
#include "algorithms/body_pair/internal/Depth_monitor.h"
#include "algorithms/body_pair/internal/Kept_proof_stage.h"
#include "algorithms/body_pair/internal/Live_set.h"
#include "algorithms/body_pair/internal/Mesh_pair_stage.h"
#include "algorithms/body_pair/internal/Pair_context.h"
#include "algorithms/body_pair/internal/Pair_seeding.h"
#include "algorithms/body_pair/internal/Tuning.h"
#include "kernel/Error.h"

namespace extremal {

const char* to_string(Pair_status s) {
  switch (s) {
    case Pair_status::Tracking: return "tracking";
    case Pair_status::Contact: return "contact";
    case Pair_status::Penetrating: return "penetrating";
    case Pair_status::Boundary: return "boundary";
    case Pair_status::Farther: return "farther";
    case Pair_status::Fallback: return "fallback";
    case Pair_status::Uncertified: return "uncertified";
  }
  return "unknown";
}

const char* to_string(Reading_rule r) {
  switch (r) {
    case Reading_rule::None: return "none";
    case Reading_rule::Witness_off_face: return "witness_off_face";
    case Reading_rule::Normal_form_unsolved: return "normal_form_unsolved";
    case Reading_rule::Wandering_inside: return "wandering_inside";
    case Reading_rule::Normals_alike_in_contact: return "normals_alike_in_contact";
    case Reading_rule::Depth_normals_not_opposed: return "depth_normals_not_opposed";
    case Reading_rule::Apart_witness_inside: return "apart_witness_inside";
    case Reading_rule::Deeper_than_boxes: return "deeper_than_boxes";
    case Reading_rule::Edge_outside_wedge: return "edge_outside_wedge";
    case Reading_rule::Depth_not_reached_through_contact: return "depth_not_reached_through_contact";
  }
  return "unknown";
}

std::vector<Feature> features_of(const Body& body) {
  std::vector<Feature> f;
  if (body.is_point) f.push_back(Feature::point(Vec3::Zero()));
  for (const auto& face : body.faces) f.push_back(Feature::surface(face.surface));
  for (const auto& c : body.curves) f.push_back(Feature::curve(c));
  return f;
}

namespace {

using internal::Live;
using internal::box_diagonal;

bool same_pose(const Rigid_pose_3& x, const Rigid_pose_3& y) {
  return x.rotation() == y.rotation() && x.translation() == y.translation();
}

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

}  // namespace

// The stages and what the facade keeps between them. step() runs them in order; after each
// that changed the live set, settle() steps its new trackers and reads the tracked minimum.
struct Body_pair_tracker::Stages {
  Stages(std::shared_ptr<const Tracking_model> a, std::shared_ptr<const Tracking_model> b,
         const Body_pair_options& options, bool centres = true)
      : balls(std::move(a), std::move(b), centres), given(options),
        context(balls.inner(0), balls.inner(1), inner_options(balls, options)), live(context),
        seeding(context, live),
        candidates(std::make_unique<internal::Kept_proof_stage>(context, live, seeding)),
        depth(context, live, seeding) {
    seeding.attach(*candidates);
    if (internal::Mesh_pair_stage::takes(*context.model_a, *context.model_b))
      meshes = std::make_unique<internal::Mesh_pair_stage>(*context.model_a, *context.model_b,
                                                           context.options);
  }

  // The options the stages run with: a ball tracked as its centre is farther by its radius.
  static Body_pair_options inner_options(const internal::Ball_offset& balls,
                                         const Body_pair_options& options) {
    Body_pair_options o = options;
    if (o.threshold > 0.0) o.threshold += balls.radii();
    return o;
  }
  // The step of the stages' bodies (a ball's centre in its place).
  const Pair_report& step(double t, const Rigid_pose_3& X_WA, const Twist_3& V_A,
                          const Rigid_pose_3& X_WB, const Twist_3& V_B, double dt);
  // The step of the bodies as given (a ball as its centre, or deep, as its surface).
  const Pair_report& step_bodies(double t, const Rigid_pose_3& X_WA, const Twist_3& V_A,
                                 const Rigid_pose_3& X_WB, const Twist_3& V_B, double dt);
  bool is_farther(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) const;
  void start(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB);
  // Steps every pending tracker and reads the tracked minimum.
  void step_trackers();
  // step_trackers() if the live set changed since the last.
  void settle() {
    if (live.generation() != seen) step_trackers();
  }
  // The named stages of a step, in order.
  void monitor_depth(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB);
  void follow_candidates(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB);
  void resolve_start_overlap(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB);
  void solve_lost(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB);
  void audit(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB);
  void fill_report();

  // Balls tracked as their centres (internal/Ball_offset.h), and the options as given.
  internal::Ball_offset balls;
  Body_pair_options given;
  Pair_report given_report;
  // The bodies as given, tracked while a ball's centre lies inside the other body (made on
  // first use; `deep`: it answers).
  std::unique_ptr<Stages> whole;
  bool deep = false;
  // The last report made (made_any), at A's pose and the relative pose it was made at, and the
  // one carried from it while the bodies move as one.
  Pair_report made, carried;
  bool made_any = false;
  Rigid_pose_3 made_pose_a, made_relative;
  internal::Pair_context context;
  internal::Live_set live;
  internal::Pair_seeding seeding;
  std::unique_ptr<internal::Candidate_stage> candidates;
  internal::Depth_monitor depth;
  // Meshes and points only: the certified front in place of every stage above.
  std::unique_ptr<internal::Mesh_pair_stage> meshes;
  Pair_report report;
  long seen = -1;        // the live set's generation step_trackers last saw
  double best = HUGE_VAL;  // the tracked minimum it read
  bool started = false;
  bool have_pose = false;
  Rigid_pose_3 last_A, last_B;  // poses of the last step
  // This step's solve found the surfaces meeting (the candidate stage, or a lost step's solve)
  // and still no tracker holds a depth or contact: the report is the solver's.
  bool apart_unheld = false;
  bool meets_at_start = false;  // the start's solve found the surfaces crossing: this one,
  Distance_result start_solve;  // at this relative pose
  Rigid_pose_3 start_relative;
};

bool Body_pair_tracker::Stages::is_farther(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) const {
  const Body_pair_options& o = context.options;
  if (!(o.threshold > 0.0)) return false;
  return box_distance(transformed(context.model_a->box(), X_WA),
                      transformed(context.model_b->box(), X_WB)) > o.threshold;
}

void Body_pair_tracker::Stages::start(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) {
  live.kill_all();
  candidates->clear();
  started = true;
  depth.reset();
  const Distance_result g = context.global_solve(X_WA, X_WB);
  candidates->refresh(X_WA, X_WB, std::max(g.upper_bound, 0.0) + context.reach_margin());
  // The certified pair, should the broad phase have missed it (duplicates merge after the
  // first step).
  seeding.seed_from(g, X_WA, X_WB, std::numeric_limits<double>::infinity());
  meets_at_start = g.status == Distance_status::Intersecting;
  if (meets_at_start) {
    start_solve = g;
    start_relative = X_WA.inverse() * X_WB;
  }
  // Inside, the candidates reach across the depth.
  if (depth.seed_overlap(g, X_WA, X_WB, false))
    candidates->refresh(X_WA, X_WB, -context.solved.distance + context.reach_margin());
}

void Body_pair_tracker::Stages::step_trackers() {
  live.step_pending();
  best = live.best();
  seen = live.generation();
}

void Body_pair_tracker::Stages::monitor_depth(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) {
  const bool force = depth.shallower_pair(best);
  if (depth.check(X_WA, X_WB, best, force)) settle();
}

void Body_pair_tracker::Stages::follow_candidates(const Rigid_pose_3& X_WA,
                                                  const Rigid_pose_3& X_WB) {
  if (!std::isfinite(best)) return;  // (solve_lost re-seeds)
  candidates->update(X_WA, X_WB, best);
  settle();
  const double tol = context.options.contact_tolerance;
  if (best > tol) {
    // A pair certified to meet while every tracker read the bodies apart (the trackers on its
    // surfaces hold nothing): they are not apart. The whole pair is solved as one lost (the
    // hulls' depth where no tracker takes it), and a tracker reading apart is no answer.
    const bool meet = candidates->certify_apart(X_WA, X_WB, best);
    settle();
    if (meet) {
      const Distance_result g = context.global_solve(X_WA, X_WB);
      if (depth.seed_overlap(g, X_WA, X_WB, true)) ++context.stats.reseeds;  // (keeps g)
      settle();
      apart_unheld = !(best <= tol);
    }
    return;
  }
  // In contact every candidate pair gets a tracker. A pair seeded inside that reads deeper
  // than the depth is checked before it is reported (test
  // EdgeSlide.APegSlidOffABoxsCornerReadsTheShallowerDepth).
  const double depth_before = best;
  if (!candidates->seed_in_contact(X_WA, X_WB)) return;
  settle();
  if (depth_before < -tol && best < depth_before - context.depth_tolerance(depth_before) &&
      depth.check(X_WA, X_WB, best, true))
    settle();
}

void Body_pair_tracker::Stages::resolve_start_overlap(const Rigid_pose_3& X_WA,
                                                      const Rigid_pose_3& X_WB) {
  // Non-convex bodies whose surfaces crossed at the start: when none of the trackers seeded at
  // the common points (the start's and the candidates') found a penetration pair, the hulls'
  // may be one (Depth_monitor::seed_overlap). At the start's poses only.
  if (!meets_at_start) return;
  meets_at_start = false;
  if (!same_pose(context.relative, start_relative)) return;
  const double tol = context.options.contact_tolerance;
  if (!(best < -tol) && depth.seed_overlap(start_solve, X_WA, X_WB, true)) settle();
  // The surfaces cross here: a tracker reading apart is no answer (test
  // ProbeScenes.ABoxStartedAcrossASheetsBorderIsNotApart).
  if (!(best <= tol)) apart_unheld = true;
}

void Body_pair_tracker::Stages::solve_lost(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) {
  // Nothing on the bodies (witnesses left them, or trackers wandering in a deep overlap): the
  // certified solver seeds again, and its answer is reported while no tracker holds. The
  // penetrating trackers that hold nothing go first (they would pile up).
  const double tol = context.options.contact_tolerance;
  for (std::size_t k = 0; k < live.slots().size(); ++k) {
    const Live& L = live[static_cast<int>(k)];
    if (L.alive && !L.valid && internal::is_inside(L.regime)) live.kill(static_cast<int>(k));
  }
  const Distance_result g = context.global_solve(X_WA, X_WB);
  if (seeding.seed_from(g, X_WA, X_WB, std::numeric_limits<double>::infinity()))
    ++context.stats.reseeds;
  if (depth.seed_overlap(g, X_WA, X_WB, true)) ++context.stats.reseeds;
  step_trackers();
  // The surfaces cross by this step's solve: a tracker seeded at the common point that reads
  // apart (not converged: a point of each surface, near each other) is no answer.
  if (g.status == Distance_status::Intersecting && !(best <= tol)) apart_unheld = true;
}

void Body_pair_tracker::Stages::audit(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) {
  const int every = context.options.audit_every;
  if (every <= 0 || context.steps % every != 0) return;
  if (seeding.seed_from(context.global_solve(X_WA, X_WB), X_WA, X_WB, best)) {
    ++context.stats.reseeds;
    settle();
  }
}

void Body_pair_tracker::Stages::fill_report() {
  Pair_report& r = report;
  int held = -1, rejected = -1;
  double held_d = std::numeric_limits<double>::infinity(), rejected_d = held_d;
  for (std::size_t k = 0; k < live.slots().size(); ++k) {
    const Live& L = live[static_cast<int>(k)];
    if (!L.alive) continue;
    if (L.valid && L.result.distance < held_d) held_d = L.result.distance, held = static_cast<int>(k);
    if (!L.valid && L.stepped == context.steps && L.result.distance < rejected_d)
      rejected_d = L.result.distance, rejected = static_cast<int>(k);
  }
  const double tol = context.options.contact_tolerance;
  if (apart_unheld && held_d > tol) held = -1;
  context.stats.trackers = live.count();
  context.stats.candidates = candidates->size();
  // No tracker holds: the solver's answer of this step (a step whose trackers hold nothing
  // solves again).
  r.solved = held < 0;
  r.rejected_by = r.solved && rejected >= 0 ? live[rejected].rejected_by : Reading_rule::None;
  const internal::Solved& s = context.solved;
  const Track_result* tr = held >= 0 ? &live[held].result : nullptr;
  const int pa = tr ? live[held].pa : s.pa, pb = tr ? live[held].pb : s.pb;
  const Vec4& params = tr ? tr->params : s.params;
  r.distance = tr ? tr->distance : s.distance;
  r.point_a = tr ? tr->point_a : s.point_a;
  r.point_b = tr ? tr->point_b : s.point_b;
  r.normal = tr ? tr->normal : s.normal;
  r.degeneracy = tr ? tr->degeneracy : Degeneracy::None;
  r.feature_a = r.feature_b = r.edge_a = r.edge_b = -1;
  r.params.setZero();
  if (pa >= 0 && pb >= 0) {
    const int na = context.primitive(0, pa).feature.dimension();
    double qa[2] = {0, 0}, qb[2] = {0, 0};
    int da = 0, db = 0;
    r.feature_a = report_feature(*context.model_a, pa, params.data(), qa, r.edge_a, da);
    r.feature_b = report_feature(*context.model_b, pb, params.data() + na, qb, r.edge_b, db);
    for (int c = 0; c < da; ++c) r.params[c] = qa[c];
    for (int c = 0; c < db; ++c) r.params[da + c] = qb[c];
  }
  r.status = r.distance < -tol                                     ? Pair_status::Penetrating
             : r.distance <= tol                                   ? Pair_status::Contact
             : tr && tr->status == Track_status::Singular_fallback ? Pair_status::Fallback
             : tr && tr->status == Track_status::On_boundary       ? Pair_status::Boundary
                                                                   : Pair_status::Tracking;
  // Apart: the certification's bound of this step, or the solver's when it answered; a bound
  // below the budget (or none) is no certificate.
  r.lower_bound.reset();
  if (r.distance > tol) {
    double lower = -HUGE_VAL;
    if (context.certified_at == context.steps) lower = context.certified_lower;
    if (r.solved && s.step == context.steps) lower = std::max(lower, s.lower_bound);
    lower = std::min(lower, r.distance);
    if (lower > -HUGE_VAL) r.lower_bound = lower;
    if (!(lower >= internal::certified_floor(r.distance, context.options.tolerance)))
      r.status = Pair_status::Uncertified;
  }
}

Body_pair_tracker::Body_pair_tracker(const Body& a, const Body& b, const Body_pair_options& options)
    : Body_pair_tracker(std::make_shared<const Tracking_model>(a),
                        std::make_shared<const Tracking_model>(b), options) {}

Body_pair_tracker::Body_pair_tracker(std::shared_ptr<const Tracking_model> a,
                                     std::shared_ptr<const Tracking_model> b,
                                     const Body_pair_options& options) {
  EXTREMAL_PRECONDITION_MSG(options.own_basin_gap >= 0.0 && options.own_basin_gap < 1.0,
                            "Body_pair_options::own_basin_gap must be >= 0 and < 1");
  m = std::make_unique<Stages>(std::move(a), std::move(b), options);
}

Body_pair_tracker::~Body_pair_tracker() = default;
Body_pair_tracker::Body_pair_tracker(Body_pair_tracker&&) noexcept = default;
Body_pair_tracker& Body_pair_tracker::operator=(Body_pair_tracker&&) noexcept = default;

const Pair_statistics& Body_pair_tracker::statistics() const { return m->context.stats; }
const std::vector<Feature>& Body_pair_tracker::features_a() const { return m->balls.given_features(0); }
const std::vector<Feature>& Body_pair_tracker::features_b() const { return m->balls.given_features(1); }
const Tracking_model& Body_pair_tracker::model_a() const { return *m->balls.given(0); }
const Tracking_model& Body_pair_tracker::model_b() const { return *m->balls.given(1); }

void Body_pair_tracker::start(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) {
  if (m->meshes) {  // (the first step makes the front)
    m->meshes->reset();
    return;
  }
  if (!m->balls.any()) {
    m->start(X_WA, X_WB);
    return;
  }
  Rigid_pose_3 XA, XB;
  Twist_3 VA, VB;
  m->balls.place(0, X_WA, Twist_3{}, XA, VA);
  m->balls.place(1, X_WB, Twist_3{}, XB, VB);
  m->start(XA, XB);
}

const Pair_report& Body_pair_tracker::step(double t, const Rigid_pose_3& X_WA, const Twist_3& V_A,
                                           const Rigid_pose_3& X_WB, const Twist_3& V_B,
                                           double dt) {
  Stages& s = *m;
  // Bodies that moved as one since the report was made (their relative pose the same, to
  // rounding): it stands, carried along in the world, its bound less that rounding's motion.
  // Test BodyScenes.BodiesMovingAsOneAreComputedOnce.
  const Rigid_pose_3 relative = X_WA.inverse() * X_WB;
  const Tracking_model& A = *s.balls.given(0);
  const Tracking_model& B = *s.balls.given(1);
  if (s.made_any && s.made.status != Pair_status::Farther &&
      internal::near_pose(relative, s.made_relative,
                          std::max(box_diagonal(A.box()), box_diagonal(B.box())))) {
    const Rigid_pose_3 M = X_WA * s.made_pose_a.inverse();
    Pair_report& r = s.carried;
    r = s.made;
    r.time = t;
    r.point_a = M.apply_point(s.made.point_a);
    r.point_b = M.apply_point(s.made.point_b);
    r.normal = M.rotation() * s.made.normal;
    if (r.lower_bound)
      *r.lower_bound -= internal::approach_bound(A.box(), B.box(), s.made_relative, relative).closer;
    return r;
  }
  s.made = s.step_bodies(t, X_WA, V_A, X_WB, V_B, dt);
  s.made_any = true;
  s.made_pose_a = X_WA;
  s.made_relative = relative;
  return s.made;
}

const Pair_report& Body_pair_tracker::Stages::step_bodies(double t, const Rigid_pose_3& X_WA,
                                                          const Twist_3& V_A,
                                                          const Rigid_pose_3& X_WB,
                                                          const Twist_3& V_B, double dt) {
  Stages& s = *this;
  if (!s.balls.any()) return s.step(t, X_WA, V_A, X_WB, V_B, dt);
  // A ball deep in the other body: its surface tracked, until its centre is back out by a
  // fraction of its radius (then the centre's stages start again).
  const double radii = s.balls.radii();
  if (s.deep) {
    const Pair_report& r = s.whole->step(t, X_WA, V_A, X_WB, V_B, dt);
    if (!(r.distance > -(1.0 - internal::k_ball_leaves) * radii)) return r;
    s.deep = false;
    s.started = false;
  }
  // A ball as its centre: its pair's stages on the centre, certified at the given budget.
  Rigid_pose_3 XA, XB;
  Twist_3 VA, VB;
  s.balls.place(0, X_WA, V_A, XA, VA);
  s.balls.place(1, X_WB, V_B, XB, VB);
  s.context.options.tolerance = s.balls.inner_budget(s.given.tolerance, X_WA, X_WB);
  const Pair_report& inner = s.step(t, XA, VA, XB, VB, dt);
  if (inner.status != Pair_status::Farther && !(inner.distance > internal::k_ball_enters * radii)) {
    if (!s.whole) s.whole = std::make_unique<Stages>(s.balls.given(0), s.balls.given(1), s.given, false);
    s.whole->started = false;
    s.deep = true;
    return s.whole->step(t, X_WA, V_A, X_WB, V_B, dt);
  }
  s.balls.report(inner, s.given, X_WA, X_WB, s.given_report);
  return s.given_report;
}

const Pair_report& Body_pair_tracker::Stages::step(double t, const Rigid_pose_3& X_WA,
                                                   const Twist_3& V_A, const Rigid_pose_3& X_WB,
                                                   const Twist_3& V_B, double dt) {
  Stages& s = *this;
  internal::Pair_context& c = s.context;
  Pair_report& r = s.report;
  r.time = t;
  if (s.is_farther(X_WA, X_WB)) {
    r.status = Pair_status::Farther;
    r.distance = box_distance(transformed(c.model_a->box(), X_WA), transformed(c.model_b->box(), X_WB));
    r.lower_bound = r.distance;  // (the boxes hold the bodies)
    r.point_a = r.point_b = r.normal = Vec3::Zero();
    r.feature_a = r.feature_b = r.edge_a = r.edge_b = -1;
    r.degeneracy = Degeneracy::None;
    r.solved = false;
    r.rejected_by = Reading_rule::None;
    c.stats.trackers = 0;
    c.stats.candidates = 0;
    s.started = false;  // re-seed when the pair comes back within the threshold
    s.have_pose = false;
    if (s.meshes) s.meshes->reset();
    return r;
  }
  // Nothing moved since the last step: the same answer.
  if (s.started && s.have_pose && same_pose(X_WA, s.last_A) && same_pose(X_WB, s.last_B)) return r;
  if (s.meshes) {
    ++c.steps;
    ++c.stats.computed_steps;
    s.meshes->step(X_WA, X_WB, r, c.stats);
    s.started = s.have_pose = true;
    s.last_A = X_WA;
    s.last_B = X_WB;
    return r;
  }
  c.t = t;
  c.dt = dt;
  c.X_WA = &X_WA;
  c.X_WB = &X_WB;
  c.V_A = &V_A;
  c.V_B = &V_B;
  ++c.steps;
  ++c.stats.computed_steps;
  s.apart_unheld = false;
  c.relative = X_WA.inverse() * X_WB;
  if (!s.started) {
    s.start(X_WA, X_WB);
    c.previous_relative = c.relative;
  }
  s.step_trackers();
  s.monitor_depth(X_WA, X_WB);
  s.follow_candidates(X_WA, X_WB);
  s.resolve_start_overlap(X_WA, X_WB);
  if (!std::isfinite(s.best)) s.solve_lost(X_WA, X_WB);
  s.live.merge_duplicates();
  s.settle();
  s.audit(X_WA, X_WB);
  // No tracker holds at the end of the step while the solver's last answer is an earlier
  // step's: solved again, so that no row repeats an earlier step's answer (test
  // ProbeScenes.AScrewPushedThroughAPlaneIsApartOnceOut).
  if (c.solved.step != c.steps && !s.live.any_valid()) s.solve_lost(X_WA, X_WB);
  s.fill_report();
  s.depth.note_report(r, X_WA);
  c.previous_relative = c.relative;
  s.last_A = X_WA;
  s.last_B = X_WB;
  s.have_pose = true;
  return r;
}

}  // namespace extremal
