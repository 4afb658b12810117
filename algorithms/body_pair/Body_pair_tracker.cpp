#include "algorithms/body_pair/Body_pair_tracker.h"

#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <new>

#include "algorithms/distance/Triangle_distance.h"
#include "algorithms/body_pair/internal/Body_pair_support.h"
#include "algorithms/distance/internal/Restricted_solve.h"
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

using internal::approach_bound;
using internal::box_diagonal;
using internal::closed_form_pair;
using internal::key_a;
using internal::key_b;
using internal::pair_key;
using internal::params_from_global;
using internal::k_wandering_error;
using internal::inflate;
using internal::off_centre;

using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, int,
                                                      CGAL::Box_intersection_d::ID_FROM_BOX_ADDRESS>;

bool same_pose(const Rigid_pose_3& x, const Rigid_pose_3& y) {
  return x.rotation() == y.rotation() && x.translation() == y.translation();
}

bool near_pose(const Rigid_pose_3& x, const Rigid_pose_3& y, double length) {
  return (x.rotation() - y.rotation()).cwiseAbs().maxCoeff() <= 1e-14 &&
         (x.translation() - y.translation()).cwiseAbs().maxCoeff() <= 1e-14 * length;
}

// The broad phase reaches this fraction of the margin farther than it must, so that it runs
// again only once the relative motion since has used that up (between runs the candidate set
// holds some pairs beyond the reach, whose checks cost little).
constexpr double k_broad_extra = 0.5;

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
  std::vector<std::pair<std::uint64_t, double>> found;  // (key, box distance), sorted by key
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
  EXTREMAL_PRECONDITION_MSG(options.own_basin_gap >= 0.0 && options.own_basin_gap < 1.0,
                            "Body_pair_options::own_basin_gap must be >= 0 and < 1");
  m_live.reserve(64);
  m_free.reserve(64);
}

Body_pair_tracker::~Body_pair_tracker() = default;
Body_pair_tracker::Body_pair_tracker(Body_pair_tracker&&) noexcept = default;

double Body_pair_tracker::reach_margin() const {
  if (m_options.broad_margin > 0.0) return m_options.broad_margin;
  return 0.02 * std::min(box_diagonal(m_model_a->box()), box_diagonal(m_model_b->box()));
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
  L.holds_unreached = L.was_shallower = false;
  L.seeded_apart = false;
  L.behind_sheet = false;
  L.closed_form = closed_form_pair(A, B);
  if (!L.closed_form) L.tracker = Extremal_tracker(A.feature, B.feature, params, m_options.tracker);
  return k;
}

void Body_pair_tracker::kill(int k) {
  m_live[k].alive = false;
  m_free.push_back(k);
}

namespace {

// Sampled closest pair of two features, polished by Newton at rest (pairs the global solver
// has no element for: mesh edges).
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

double Body_pair_tracker::seed_pair(int pa, int pb, const Rigid_pose_3& X_WA,
                                    const Rigid_pose_3& X_WB) {
  const Primitive& A = m_model_a->primitives()[pa];
  const Primitive& B = m_model_b->primitives()[pb];
  Vec4 params = Vec4::Zero();
  if (closed_form_pair(A, B)) {
    add_live(pa, pb, params);
    return -HUGE_VAL;
  }
  double lower = -HUGE_VAL;
  if (A.global_element >= 0 && B.global_element >= 0) {
    const Distance_result g = extremal_distance_between(
        m_model_a->hierarchy(), X_WA, A.global_element, m_model_b->hierarchy(), X_WB,
        B.global_element, m_options.seeding, m_workspace);
    if (g.is_certified()) lower = g.lower_bound;
    if (g.element_a < 0 || g.element_b < 0) return lower;  // nothing of the pair on the bodies
    params_from_global(A, g.params_a, params.data());
    params_from_global(B, g.params_b, params.data() + A.feature.dimension());
  } else {
    params = sampled_seed(A.feature, X_WA, B.feature, X_WB);
  }
  prefer_central(pa, pb, X_WA, X_WB, params);
  add_live(pa, pb, params);
  ++m_report.seeds;
  return lower;
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

void Body_pair_tracker::index_live() {
  m_live_keys.clear();
  for (std::size_t k = 0; k < m_live.size(); ++k)
    if (m_live[k].alive)
      m_live_keys.emplace_back(pair_key(m_live[k].pa, m_live[k].pb), static_cast<int>(k));
  std::sort(m_live_keys.begin(), m_live_keys.end());
}

template <class F>
void Body_pair_tracker::each_live(std::uint64_t key, F f) const {
  auto e = std::lower_bound(m_live_keys.begin(), m_live_keys.end(), std::make_pair(key, -1));
  for (; e != m_live_keys.end() && e->first == key; ++e) {
    const Live& L = m_live[e->second];
    if (L.alive && pair_key(L.pa, L.pb) == key) f(e->second);
  }
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
  // Sorted as (key, distance) pairs, then made candidates: a candidate is large (its kept
  // solves' poses), and sorting them moved 4% of a step's time in a contact of many pairs.
  auto& found = m_scratch->found;
  found.clear();
  CGAL::box_intersection_d(ba.begin(), ba.end(), bb.begin(), bb.end(),
                           [&](const Box& x, const Box& y) {
                             const int i = x.info(), j = y.info();
                             const double d = box_distance(m_world_a[i], m_world_b[j]);
                             if (d > reach) return;
                             found.emplace_back(pair_key(m_prims_a[i], m_prims_b[j]), d);
                           });
  std::sort(found.begin(), found.end());  // (keys are distinct)
  m_next_candidates.clear();
  for (const auto& [key, d] : found) {
    Candidate c;
    c.key = key;
    c.lower = d;  // the boxes hold the primitives
    c.at = relative;
    m_next_candidates.push_back(c);
  }
  // Pairs that left: their trackers go. Pairs that entered: their box distance is their bound
  // (check_vacated certifies them apart, seed_in_contact seeds them in contact), but pairs
  // those cannot certify are seeded now. Pairs that stayed keep their carried bound unless the
  // box distance now is at least as high.
  // (By key: in contact every candidate pair has a tracker, and thousands of mesh triangles'
  // pairs made a scan of the trackers per candidate most of a step.)
  index_live();
  std::size_t i = 0, j = 0;
  auto drop = [&](std::uint64_t key) { each_live(key, [&](int k) { kill(k); }); };
  while (i < m_candidates.size() || j < m_next_candidates.size()) {
    if (j == m_next_candidates.size() ||
        (i < m_candidates.size() && m_candidates[i].key < m_next_candidates[j].key)) {
      release_solves(m_candidates[i]);
      drop(m_candidates[i++].key);
    } else if (i == m_candidates.size() || m_next_candidates[j].key < m_candidates[i].key) {
      const std::uint64_t key = m_next_candidates[j++].key;
      // (A tracker may have arrived by a transition.)
      const int pa = key_a(key), pb = key_b(key);
      if (!certifiable(pa, pb)) {
        bool tracked = false;
        each_live(key, [&](int) { tracked = true; });
        if (!tracked) seed_pair(pa, pb, X_WA, X_WB);
      }
    } else {
      // The carried bound (with its pose, reach and carried sides) when it is the higher one;
      // the slack in any case, and so, for a pair seeded in contact whose solve certified it
      // apart, that bound and pose (see seed_in_contact).
      Candidate& next = m_next_candidates[j];
      Candidate& was = m_candidates[i];
      if (was.lower > next.lower) {
        next = was;
      } else {
        release_solves(was);  // (its proofs go with it)
        next.slack = was.slack;
        if (was.seeded_lower < HUGE_VAL) {
          next.contact_seeded = was.contact_seeded;
          next.seeded_lower = was.seeded_lower;
          next.seeded_at = was.seeded_at;
        }
      }
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
  m_kept_proof_total = m_kept_bound_total = 0;
  for (const Candidate& c : m_candidates) {
    m_kept_proof_total += c.proof_count;
    m_kept_bound_total += c.bound_count;
  }
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
  m_live[place(pa, pb, params, X_WA, X_WB)].seeded_apart = g.distance > m_options.contact_tolerance;
  return true;
}

int Body_pair_tracker::place(int pa, int pb, const Vec4& params, const Rigid_pose_3& X_WA,
                             const Rigid_pose_3& X_WB) {
  // Another basin of a tracked pair: its tracker moves there, one whose witnesses left the
  // bodies first.
  int moved = -1;
  for (std::size_t k = 0; k < m_live.size(); ++k)
    if (m_live[k].alive && m_live[k].pa == pa && m_live[k].pb == pb && !m_live[k].closed_form &&
        (moved < 0 || (m_live[moved].valid && !m_live[k].valid)))
      moved = static_cast<int>(k);
  if (moved >= 0) {
    m_live[moved].tracker.reset(params);
    m_live[moved].stepped = -1;
    m_live[moved].seeded_apart = m_live[moved].behind_sheet = false;
    m_live[moved].holds_unreached = m_live[moved].was_shallower = false;
    return moved;
  }
  const int slot = add_live(pa, pb, params);
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
  return slot;
}

void Body_pair_tracker::start(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) {
  // An open sheet A against a solid B: the solid's normal tells inside from apart (a solid
  // that passed through a sheet and left it behind read minus its distance: the right pair
  // held nothing, and another, 0.16 farther, was reported).
  m_options.tracker.sign_from_b = !closed(0) && closed(1);
  for (std::size_t k = 0; k < m_live.size(); ++k)
    if (m_live[k].alive) kill(static_cast<int>(k));
  m_candidates.clear();
  m_proofs.clear();
  m_bounds.clear();
  m_solve_poses.clear();
  m_free_solve_blocks.clear();
  m_kept_proof_total = m_kept_bound_total = 0;
  m_started = true;
  m_deep_checked = HUGE_VAL;
  const Distance_result g = global_solve(X_WA, X_WB);
  broad_phase(X_WA, X_WB, std::max(g.upper_bound, 0.0) + reach_margin());
  // The certified pair, should the broad phase have missed it (duplicates merge after the
  // first step).
  seed_from(g, X_WA, X_WB, std::numeric_limits<double>::infinity());
  m_meets_at_start = g.status == Distance_status::Intersecting;
  if (m_meets_at_start) {
    m_start_solve = g;
    m_start_relative = X_WA.inverse() * X_WB;
  }
  if (seed_overlap(g, X_WA, X_WB, false))  // inside, the broad phase reaches across the depth
    broad_phase(X_WA, X_WB, -m_solved.distance + reach_margin());
}

void Body_pair_tracker::step_live(int k) {
  Live& L = m_live[k];
  const bool first = L.stepped == -1;
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
  judge(k, first);
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
        // Only onto a face that starts no farther than the edge: a B-rep edge lies on its faces
        // only up to the file's tolerance (screw.step: 1.8e-4 off at a ball 1 mm away), and a
        // face that starts above it may settle above it, where the edge's pair is lower. (A
        // face pair that does come closer is found as any other, by check_vacated.)
        Surface_point fp;
        S.evaluate(cq[0], cq[1], fp, 0);
        const double from_face = (X.apply_point(fp.p) - other).norm();
        const double slack = std::max(m_options.seeding.absolute_tolerance,
                                      m_options.seeding.relative_tolerance * r.distance);
        if (inward > 1e-10 * std::max(scale[0], scale[1]) && from_face <= r.distance + slack) {
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
    L.holds_unreached = L.was_shallower = false;
    ++m_report.transitions;
    step_live(k);
    return true;
  }
  return false;
}

void Body_pair_tracker::merge_duplicates() {
  const double tol = 1e-7 * std::max(box_diagonal(m_model_a->box()), box_diagonal(m_model_b->box()));
  // Only trackers of one primitive pair can merge: compared within runs of equal keys, in slot
  // order (index_live sorts by key, then slot).
  index_live();
  for (std::size_t first = 0, last = 0; first < m_live_keys.size(); first = last) {
    last = first + 1;
    while (last < m_live_keys.size() && m_live_keys[last].first == m_live_keys[first].first) ++last;
    for (std::size_t a = first; a < last; ++a) {
      const std::size_t i = static_cast<std::size_t>(m_live_keys[a].second);
      if (!m_live[i].alive) continue;
      for (std::size_t b = a + 1; b < last; ++b) {
        const std::size_t j = static_cast<std::size_t>(m_live_keys[b].second);
        Live& x = m_live[i];
        Live& y = m_live[j];
        if (!y.alive) continue;
        if ((x.result.point_a - y.result.point_a).norm() +
                (x.result.point_b - y.result.point_b).norm() >
            tol)
          continue;
        if (!x.valid && y.valid) {  // keep the one that holds (a wandering seed does not)
          kill(static_cast<int>(i));
          ++m_report.merges;
          break;
        }
        kill(static_cast<int>(j));
        ++m_report.merges;
      }
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
  if (m_apart_unheld && best_d > m_options.contact_tolerance) best = -1;
  r.trackers = trackers;
  r.candidates = static_cast<int>(m_candidates.size());
  // No tracker holds: the solver's answer of this step (a step whose trackers hold nothing
  // solves again).
  r.solved = best < 0;
  const Solved& s = m_solved;
  const Track_result* tr = best >= 0 ? &m_live[best].result : nullptr;
  const int pa = tr ? m_live[best].pa : s.pa, pb = tr ? m_live[best].pb : s.pb;
  const Vec4& params = tr ? tr->params : s.params;
  r.distance = tr ? tr->distance : s.distance;
  r.point_a = tr ? tr->point_a : s.point_a;
  r.point_b = tr ? tr->point_b : s.point_b;
  r.normal = tr ? tr->normal : s.normal;
  r.degeneracy = tr ? tr->degeneracy : Degeneracy::None;
  r.feature_a = r.feature_b = r.edge_a = r.edge_b = -1;
  r.params.setZero();
  if (pa >= 0 && pb >= 0) {
    const int na = m_model_a->primitives()[pa].feature.dimension();
    double qa[2] = {0, 0}, qb[2] = {0, 0};
    int da = 0, db = 0;
    r.feature_a = report_feature(*m_model_a, pa, params.data(), qa, r.edge_a, da);
    r.feature_b = report_feature(*m_model_b, pb, params.data() + na, qb, r.edge_b, db);
    for (int c = 0; c < da; ++c) r.params[c] = qa[c];
    for (int c = 0; c < db; ++c) r.params[da + c] = qb[c];
  }
  const double tol = m_options.contact_tolerance;
  r.status = r.distance < -tol                                     ? Pair_status::Penetrating
             : r.distance <= tol                                   ? Pair_status::Contact
             : tr && tr->status == Track_status::Singular_fallback ? Pair_status::Fallback
             : tr && tr->status == Track_status::On_boundary       ? Pair_status::Boundary
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
    r.solved = false;
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
  m_apart_unheld = false;
  m_relative = X_WA.inverse() * X_WB;
  if (!m_started) {
    start(X_WA, X_WB);
    m_previous_relative = m_relative;
  }
  // 1. Step the live trackers at t; hand the ones that left their primitive across.
  double best = std::numeric_limits<double>::infinity();
  auto step_all = [&] {
    step_pending();
    best = std::numeric_limits<double>::infinity();
    for (const Live& L : m_live)
      if (L.alive && L.valid) best = std::min(best, L.result.distance);
  };
  step_all();
  // Deep inside, the tracked pair may no longer be the depth (see check_deep). A penetration
  // pair that has just become shallower than the tracked depth (by more than its tolerance)
  // may be the depth now, whether it holds or would but for not having come through contact:
  // the deep check runs. A peg slid off a box's corner: the corner's pair, held or seeded
  // inside, read 2.9 to 0.4 while the cap's stale 3 was reported for up to 6 steps, until the
  // motion check. Once each time a pair becomes shallower (a step it holds nothing leaves its
  // flag as it was: a pair flickering in and out of holding does not solve each time).
  bool shallower_depth = false;
  for (Live& L : m_live) {
    if (!L.alive || !(L.valid || L.holds_unreached)) continue;
    const bool shallower = L.result.distance < -m_options.contact_tolerance &&
                           L.result.distance > best + depth_tolerance(best);
    if (shallower && !L.was_shallower) shallower_depth = true;
    L.was_shallower = shallower;
  }
  if (!(best < -m_options.contact_tolerance)) m_deep_checked = HUGE_VAL;
  else if (check_deep(X_WA, X_WB, best, shallower_depth)) step_all();
  // 2. Broad phase where the candidate set may miss a pair within |best| plus the margin (|best|:
  //    inside, the tracked pair's own primitives lie |best| apart): entering pairs get a bound,
  //    far ones go. A set built with reach R holds every pair that was within R then, so every
  //    pair within R less the relative motion since (k_broad_extra).
  // 3. Candidate pairs without a tracker may hold a new basin closer than the tracked minimum:
  //    the certified solver on the pair, cut off at it, says so at little cost when they do
  //    not. In contact (a signed minimum) every candidate pair gets a tracker instead.
  // 4. Lost everything (all witnesses off the bodies): the certified solver re-seeds.
  if (std::isfinite(best)) {
    const double length = std::max(box_diagonal(m_model_a->box()), box_diagonal(m_model_b->box()));
    const double reach = std::abs(best) + reach_margin();
    if (!near_pose(m_relative, m_last_relative, length) &&
        reach + approach_bound(m_model_a->box(), m_model_b->box(), m_last_relative, m_relative)
                    .closer > m_broad_reach) {
      broad_phase(X_WA, X_WB, reach + k_broad_extra * reach_margin());
      step_all();
    }
    if (best > m_options.contact_tolerance) {
      // A pair certified to meet while every tracker read the bodies apart (the trackers on
      // its surfaces hold nothing): they are not apart. The whole pair is solved as one lost
      // (the hulls' depth where no tracker takes it), and a tracker reading apart is no answer.
      if (check_vacated(X_WA, X_WB, best)) {
        const Distance_result g = global_solve(X_WA, X_WB);
        if (seed_overlap(g, X_WA, X_WB, true)) ++r.reseeds;  // (keeps g, or the hulls' depth)
        step_all();
        m_apart_unheld = !(best <= m_options.contact_tolerance);
      }
    } else {
      // A pair seeded inside that reads deeper than the depth is checked before it is reported:
      // a peg 1 deep slid off a box's corner had its cap's pair, just dropped by the deep check
      // (the corner's 0.49 the depth), seeded again, and its 1 was read for a step or two.
      const double depth = best;
      if (seed_in_contact(X_WA, X_WB)) {
        step_all();
        if (depth < -m_options.contact_tolerance && best < depth - depth_tolerance(depth) &&
            check_deep(X_WA, X_WB, best, true))
          step_all();
      }
    }
  }
  // Non-convex bodies whose surfaces crossed at the start: when none of the trackers seeded at
  // the common points (the start's and the candidates') found a penetration pair, the hulls'
  // may be one (see seed_overlap). At the start's poses only (start() may run before a step).
  if (m_meets_at_start) {
    m_meets_at_start = false;
    if (same_pose(m_relative, m_start_relative)) {
      if (!(best < -m_options.contact_tolerance) && seed_overlap(m_start_solve, X_WA, X_WB, true))
        step_all();
      // The surfaces cross here: a tracker reading apart is no answer (a box started across a
      // sheet's border read +21, the hulls' depth with the sheet's sign, where it is -21).
      if (!(best <= m_options.contact_tolerance)) m_apart_unheld = true;
    }
  }
  // Nothing on the bodies (witnesses left them, or trackers wandering in a deep overlap): the
  // certified solver seeds again, and its answer is reported while no tracker holds. The
  // penetrating trackers that hold nothing go first (they would pile up).
  auto solve_lost = [&] {
    for (std::size_t k = 0; k < m_live.size(); ++k)
      if (m_live[k].alive && !m_live[k].valid &&
          m_live[k].result.distance < -m_options.contact_tolerance)
        kill(static_cast<int>(k));
    const Distance_result g = global_solve(X_WA, X_WB);
    if (seed_from(g, X_WA, X_WB, std::numeric_limits<double>::infinity())) ++r.reseeds;
    if (seed_overlap(g, X_WA, X_WB, true)) ++r.reseeds;
    step_all();
    // The surfaces cross by this step's solve: a tracker seeded at the common point that
    // reads apart (not converged: a point of each surface, near each other) is no answer.
    if (g.status == Distance_status::Intersecting && !(best <= m_options.contact_tolerance))
      m_apart_unheld = true;
  };
  if (!std::isfinite(best)) solve_lost();
  merge_duplicates();
  if (m_options.audit_every > 0 && m_steps % m_options.audit_every == 0 &&
      seed_from_global(X_WA, X_WB, best)) {
    ++r.reseeds;
    step_all();
  }
  // No tracker holds at the end of the step while the solver's last answer is an earlier
  // step's (the trackers seeded from it read the pair behind a sheet, say): solved again, so
  // that no row repeats an earlier step's answer (a screw out below a plane read the step
  // before's 0.68 where it was 1.88 apart).
  if (m_solved.step != m_steps &&
      std::none_of(m_live.begin(), m_live.end(), [](const Live& L) { return L.alive && L.valid; }))
    solve_lost();
  fill_report();
  m_previous_relative = m_relative;
  m_last_A = X_WA;
  m_last_B = X_WB;
  m_have_pose = true;
  return r;
}

}  // namespace extremal
