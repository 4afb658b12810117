#include "algorithms/Body_pair_tracker.h"

#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <new>

#include "algorithms/Triangle_distance.h"

namespace extremal {

const char* to_string(Pair_status s) {
  switch (s) {
    case Pair_status::Tracking: return "tracking";
    case Pair_status::Contact: return "contact";
    case Pair_status::Penetrating: return "penetrating";
    case Pair_status::Boundary: return "boundary";
    case Pair_status::Farther: return "farther";
    case Pair_status::Fallback: return "fallback";
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

using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, int,
                                                      CGAL::Box_intersection_d::ID_FROM_BOX_ADDRESS>;

std::uint64_t pair_key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}
int key_a(std::uint64_t k) { return static_cast<int>(k >> 32); }
int key_b(std::uint64_t k) { return static_cast<int>(k & 0xffffffffu); }

Bbox_3 inflate(const Bbox_3& b, double r) {
  return Bbox_3(b.xmin() - r, b.ymin() - r, b.zmin() - r, b.xmax() + r, b.ymax() + r, b.zmax() + r);
}

double diagonal(const Bbox_3& b) {
  return std::sqrt((b.xmax() - b.xmin()) * (b.xmax() - b.xmin()) +
                   (b.ymax() - b.ymin()) * (b.ymax() - b.ymin()) +
                   (b.zmax() - b.zmin()) * (b.zmax() - b.zmin()));
}

bool same_pose(const Rigid_pose_3& x, const Rigid_pose_3& y) {
  return x.rotation() == y.rotation() && x.translation() == y.translation();
}

bool near_pose(const Rigid_pose_3& x, const Rigid_pose_3& y, double length) {
  return (x.rotation() - y.rotation()).cwiseAbs().maxCoeff() <= 1e-14 &&
         (x.translation() - y.translation()).cwiseAbs().maxCoeff() <= 1e-14 * length;
}

// The relative motion from X0 to X1 (poses X_AB: B's frame in A's) for a primitive of A
// (body-frame box box_a) and one of B (box_b): the largest displacement of a point of B's box
// in A's frame (move_b) and of A's box in B's frame (move_a), and how much closer it can have
// brought the two, the smaller of those. Over the ball (c, r) that holds a box,
// |(R1 - R0) p + t1 - t0| <= |(R1 - R0) c + t1 - t0| + |R1 - R0|_F r. (Distances between
// rigid placements depend on the relative pose only, and change by at most the largest
// displacement of either side.)
struct Approach {
  double move_a = 0.0, move_b = 0.0, closer = 0.0;
};
Approach approach_bound(const Bbox_3& box_a, const Bbox_3& box_b, const Rigid_pose_3& X0,
                        const Rigid_pose_3& X1) {
  const Mat3 dR = X1.rotation() - X0.rotation();
  const double spin = dR.norm();  // Frobenius, >= the spectral norm
  const Vec3 ca(0.5 * (box_a.xmin() + box_a.xmax()), 0.5 * (box_a.ymin() + box_a.ymax()),
                0.5 * (box_a.zmin() + box_a.zmax()));
  const Vec3 cb(0.5 * (box_b.xmin() + box_b.xmax()), 0.5 * (box_b.ymin() + box_b.ymax()),
                0.5 * (box_b.zmin() + box_b.zmax()));
  const double ra = 0.5 * diagonal(box_a), rb = 0.5 * diagonal(box_b);
  const Vec3& t0 = X0.translation();
  const Vec3& t1 = X1.translation();
  const double move_b = (dR * cb + (t1 - t0)).norm() + spin * rb;
  // A in B's frame: X_BA = (R^T, -R^T t).
  const Vec3 dt_inverse = X0.rotation().transpose() * t0 - X1.rotation().transpose() * t1;
  const double move_a = (dR.transpose() * ca + dt_inverse).norm() + spin * ra;
  // Rounding of these products: a few ulps of the lengths involved.
  const double size = ca.norm() + ra + cb.norm() + rb + t0.norm() + t1.norm();
  const double rounding = 16.0 * std::numeric_limits<double>::epsilon() * size;
  Approach m;
  m.move_a = move_a + rounding;
  m.move_b = move_b + rounding;
  m.closer = std::min(m.move_a, m.move_b);
  return m;
}

// A pair's restricted solve is cut off at least this many steps' worth of the pair's relative
// motion above the tracked minimum, so that its certified lower bound clears the next steps'
// checks without a solve; nothing found below the cutoff costs little, and the next solve of
// such a pair reaches k_slack_growth times higher (a far pair settles at its own minimum).
constexpr double k_slack_steps = 8.0;
constexpr double k_slack_growth = 4.0;
// The broad phase reaches this fraction of the margin farther than it must, so that it runs
// again only once the relative motion since has used that up (between runs the candidate set
// holds some pairs beyond the reach, whose checks cost little).
constexpr double k_broad_extra = 0.5;
// Trim-edge set-asides of a usual restricted solve must outlast this many steps' motion.
constexpr double k_reach_steps = 2.0;
// A proving solve (see check_vacated) is cut off this many steps' motion above the tracked
// minimum: higher, the pairs near a trim edge need deeper splits to clear it. Measured on
// scenario (c) of bench/compare at 1 kHz (sub-patch nodes of the restricted solves): 2 steps
// 442k, 1 step 468k, 4 steps 523k, 8 steps 794k, no proving solve 486k.
constexpr double k_proving_steps = 2.0;
// A crease solve (see check_vacated) is cut off this fraction of the broad-phase margin above
// the tracked minimum, and sets sub-patch pairs aside only when their gradient proof lasts as
// much relative motion: higher, the sub-patch pairs straddling the cutoff (where the gradient
// is small) cost more; lower, the solves come more often. Measured on scenario (b) of
// bench/compare (sub-patch nodes of the restricted solves, corrections rows), since the kept
// proofs re-check bounds: an eighth 179k / 43.9k / 18.1k nodes at 10 kHz / 1 kHz / 100 Hz,
// a quarter 243k / 49.4k / 17.3k, a sixteenth 152k / 44.7k / 18.9k, a half 372k / 62.8k.
// (Before the kept proofs, callgrind had a quarter beat an eighth at 1 kHz.) Its node budget
// (100: more solves fall back, 497k nodes at 10 kHz): spent, the solve still leaves the bound
// it reached, or falls back to the usual solve.
constexpr double k_crease_fraction = 0.125;
constexpr int k_crease_nodes = 200;
// A tracked pair carries a crease only when its tracker's normalised errors (sines of the
// angles off stationarity) along its free parameters are below this: the distance it is above
// its minimum is then about d e^2 / 2, far below the seeding tolerance.
constexpr double k_converged_error = 1e-6;

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

bool closed_form_pair(const Primitive& a, const Primitive& b) {
  const bool ta = a.kind == Primitive_kind::Triangle, tb = b.kind == Primitive_kind::Triangle;
  return (ta && (tb || b.kind == Primitive_kind::Point)) || (tb && a.kind == Primitive_kind::Point);
}

void triangle_corners(const Tracking_model& m, const Primitive& p, const Rigid_pose_3& X, Vec3 out[3]) {
  const auto& tri = m.body().mesh.triangles[p.index];
  for (int k = 0; k < 3; ++k) out[k] = X.apply_point(to_vec3(m.body().mesh.vertices[tri[k]]));
}

// Descent direction of |own - other|^2 / 2 along the parameters of a surface primitive at q.
void surface_descent(const Feature& f, const Rigid_pose_3& X, const double* q, const Vec3& other,
                     double g[2], double scale[2]) {
  Feature_point fp;
  evaluate_feature(f, X, q, fp, 1);
  const Vec3 d = fp.p - other;
  for (int k = 0; k < 2; ++k) {
    g[k] = -d.dot(fp.d[k]);
    scale[k] = d.norm() * fp.d[k].norm();
  }
}

}  // namespace

struct Body_pair_tracker::Broad_scratch {
  std::vector<Box> boxes_a, boxes_b;
};

Body_pair_tracker::Body_pair_tracker(const Body& a, const Body& b, const Body_pair_options& options)
    : Body_pair_tracker(std::make_shared<const Tracking_model>(a),
                        std::make_shared<const Tracking_model>(b), options) {}

Body_pair_tracker::Body_pair_tracker(std::shared_ptr<const Tracking_model> a,
                                     std::shared_ptr<const Tracking_model> b,
                                     const Body_pair_options& options)
    : m_model_a(std::move(a)), m_model_b(std::move(b)), m_options(options),
      m_features_a(features_of(m_model_a->body())), m_features_b(features_of(m_model_b->body())),
      m_scratch(std::make_unique<Broad_scratch>()) {
  m_live.reserve(64);
  m_free.reserve(64);
}

Body_pair_tracker::~Body_pair_tracker() = default;
Body_pair_tracker::Body_pair_tracker(Body_pair_tracker&&) noexcept = default;

double Body_pair_tracker::reach_margin() const {
  if (m_options.broad_margin > 0.0) return m_options.broad_margin;
  return 0.02 * std::min(diagonal(m_model_a->box()), diagonal(m_model_b->box()));
}

bool Body_pair_tracker::is_farther(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) const {
  if (!(m_options.threshold > 0.0)) return false;
  return box_distance(transformed(m_model_a->box(), X_WA), transformed(m_model_b->box(), X_WB)) >
         m_options.threshold;
}

int Body_pair_tracker::add_live(int pa, int pb, const Vec4& params) {
  int k;
  if (!m_free.empty()) {
    k = m_free.back();
    m_free.pop_back();
  } else {
    k = static_cast<int>(m_live.size());
    m_live.emplace_back();
  }
  Live& L = m_live[k];
  const Primitive& A = m_model_a->primitives()[pa];
  const Primitive& B = m_model_b->primitives()[pb];
  L.pa = pa;
  L.pb = pb;
  L.alive = true;
  L.valid = false;
  L.stepped = -1;
  L.through_contact = false;
  L.closed_form = closed_form_pair(A, B);
  if (!L.closed_form) L.tracker = Extremal_tracker(A.feature, B.feature, params, m_options.tracker);
  return k;
}

void Body_pair_tracker::kill(int k) {
  m_live[k].alive = false;
  m_free.push_back(k);
}

namespace {

// A global result's parameters on a primitive (the global solver's triangles are degree 1 x 1
// patches with corners p0, p2 | p1, p2: (u, v) there is (u (1 - v), v) here).
void params_from_global(const Primitive& p, const std::array<double, 2>& q, double* out) {
  if (p.kind == Primitive_kind::Triangle) {
    out[0] = q[0] * (1.0 - q[1]);
    out[1] = q[1];
    return;
  }
  for (int k = 0; k < p.feature.dimension(); ++k) out[k] = q[k];
}

// Sampled closest pair of two features, polished by Newton at rest (pairs the global solver
// has no element for: mesh edges).
// How far parameters sit from the middle of their domain (0 at the centre, 1 at a corner).
double off_centre(const Feature& f, const double* p) {
  double s = 0.0;
  for (int i = 0; i < f.dimension(); ++i) {
    const double mid = 0.5 * (f.lower(i) + f.upper(i)), half = 0.5 * (f.upper(i) - f.lower(i));
    if (half > 0.0) s += ((p[i] - mid) / half) * ((p[i] - mid) / half);
  }
  return s;
}

Vec4 sampled_seed(const Feature& A, const Rigid_pose_3& X_WA, const Feature& B,
                  const Rigid_pose_3& X_WB, int n = 8) {
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

void Body_pair_tracker::prefer_central(int pa, int pb, const Rigid_pose_3& X_WA,
                                       const Rigid_pose_3& X_WB, Vec4& params) const {
  // A witness on a patch side of a pair of surfaces may be one of a continuum of equal pairs
  // (flat on flat): a start inside, from the closest of a few interior samples, tracks better
  // (beside an edge the sign of the distance says nothing). Kept only when it is as close.
  const Feature& A = m_model_a->primitives()[pa].feature;
  const Feature& B = m_model_b->primitives()[pb].feature;
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
  constexpr int n = 4;
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
        const bool tie = std::abs(d - d1) <= 1e-12 * (1.0 + d1);
        if ((!tie && d < d1) || (tie && c < c1)) d1 = d, c1 = c, inner = cand;
      }
  }
  if (d1 <= d0 + 1e-12 * (1.0 + d0) &&
      c1 < off_centre(A, params.data()) + off_centre(B, params.data() + 2))
    params = inner;
}

void Body_pair_tracker::seed_pair(int pa, int pb, const Rigid_pose_3& X_WA,
                                  const Rigid_pose_3& X_WB) {
  const Primitive& A = m_model_a->primitives()[pa];
  const Primitive& B = m_model_b->primitives()[pb];
  Vec4 params = Vec4::Zero();
  if (closed_form_pair(A, B)) {
    add_live(pa, pb, params);
    return;
  }
  if (A.global_element >= 0 && B.global_element >= 0) {
    const Distance_result g = extremal_distance_between(
        m_model_a->hierarchy(), X_WA, A.global_element, m_model_b->hierarchy(), X_WB,
        B.global_element, m_options.seeding, m_workspace);
    if (g.element_a < 0 || g.element_b < 0) return;  // nothing of the pair on the bodies
    params_from_global(A, g.params_a, params.data());
    params_from_global(B, g.params_b, params.data() + A.feature.dimension());
  } else {
    params = sampled_seed(A.feature, X_WA, B.feature, X_WB);
  }
  prefer_central(pa, pb, X_WA, X_WB, params);
  add_live(pa, pb, params);
  ++m_report.seeds;
}

bool Body_pair_tracker::tracks_converged(int pa, int pb) const {
  for (const Live& L : m_live) {
    if (!L.alive || !L.valid || L.closed_form || L.pa != pa || L.pb != pb) continue;
    // Converged along every parameter not held on a domain bound (one held there keeps the
    // crease's projection error): a tracker lagging behind its minimum (no corrections, a low
    // gain) may sit above a point of its own pair, the crease among them.
    const Feature& fa = m_model_a->primitives()[pa].feature;
    const Feature& fb = m_model_b->primitives()[pb].feature;
    const int na = fa.dimension();
    bool converged = true;
    for (int k = 0; k < na + fb.dimension() && converged; ++k) {
      const Feature& f = k < na ? fa : fb;
      const int j = k < na ? k : k - na;
      const double q = L.result.params[k];
      if (!f.is_closed(j) && (q <= f.lower(j) || q >= f.upper(j))) continue;
      converged = std::abs(L.result.normalised_errors[k]) <= k_converged_error;
    }
    if (converged) return true;
  }
  return false;
}

unsigned Body_pair_tracker::carried_sides(int side, int p, int other, double tol) const {
  const Primitive& P = (side == 0 ? *m_model_a : *m_model_b).primitives()[p];
  if (!P.is_surface()) return 0u;
  unsigned mask = 0u;
  for (int s = 0; s < 4; ++s) {
    const int n = P.side_neighbour[s];
    if (n < 0 || !(P.side_gap[s] <= 0.25 * tol)) continue;
    if (side == 0 ? tracks_converged(n, other) : tracks_converged(other, n)) mask |= 1u << s;
  }
  return mask;
}

bool Body_pair_tracker::carriers_tracked(const Candidate& C) const {
  const int pa = key_a(C.key), pb = key_b(C.key);
  for (int side = 0; side < 2; ++side) {
    const unsigned mask = C.carried[side];
    if (!mask) continue;
    const Primitive& P = (side == 0 ? *m_model_a : *m_model_b).primitives()[side == 0 ? pa : pb];
    for (int s = 0; s < 4; ++s) {
      if (!(mask & (1u << s))) continue;
      const int n = P.side_neighbour[s];
      if (!(side == 0 ? tracks_converged(n, pb) : tracks_converged(pa, n))) return false;
    }
  }
  return true;
}

bool Body_pair_tracker::certifiable(int pa, int pb) const {
  const Primitive& A = m_model_a->primitives()[pa];
  const Primitive& B = m_model_b->primitives()[pb];
  return A.global_element >= 0 && B.global_element >= 0 && !closed_form_pair(A, B);
}

void Body_pair_tracker::mark_tracked() {
  for (Candidate& c : m_candidates) c.tracked = false;
  for (const Live& L : m_live) {
    if (!L.alive) continue;
    const int i = find_candidate(pair_key(L.pa, L.pb));
    if (i >= 0) m_candidates[i].tracked = true;
  }
}

bool Body_pair_tracker::seed_in_contact(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) {
  mark_tracked();
  bool seeded = false;
  for (Candidate& C : m_candidates) {
    if (C.tracked || C.contact_seeded) continue;
    C.contact_seeded = true;
    seed_pair(key_a(C.key), key_b(C.key), X_WA, X_WB);
    seeded = true;
  }
  return seeded;
}

void Body_pair_tracker::check_vacated(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB,
                                      double best) {
  mark_tracked();
  const double tol = std::max(m_options.seeding.absolute_tolerance,
                              m_options.seeding.relative_tolerance * best);
  const double need = best - tol;  // a pair certified at or above this holds nothing closer
  bool seeded = false;
  const Symmetry turning = m_VA != nullptr && m_VB != nullptr
                               ? turn_axis(*m_VA, X_WA, *m_VB, X_WB)
                               : Symmetry();
  for (Candidate& C : m_candidates) {
    if (C.tracked) continue;
    const int pa = key_a(C.key), pb = key_b(C.key);
    if (!certifiable(pa, pb)) continue;
    const Primitive& A = m_model_a->primitives()[pa];
    const Primitive& B = m_model_b->primitives()[pb];
    ++m_report.vacated_checks;
    // The bound carried from an earlier step, less how much closer the pair can have come;
    // pairs that solve set aside (their minimum on a carried boundary: a trim edge, or a
    // side shared with a face whose pair is tracked) stay so while the relative motion is
    // below their gradient's reach and the carrying pairs are still tracked (see below).
    const Approach moved = approach_bound(A.box, B.box, C.at, m_relative);
    bool clear = C.lower - moved.closer >= need;
    if (!clear && C.bound_count > 0) {
      // The decay assumed the worst direction of motion for the whole pair: its last solve's
      // bounded sub-patch pairs, re-bounded at this pose, often still clear it.
      const double now = bounds_now(C, need);
      if (now >= need) {
        clear = true;
        ++m_report.vacated_bound_checks;
        C.lower = now;
        C.at = m_relative;
      }
    }
    if (clear && carriers_tracked(C)) {
      const bool finite = C.reach[0] < HUGE_VAL || C.reach[1] < HUGE_VAL;
      const Approach since = finite ? approach_bound(A.box, B.box, C.reach_at, m_relative) : moved;
      if (since.move_b < C.reach[0] && since.move_a < C.reach[1]) continue;
      // Past the reach, which assumed the worst direction of motion: the set-aside pairs
      // checked again at this pose (the other box moved rigidly) usually still hold.
      std::array<double, 2> reach;
      if (proofs_hold(C, reach)) {
        ++m_report.vacated_proof_checks;
        C.reach = reach;
        C.reach_at = m_relative;
        continue;
      }
    }
    const double boxes = box_distance(transformed(A.box, X_WA), transformed(B.box, X_WB));
    if (boxes >= need) {
      C.lower = boxes;
      C.at = m_relative;
      C.reach = {HUGE_VAL, HUGE_VAL};
      C.reach_at = m_relative;
      C.carried = {0u, 0u};
      C.proof_count = C.bound_count = C.solve_count = 0;
      continue;
    }
    // The certified solver on the pair, cut off some steps' motion above `need`: it seeds the
    // pair when it holds something closer than the tracked minimum, and otherwise leaves a
    // lower bound that stays clear of `need` for the next steps.
    ++m_report.vacated_solves;
    if (clear) ++m_report.vacated_reach_solves;
    const double step_motion = approach_bound(A.box, B.box, m_previous_relative, m_relative).closer;
    // At most the broad phase's margin: a cutoff far above the minimum would have the solver
    // settle every pair below it. When one step's motion exceeds that margin (low rates) the
    // bound cannot outlast the step anyway: cut off at `need` itself.
    const double cap = reach_margin();
    const double slack =
        step_motion >= cap
            ? 4.0 * tol
            : std::max(4.0 * tol,
                       std::min(std::max(k_slack_steps * step_motion, k_slack_growth * C.slack), cap));
    Distance_request request = m_options.seeding;
    request.keep_proofs = true;
    request.motion_axis = turning;
    request.cutoff = need + slack;
    // Trim-edge set-asides of trimmed faces: their proofs outlast a few steps' motion.
    request.carried_min_reach = std::min(slack, k_reach_steps * step_motion);
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
    // taken not to do (check_vacated never checks tracked pairs), required here of a converged
    // tracker only (tracks_converged: a lagging one may sit above the crease). After motion,
    // the gradient keeps its sign while the other primitive has moved less than the reach the
    // solve reports, and the other pairs' bound decays as before; a deeper minimum of the face
    // away from the side is found as any other basin (its pairs are neither set aside nor
    // above it).
    // The pair's elements whole, or only the sub-patch pairs in m_restarts (`partial`).
    auto solve = [&](const Distance_request& r, bool partial) {
      const Distance_hierarchy& ha = m_model_a->hierarchy();
      const Distance_hierarchy& hb = m_model_b->hierarchy();
      Distance_result result =
          partial ? extremal_distance_between(ha, X_WA, A.global_element, hb, X_WB,
                                              B.global_element, m_restarts, r, m_workspace)
                  : extremal_distance_between(ha, X_WA, A.global_element, hb, X_WB,
                                              B.global_element, r, m_workspace);
      m_report.vacated_nodes += result.nodes_created;
      return result;
    };
    unsigned carried_a = carried_sides(0, pa, pb, tol);
    unsigned carried_b = carried_sides(1, pb, pa, tol);
    const bool carrying = (carried_a | carried_b) != 0u;
    // A trimmed pair tied with the tracked minimum on a trim edge (the tracked pair holds that
    // edge) would likewise be solved to its witness there every time: it is proved against a
    // cutoff too (floor `need`), its pairs at the edge set aside by their gradient. Untrimmed
    // pairs without carried sides have no such ties and nothing to set aside: the usual solve.
    const bool trimmed = m_model_a->hierarchy().elements()[A.global_element].trimmed ||
                         m_model_b->hierarchy().elements()[B.global_element].trimmed;
    Distance_request first = request;
    if (carrying || trimmed) {
      first.cutoff_floor = need;
      first.max_nodes = k_crease_nodes;
      if (carrying) {
        first.carried_sides = {carried_a, carried_b};
        // Cutoff and gradient reach alike (the motion either proof outlasts).
        const double crease_slack =
            step_motion >= cap ? 4.0 * tol : std::max(4.0 * tol, k_crease_fraction * cap);
        first.cutoff = need + crease_slack;
        first.carried_min_reach = crease_slack;
        ++m_report.vacated_crease_solves;
      } else {
        first.cutoff = need + std::max(4.0 * tol, std::min(slack, k_proving_steps * step_motion));
        first.carried_min_reach = std::min(first.cutoff - need, k_reach_steps * step_motion);
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
                           first.carried_min_reach, first.max_nodes, kept_lower, kept_reach);
    Distance_result g = solve(first, partial);
    bool kept = partial;
    // A proving solve not settled within its budget (a stationary point of the pair between
    // the tracked minimum and the cutoff): the usual solve, to the witness. (Kept proofs are
    // at or above the cutoff.)
    if ((carrying || trimmed) && !(g.upper_bound < need) && !(g.uncarried_lower_bound >= need)) {
      g = solve(request, false);
      carried_a = carried_b = 0u;
      kept = false;
    }
    if (kept) ++m_report.vacated_partial_solves;
    C.lower = kept ? std::min(g.uncarried_lower_bound, kept_lower) : g.uncarried_lower_bound;
    C.at = m_relative;
    C.reach = g.carried_reach;
    if (kept)
      for (int side = 0; side < 2; ++side) C.reach[side] = std::min(C.reach[side], kept_reach[side]);
    C.reach_at = m_relative;
    C.carried = {carried_a, carried_b};
    keep_proofs(C, Solve_pose{X_WA, m_relative}, kept);
    C.slack = g.element_a < 0 ? slack : 0.0;
    if (g.element_a < 0 || g.element_b < 0 || !(g.upper_bound < need)) continue;
    Vec4 params = Vec4::Zero();
    params_from_global(A, g.params_a, params.data());
    params_from_global(B, g.params_b, params.data() + A.feature.dimension());
    add_live(pa, pb, params);
    ++m_report.seeds;
    ++m_report.vacated_seeds;
    C.tracked = true;
    seeded = true;
  }
  if (seeded) step_pending();
}

const Rigid_pose_3& Body_pair_tracker::Motions::b(int k) {
  if (!(m_made_b & (1u << k))) {
    // X_WA0 X_AB X_AB0^-1 X_WA0^-1 (A's points move by its inverse with B held).
    const Solve_pose& s = m_c.solves[k];
    m_length[k] = s.a.translation().cwiseAbs().maxCoeff() +
                  m_relative.translation().cwiseAbs().maxCoeff() +
                  s.relative.translation().cwiseAbs().maxCoeff();
    new (&m_b[k].pose) Rigid_pose_3(s.a * m_relative * s.relative.inverse() * s.a.inverse());
    m_made_b |= 1u << k;
  }
  return m_b[k].pose;
}

const Rigid_pose_3& Body_pair_tracker::Motions::a(int k) {
  if (!(m_made_a & (1u << k))) {
    new (&m_a[k].pose) Rigid_pose_3(b(k).inverse());
    m_made_a |= 1u << k;
  }
  return m_a[k].pose;
}

bool Body_pair_tracker::proofs_hold(const Candidate& C, std::array<double, 2>& reach) const {
  if (C.proof_count == 0) return false;
  Motions m(C, m_relative);
  reach = {HUGE_VAL, HUGE_VAL};
  for (int i = C.proof_begin; i < C.proof_begin + C.proof_count; ++i) {
    const Gradient_proof& p = m_proofs[i].proof;
    const int k = m_proofs[i].solve;
    double r = 0.0;
    if (!gradient_proof_holds(p, p.side == 0 ? m.b(k) : m.a(k), m.length(k), r)) return false;
    reach[p.side] = std::min(reach[p.side], r);
  }
  return true;
}

double Body_pair_tracker::bounds_now(const Candidate& C, double need) const {
  if (C.bound_count == 0) return -HUGE_VAL;
  Motions m(C, m_relative);
  double lowest = HUGE_VAL;
  for (int i = C.bound_begin; i < C.bound_begin + C.bound_count; ++i) {
    const int k = m_bounds[i].solve;
    lowest = std::min(lowest, bound_after_motion(m_bounds[i].proof, m.b(k), m.length(k)));
    if (lowest < need) break;
  }
  return lowest;
}

bool Body_pair_tracker::plan_partial_solve(const Candidate& C, int element_a, int element_b,
                                           double cutoff, double min_reach, int max_nodes,
                                           double& lower, std::array<double, 2>& reach) {
  if (C.solve_count == 0 || C.solve_count >= k_kept_solves || C.bound_count + C.proof_count == 0)
    return false;
  Motions m(C, m_relative);
  m_restarts.clear();
  m_keep_bound.assign(static_cast<std::size_t>(C.bound_count), 0);
  m_keep_proof.assign(static_cast<std::size_t>(C.proof_count), 0);
  lower = HUGE_VAL;
  reach = {HUGE_VAL, HUGE_VAL};
  for (int i = 0; i < C.bound_count; ++i) {
    const Kept_bound& kb = m_bounds[C.bound_begin + i];
    const Bound_proof& p = kb.proof;
    if (p.a_element != element_a || p.b_element != element_b) return false;
    const double now = bound_after_motion(p, m.b(kb.solve), m.length(kb.solve));
    if (now >= cutoff) {
      m_keep_bound[i] = 1;
      lower = std::min(lower, now);
    } else {
      m_restarts.push_back({p.a_lo, p.a_hi, p.b_lo, p.b_hi});
    }
  }
  for (int i = 0; i < C.proof_count; ++i) {
    const Kept_proof& kp = m_proofs[C.proof_begin + i];
    const Gradient_proof& p = kp.proof;
    double r = 0.0;
    const int k = kp.solve;
    if (gradient_proof_holds(p, p.side == 0 ? m.b(k) : m.a(k), m.length(k), r) &&
        r >= min_reach) {
      m_keep_proof[i] = 1;
      reach[p.side] = std::min(reach[p.side], r);
    } else if (p.side == 0) {
      m_restarts.push_back({p.own_lo, p.own_hi, p.other_lo, p.other_hi});
    } else {
      m_restarts.push_back({p.other_lo, p.other_hi, p.own_lo, p.own_hi});
    }
  }
  // (Measured on compare (c) at 1 kHz, nodes of the restricted solves: at most twice the
  // budget 293k, at most the budget 307k, at most half 374k; no limit 306k, and as1's scene
  // (BodyScenes) then ran away: a fallback's tens of thousands of kept pairs restarted at once,
  // over budget, falling back again.)
  return m_restarts.size() <= 2 * static_cast<std::size_t>(max_nodes);
}

void Body_pair_tracker::keep_proofs(Candidate& C, const Solve_pose& at, bool partial) {
  const std::vector<Gradient_proof>& proofs = m_workspace.gradient_proofs();
  const std::vector<Bound_proof>& bounds = m_workspace.bound_proofs();
  // C's earlier proofs, kept (partial) or dropped: their range is read after the compaction
  // below, which keeps the order within each range.
  if (!partial) C.proof_count = C.bound_count = 0;
  std::size_t live_proofs = proofs.size(), live_bounds = bounds.size();
  for (const Candidate& c : m_candidates) {
    live_proofs += static_cast<std::size_t>(c.proof_count);
    live_bounds += static_cast<std::size_t>(c.bound_count);
  }
  // Ranges of re-solved or dropped candidates are stale: compact when they dominate, in place
  // (ranges slid down in the order they were written), so the pools keep their capacity.
  if (m_proofs.size() > 2 * live_proofs + 1024 || m_bounds.size() > 2 * live_bounds + 4096) {
    m_order.clear();
    for (int i = 0; i < static_cast<int>(m_candidates.size()); ++i) m_order.push_back(i);
    auto compact = [&](auto& pool, int Candidate::*begin, int Candidate::*count) {
      std::sort(m_order.begin(), m_order.end(),
                [&](int x, int y) { return m_candidates[x].*begin < m_candidates[y].*begin; });
      int next = 0;
      for (const int i : m_order) {
        Candidate& c = m_candidates[i];
        if (next < c.*begin)  // (copying to the left may overlap)
          std::copy(pool.begin() + c.*begin, pool.begin() + c.*begin + c.*count, pool.begin() + next);
        c.*begin = next;
        next += c.*count;
      }
      pool.resize(next);
    };
    compact(m_proofs, &Candidate::proof_begin, &Candidate::proof_count);
    compact(m_bounds, &Candidate::bound_begin, &Candidate::bound_count);
  }
  // The solves the kept proofs still refer to, renumbered in order, then this one.
  std::array<int, k_kept_solves> renumber;
  renumber.fill(-1);
  int solves = 0;
  if (partial) {
    std::array<bool, k_kept_solves> used{};
    for (int i = 0; i < C.bound_count; ++i)
      if (m_keep_bound[i]) used[m_bounds[C.bound_begin + i].solve] = true;
    for (int i = 0; i < C.proof_count; ++i)
      if (m_keep_proof[i]) used[m_proofs[C.proof_begin + i].solve] = true;
    for (int k = 0; k < C.solve_count; ++k)
      if (used[k]) {
        renumber[k] = solves;
        C.solves[solves++] = C.solves[k];
      }
  }
  const int current = solves;
  C.solves[solves++] = at;
  C.solve_count = solves;
  const int old_proofs = C.proof_begin, old_bounds = C.bound_begin;
  C.proof_begin = static_cast<int>(m_proofs.size());
  if (partial)
    for (int i = 0; i < C.proof_count; ++i)
      if (m_keep_proof[i]) {
        Kept_proof p = m_proofs[old_proofs + i];  // (a copy: the pool may grow)
        p.solve = renumber[p.solve];
        m_proofs.push_back(p);
      }
  for (const Gradient_proof& p : proofs) m_proofs.push_back({p, current});
  C.proof_count = static_cast<int>(m_proofs.size()) - C.proof_begin;
  C.bound_begin = static_cast<int>(m_bounds.size());
  if (partial)
    for (int i = 0; i < C.bound_count; ++i)
      if (m_keep_bound[i]) {
        Kept_bound b = m_bounds[old_bounds + i];
        b.solve = renumber[b.solve];
        m_bounds.push_back(b);
      }
  for (const Bound_proof& b : bounds) m_bounds.push_back({b, current});
  C.bound_count = static_cast<int>(m_bounds.size()) - C.bound_begin;
}

int Body_pair_tracker::find_candidate(std::uint64_t key) const {
  const auto it = std::lower_bound(m_candidates.begin(), m_candidates.end(), key,
                                   [](const Candidate& c, std::uint64_t k) { return c.key < k; });
  return it != m_candidates.end() && it->key == key ? static_cast<int>(it - m_candidates.begin())
                                                    : -1;
}

void Body_pair_tracker::step_pending() {
  for (std::size_t k = 0; k < m_live.size(); ++k) {
    if (!m_live[k].alive || m_live[k].stepped == m_steps) continue;
    step_live(static_cast<int>(k));
    for (int hop = 0; hop < 3 && transition(static_cast<int>(k)); ++hop) {
    }
  }
}

bool Body_pair_tracker::tracks(std::uint64_t key) const {
  for (const Live& L : m_live)
    if (L.alive && pair_key(L.pa, L.pb) == key) return true;
  return false;
}

void Body_pair_tracker::broad_phase(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB,
                                    double reach) {
  const Tracking_model& A = *m_model_a;
  const Tracking_model& B = *m_model_b;
  // Cut each body's tree by the other body's world box (inflated by the reach) taken into its
  // frame: what remains is near the other body.
  const Bbox_3 wa = transformed(A.box(), X_WA);
  const Bbox_3 wb = transformed(B.box(), X_WB);
  m_prims_a.clear();
  m_prims_b.clear();
  const bool edges_a = !(B.has_mesh() || B.body().is_point);
  const bool edges_b = !(A.has_mesh() || A.body().is_point);
  A.collect(transformed(inflate(wb, reach), X_WA.inverse()), edges_a, m_prims_a);
  B.collect(transformed(inflate(wa, reach), X_WB.inverse()), edges_b, m_prims_b);
  // World boxes of the survivors, inflated by half the reach each: boxes that intersect are
  // within the reach along every axis; the exact box distance decides.
  auto& ba = m_scratch->boxes_a;
  auto& bb = m_scratch->boxes_b;
  ba.clear();
  bb.clear();
  m_world_a.clear();
  m_world_b.clear();
  for (int p : m_prims_a) {
    m_world_a.push_back(transformed(A.primitives()[p].box, X_WA));
    ba.emplace_back(inflate(m_world_a.back(), 0.5 * reach), static_cast<int>(m_world_a.size()) - 1);
  }
  for (int p : m_prims_b) {
    m_world_b.push_back(transformed(B.primitives()[p].box, X_WB));
    bb.emplace_back(inflate(m_world_b.back(), 0.5 * reach), static_cast<int>(m_world_b.size()) - 1);
  }
  const Rigid_pose_3 relative = X_WA.inverse() * X_WB;
  m_next_candidates.clear();
  CGAL::box_intersection_d(ba.begin(), ba.end(), bb.begin(), bb.end(),
                           [&](const Box& x, const Box& y) {
                             const int i = x.info(), j = y.info();
                             const double d = box_distance(m_world_a[i], m_world_b[j]);
                             if (d > reach) return;
                             Candidate c;
                             c.key = pair_key(m_prims_a[i], m_prims_b[j]);
                             c.lower = d;  // the boxes hold the primitives
                             c.at = relative;
                             m_next_candidates.push_back(c);
                           });
  std::sort(m_next_candidates.begin(), m_next_candidates.end(),
            [](const Candidate& x, const Candidate& y) { return x.key < y.key; });
  // Pairs that left: their trackers go. Pairs that entered: their box distance is their bound
  // (check_vacated certifies them apart, seed_in_contact seeds them in contact), but pairs
  // those cannot certify are seeded now. Pairs that stayed keep their carried bound unless the
  // box distance now is at least as high.
  std::size_t i = 0, j = 0;
  auto drop = [&](std::uint64_t key) {
    for (std::size_t k = 0; k < m_live.size(); ++k)
      if (m_live[k].alive && pair_key(m_live[k].pa, m_live[k].pb) == key) kill(static_cast<int>(k));
  };
  while (i < m_candidates.size() || j < m_next_candidates.size()) {
    if (j == m_next_candidates.size() ||
        (i < m_candidates.size() && m_candidates[i].key < m_next_candidates[j].key)) {
      drop(m_candidates[i++].key);
    } else if (i == m_candidates.size() || m_next_candidates[j].key < m_candidates[i].key) {
      const std::uint64_t key = m_next_candidates[j++].key;
      // (A tracker may have arrived by a transition.)
      const int pa = key_a(key), pb = key_b(key);
      if (!certifiable(pa, pb) && !tracks(key)) seed_pair(pa, pb, X_WA, X_WB);
    } else {
      // The carried bound (with its pose, reach and carried sides) when it is the higher one;
      // the slack in any case.
      if (m_candidates[i].lower > m_next_candidates[j].lower)
        m_next_candidates[j] = m_candidates[i];
      else
        m_next_candidates[j].slack = m_candidates[i].slack;
      ++i;
      ++j;
    }
  }
  // Trackers that moved by transitions onto pairs outside the set go too.
  auto by_key = [](const Candidate& c, std::uint64_t k) { return c.key < k; };
  for (std::size_t k = 0; k < m_live.size(); ++k) {
    if (!m_live[k].alive) continue;
    const std::uint64_t key = pair_key(m_live[k].pa, m_live[k].pb);
    const auto it = std::lower_bound(m_next_candidates.begin(), m_next_candidates.end(), key, by_key);
    if (it == m_next_candidates.end() || it->key != key) kill(static_cast<int>(k));
  }
  m_candidates.swap(m_next_candidates);
  m_last_relative = relative;
  m_broad_reach = reach;
  ++m_report.broad_phases;
}

Distance_result Body_pair_tracker::global_solve(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) {
  ++m_report.audits;
  return extremal_distance(m_model_a->hierarchy(), X_WA, m_model_b->hierarchy(), X_WB,
                           m_options.global, m_workspace);
}

bool Body_pair_tracker::seed_from_global(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB,
                                         double tracked) {
  return seed_from(global_solve(X_WA, X_WB), X_WA, X_WB, tracked);
}

bool Body_pair_tracker::seed_from(const Distance_result& g, const Rigid_pose_3& X_WA,
                                  const Rigid_pose_3& X_WB, double tracked) {
  if (g.element_a < 0 || g.element_b < 0) return false;
  if (!(g.upper_bound < tracked - std::max(g.tolerance_used, g.upper_bound - g.lower_bound)))
    return false;
  const int pa = m_model_a->primitive_of(g.kind_a, g.element_a);
  const int pb = m_model_b->primitive_of(g.kind_b, g.element_b);
  if (pa < 0 || pb < 0) return false;
  Vec4 params = Vec4::Zero();
  const Primitive& A = m_model_a->primitives()[pa];
  params_from_global(A, g.params_a, params.data());
  params_from_global(m_model_b->primitives()[pb], g.params_b, params.data() + A.feature.dimension());
  prefer_central(pa, pb, X_WA, X_WB, params);
  for (std::size_t k = 0; k < m_live.size(); ++k)
    if (m_live[k].alive && m_live[k].pa == pa && m_live[k].pb == pb && !m_live[k].closed_form) {
      m_live[k].tracker.reset(params);  // another basin of the same pair
      m_live[k].stepped = -1;
      return true;
    }
  add_live(pa, pb, params);
  const std::uint64_t key = pair_key(pa, pb);
  if (find_candidate(key) < 0) {
    Candidate c;
    c.key = key;
    c.lower = -std::numeric_limits<double>::infinity();  // no bound yet
    c.at = X_WA.inverse() * X_WB;
    m_candidates.insert(std::lower_bound(m_candidates.begin(), m_candidates.end(), key,
                                         [](const Candidate& x, std::uint64_t k) { return x.key < k; }),
                        c);
  }
  return true;
}

void Body_pair_tracker::start(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) {
  for (std::size_t k = 0; k < m_live.size(); ++k)
    if (m_live[k].alive) kill(static_cast<int>(k));
  m_candidates.clear();
  m_proofs.clear();
  m_bounds.clear();
  m_started = true;
  const Distance_result g = global_solve(X_WA, X_WB);
  broad_phase(X_WA, X_WB, std::max(g.upper_bound, 0.0) + reach_margin());
  // The certified pair, should the broad phase have missed it (duplicates merge after the
  // first step).
  seed_from(g, X_WA, X_WB, std::numeric_limits<double>::infinity());
}

void Body_pair_tracker::step_live(int k) {
  Live& L = m_live[k];
  L.stepped = m_steps;
  const Tracking_model& MA = *m_model_a;
  const Tracking_model& MB = *m_model_b;
  const Primitive& A = MA.primitives()[L.pa];
  const Primitive& B = MB.primitives()[L.pb];
  if (L.closed_form) {
    Track_result& r = L.result;
    r.time = m_t;
    r.status = Track_status::Tracking;
    r.degeneracy = Degeneracy::None;
    r.params.setZero();
    r.iterations = 0;
    if (A.kind == Primitive_kind::Triangle && B.kind == Primitive_kind::Triangle) {
      Vec3 ta[3], tb[3];
      triangle_corners(MA, A, *m_XA, ta);
      triangle_corners(MB, B, *m_XB, tb);
      const Triangle_closest c = triangle_distance(ta, tb);
      r.distance = c.distance;
      r.point_a = c.point_a;
      r.point_b = c.point_b;
      r.params << c.uv_a[0], c.uv_a[1], c.uv_b[0], c.uv_b[1];
    } else {
      const bool tri_a = A.kind == Primitive_kind::Triangle;
      Vec3 t[3];
      triangle_corners(tri_a ? MA : MB, tri_a ? A : B, tri_a ? *m_XA : *m_XB, t);
      const Vec3 q = (tri_a ? *m_XB : *m_XA).translation();
      double uv[2];
      const Vec3 c = closest_on_triangle(q, t[0], t[1], t[2], uv);
      r.point_a = tri_a ? c : q;
      r.point_b = tri_a ? q : c;
      r.distance = (r.point_b - r.point_a).norm();
      r.params[0] = uv[0];
      r.params[1] = uv[1];
    }
    r.normal = r.distance > 0.0 ? Vec3((r.point_b - r.point_a) / r.distance) : Vec3::Zero();
    L.valid = true;
    return;
  }
  L.result = L.tracker.step(m_t, *m_XA, *m_VA, *m_XB, *m_VB, m_dt);
  m_report.corrections += L.result.corrections;
  if (m_options.tracker.corrections > 0 && L.result.corrections == m_options.tracker.corrections)
    ++m_report.capped_corrections;
  const int na = A.feature.dimension();
  L.valid = (!A.is_surface() || MA.contains(L.pa, L.result.params.data())) &&
            (!B.is_surface() || MB.contains(L.pb, L.result.params.data() + na));
  // A penetration depth counts only for a pair that went inside through contact (the normal
  // form's band around it): a face turned away from the other body (the far side of a torus
  // seen from its hole) also has d against its outward normal, with the bodies apart.
  if (L.result.normal_form) L.through_contact = true;
  else if (L.result.distance > 0.0) L.through_contact = false;
  if (L.result.distance < -m_options.contact_tolerance && !L.through_contact) L.valid = false;
}

bool Body_pair_tracker::transition(int k) {
  Live& L = m_live[k];
  if (L.closed_form || !L.alive) return false;
  const Track_result& r = L.result;
  // Only apart: inside, the tracked pair is a saddle of the distance and descent means nothing.
  if (!(r.distance > m_options.contact_tolerance)) return false;
  const int na = m_model_a->primitives()[L.pa].feature.dimension();
  for (int side = 0; side < 2; ++side) {
    const Tracking_model& M = side == 0 ? *m_model_a : *m_model_b;
    const int p = side == 0 ? L.pa : L.pb;
    const Primitive& P = M.primitives()[p];
    const double* q = r.params.data() + (side == 0 ? 0 : na);
    const Rigid_pose_3& X = side == 0 ? *m_XA : *m_XB;
    const Vec3& other = side == 0 ? r.point_b : r.point_a;
    int np = -1;
    double nq[2] = {0, 0};
    if (P.is_surface()) {
      const Nurbs_surface_3& S = *P.feature.surface();
      double g[2], scale[2];
      surface_descent(P.feature, X, q, other, g, scale);
      const double bound[4] = {S.u_min(), S.u_max(), S.v_min(), S.v_max()};
      // Sides the point sits on with the descent pointing out of the patch.
      int out_side = -1;
      for (int s = 0; s < 4; ++s) {
        const int dir = s / 2;
        if (q[dir] != bound[s]) continue;
        if (P.feature.collapsed_edges() & (1u << s)) continue;
        if (dir == 0 ? S.is_closed_u() : S.is_closed_v()) continue;
        const double outward = (s % 2 == 0) ? -g[dir] : g[dir];
        if (outward > 1e-10 * scale[dir]) out_side = s;
      }
      int link_count = 0;
      M.edges_of(p, link_count);
      if (link_count > 0 && (out_side >= 0 || !M.contains(p, q))) {
        // Off a trimmed face, a triangle or a face with B-rep edges: onto the nearest edge.
        Surface_point sp;
        S.evaluate(q[0], q[1], sp, 0);
        double t = 0.0;
        const Vec3 toward = X.inverse().apply_point(other);
        np = M.nearest_edge(p, sp.p, t, &toward);
        nq[0] = t;
      } else if (out_side >= 0 && P.side_neighbour[out_side] >= 0) {
        // Across a matched patch side, if the descent enters the neighbour.
        const int n = P.side_neighbour[out_side];
        const int ns = P.side_neighbour_side[out_side];
        double mq[2];
        if (M.map_across_side(p, out_side, q, mq)) {
          double gn[2], sn[2];
          surface_descent(M.primitives()[n].feature, X, mq, other, gn, sn);
          const int dir = ns / 2;
          const double inward = (ns % 2 == 0) ? gn[dir] : -gn[dir];
          if (inward > 1e-10 * sn[dir]) {
            np = n;
            nq[0] = mq[0];
            nq[1] = mq[1];
          }
        }
      }
    } else if (P.feature.dimension() == 1) {
      int count = 0;
      const Edge_on_face* faces = M.faces_of(p, count);
      const double t = q[0];
      for (int f = 0; f < count && np < 0; ++f) {
        const Edge_on_face& use = faces[f];
        const Primitive& F = M.primitives()[use.face];
        double uv[2], uv1[2], uv0[2];
        use.map(t, uv);
        const double h = 1e-6 * (P.feature.upper(0) - P.feature.lower(0));
        use.map(t + h, uv1);
        use.map(t - h, uv0);
        // The edge's normal in the face's parameter plane, oriented into the face.
        double nrm[2] = {-(uv1[1] - uv0[1]), uv1[0] - uv0[0]};
        const double len = std::hypot(nrm[0], nrm[1]);
        if (!(len > 0.0)) continue;
        nrm[0] /= len;
        nrm[1] /= len;
        const Nurbs_surface_3& S = *F.feature.surface();
        const double band = F.trim ? F.trim->tolerance()
                                   : 1e-6 * std::max(S.u_max() - S.u_min(), S.v_max() - S.v_min());
        const double eps = 4.0 * band;
        auto inside = [&](double s) {
          const double x[2] = {uv[0] + s * eps * nrm[0], uv[1] + s * eps * nrm[1]};
          return x[0] >= S.u_min() && x[0] <= S.u_max() && x[1] >= S.v_min() && x[1] <= S.v_max() &&
                 M.contains(use.face, x);
        };
        const bool plus = inside(1.0), minus = inside(-1.0);
        if (plus == minus) continue;  // cannot tell the face's side here
        if (!plus) nrm[0] = -nrm[0], nrm[1] = -nrm[1];
        double cq[2] = {std::clamp(uv[0], S.u_min(), S.u_max()), std::clamp(uv[1], S.v_min(), S.v_max())};
        double g[2], scale[2];
        surface_descent(F.feature, X, cq, other, g, scale);
        const double inward = g[0] * nrm[0] + g[1] * nrm[1];
        if (inward > 1e-10 * std::max(scale[0], scale[1])) {
          np = use.face;
          nq[0] = cq[0];
          nq[1] = cq[1];
        }
      }
    }
    if (np < 0) continue;
    // Just inside the new primitive's domain: a parameter held on a patch edge is left out of
    // the tracker's corrections, so a handed-over point must not start on one.
    {
      const Feature& f = M.primitives()[np].feature;
      for (int k = 0; k < f.dimension(); ++k) {
        if (f.is_closed(k)) continue;
        const double margin = 1e-9 * (f.upper(k) - f.lower(k));
        nq[k] = std::clamp(nq[k], f.lower(k) + margin, f.upper(k) - margin);
      }
    }
    // Hand the tracker over: same other side, this side on the new primitive.
    const int npa = side == 0 ? np : L.pa;
    const int npb = side == 0 ? L.pb : np;
    const Feature& fa = m_model_a->primitives()[npa].feature;
    const Feature& fb = m_model_b->primitives()[npb].feature;
    Vec4 params = Vec4::Zero();
    if (side == 0) {
      for (int c = 0; c < fa.dimension(); ++c) params[c] = nq[c];
      for (int c = 0; c < fb.dimension(); ++c) params[fa.dimension() + c] = r.params[na + c];
    } else {
      for (int c = 0; c < fa.dimension(); ++c) params[c] = r.params[c];
      for (int c = 0; c < fb.dimension(); ++c) params[fa.dimension() + c] = nq[c];
    }
    L.pa = npa;
    L.pb = npb;
    L.tracker = Extremal_tracker(fa, fb, params, m_options.tracker);
    L.through_contact = false;
    ++m_report.transitions;
    step_live(k);
    return true;
  }
  return false;
}

void Body_pair_tracker::merge_duplicates() {
  const double tol = 1e-7 * std::max(diagonal(m_model_a->box()), diagonal(m_model_b->box()));
  for (std::size_t i = 0; i < m_live.size(); ++i) {
    if (!m_live[i].alive) continue;
    for (std::size_t j = i + 1; j < m_live.size(); ++j) {
      Live& x = m_live[i];
      Live& y = m_live[j];
      if (!y.alive || x.pa != y.pa || x.pb != y.pb) continue;
      if ((x.result.point_a - y.result.point_a).norm() + (x.result.point_b - y.result.point_b).norm() >
          tol)
        continue;
      kill(static_cast<int>(j));
      ++m_report.merges;
    }
  }
}

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

}  // namespace

void Body_pair_tracker::fill_report() {
  Pair_report& r = m_report;
  int best = -1;
  double best_d = std::numeric_limits<double>::infinity();
  int trackers = 0;
  for (std::size_t k = 0; k < m_live.size(); ++k) {
    const Live& L = m_live[k];
    if (!L.alive) continue;
    ++trackers;
    if (L.valid && L.result.distance < best_d) best_d = L.result.distance, best = static_cast<int>(k);
  }
  r.trackers = trackers;
  r.candidates = static_cast<int>(m_candidates.size());
  if (best < 0) return;
  const Live& L = m_live[best];
  const Track_result& tr = L.result;
  r.distance = tr.distance;
  r.point_a = tr.point_a;
  r.point_b = tr.point_b;
  r.normal = tr.normal;
  r.degeneracy = tr.degeneracy;
  const int na = m_model_a->primitives()[L.pa].feature.dimension();
  double qa[2] = {0, 0}, qb[2] = {0, 0};
  int da = 0, db = 0;
  r.feature_a = report_feature(*m_model_a, L.pa, tr.params.data(), qa, r.edge_a, da);
  r.feature_b = report_feature(*m_model_b, L.pb, tr.params.data() + na, qb, r.edge_b, db);
  r.params.setZero();
  for (int c = 0; c < da; ++c) r.params[c] = qa[c];
  for (int c = 0; c < db; ++c) r.params[da + c] = qb[c];
  const double tol = m_options.contact_tolerance;
  r.status = tr.distance < -tol                             ? Pair_status::Penetrating
             : tr.distance <= tol                           ? Pair_status::Contact
             : tr.status == Track_status::Singular_fallback ? Pair_status::Fallback
             : tr.status == Track_status::On_boundary       ? Pair_status::Boundary
                                                            : Pair_status::Tracking;
}

const Pair_report& Body_pair_tracker::step(double t, const Rigid_pose_3& X_WA, const Twist_3& V_A,
                                           const Rigid_pose_3& X_WB, const Twist_3& V_B,
                                           double dt) {
  Pair_report& r = m_report;
  r.time = t;
  if (is_farther(X_WA, X_WB)) {
    r.status = Pair_status::Farther;
    r.distance = box_distance(transformed(m_model_a->box(), X_WA), transformed(m_model_b->box(), X_WB));
    r.point_a = r.point_b = r.normal = Vec3::Zero();
    r.feature_a = r.feature_b = r.edge_a = r.edge_b = -1;
    r.degeneracy = Degeneracy::None;
    r.trackers = 0;
    r.candidates = 0;
    m_started = false;  // re-seed when the pair comes back within the threshold
    m_have_pose = false;
    return r;
  }
  // Nothing moved since the last step: the same answer.
  if (m_started && m_have_pose && same_pose(X_WA, m_last_A) && same_pose(X_WB, m_last_B))
    return r;
  m_t = t;
  m_dt = dt;
  m_XA = &X_WA;
  m_XB = &X_WB;
  m_VA = &V_A;
  m_VB = &V_B;
  ++m_steps;
  m_relative = X_WA.inverse() * X_WB;
  if (!m_started) {
    start(X_WA, X_WB);
    m_previous_relative = m_relative;
  }
  // 1. Step the live trackers at t; hand the ones that left their primitive across.
  double best = std::numeric_limits<double>::infinity();
  auto step_all = [&] {
    step_pending();
    for (const Live& L : m_live)
      if (L.alive && L.valid) best = std::min(best, L.result.distance);
  };
  step_all();
  // 2. Broad phase where the candidate set may miss a pair within |best| plus the margin (|best|:
  //    inside, the tracked pair's own primitives lie |best| apart): entering pairs get a bound,
  //    far ones go. A set built with reach R holds every pair that was within R then, so every
  //    pair within R less the relative motion since (k_broad_extra).
  // 3. Candidate pairs without a tracker may hold a new basin closer than the tracked minimum:
  //    the certified solver on the pair, cut off at it, says so at little cost when they do
  //    not. In contact (a signed minimum) every candidate pair gets a tracker instead.
  // 4. Lost everything (all witnesses off the bodies): the certified solver re-seeds.
  if (std::isfinite(best)) {
    const double length = std::max(diagonal(m_model_a->box()), diagonal(m_model_b->box()));
    const double reach = std::abs(best) + reach_margin();
    if (!near_pose(m_relative, m_last_relative, length) &&
        reach + approach_bound(m_model_a->box(), m_model_b->box(), m_last_relative, m_relative)
                    .closer > m_broad_reach) {
      broad_phase(X_WA, X_WB, reach + k_broad_extra * reach_margin());
      step_all();
    }
    if (best > m_options.contact_tolerance)
      check_vacated(X_WA, X_WB, best);
    else if (seed_in_contact(X_WA, X_WB))
      step_all();
  } else {
    if (seed_from_global(X_WA, X_WB, std::numeric_limits<double>::infinity())) ++r.reseeds;
    step_all();
  }
  merge_duplicates();
  if (m_options.audit_every > 0 && m_steps % m_options.audit_every == 0 &&
      seed_from_global(X_WA, X_WB, best)) {
    ++r.reseeds;
    step_all();
  }
  fill_report();
  m_previous_relative = m_relative;
  m_last_A = X_WA;
  m_last_B = X_WB;
  m_have_pose = true;
  return r;
}

}  // namespace extremal
