#include "algorithms/Body_pair_tracker.h"

#include <algorithm>
#include <cmath>
#include <limits>

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

double box_distance(const Bbox_3& a, const Bbox_3& b) {
  double s = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double gap = std::max(a.min(i) - b.max(i), b.min(i) - a.max(i));
    if (gap > 0.0) s += gap * gap;
  }
  return std::sqrt(s);
}

namespace {

// Sample parameters of a feature at the centres of a regular grid of cells: interior, so a
// seed on a flat continuum starts away from the edges (Newton still reaches an edge or corner
// when the pair lies there).
std::vector<Vec4> sample_params(const Feature& f, int n) {
  std::vector<Vec4> out;
  auto at = [&](int dir, int i, int count) {
    return f.lower(dir) + (f.upper(dir) - f.lower(dir)) * (i + 0.5) / count;
  };
  if (f.dimension() == 0) {
    out.push_back(Vec4::Zero());
  } else if (f.dimension() == 1) {
    for (int i = 0; i < 2 * n; ++i) out.push_back(Vec4(at(0, i, 2 * n), 0, 0, 0));
  } else {
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) out.push_back(Vec4(at(0, i, n), at(1, j, n), 0, 0));
  }
  return out;
}

// How far parameters sit from the middle of their domain (0 at the centre, 1 at a corner).
double off_centre(const Feature& f, const Vec4& p) {
  double s = 0.0;
  for (int i = 0; i < f.dimension(); ++i) {
    const double mid = 0.5 * (f.lower(i) + f.upper(i)), half = 0.5 * (f.upper(i) - f.lower(i));
    s += ((p[i] - mid) / half) * ((p[i] - mid) / half);
  }
  return s;
}

Bbox_3 world_box(const Feature& f, const Rigid_pose_3& X) {
  if (f.surface()) return transformed(f.surface()->hull_bbox(), X);
  if (f.curve()) return transformed(f.curve()->hull_bbox(), X);
  return to_point(X.apply_point(f.point_in_body())).bbox();
}

}  // namespace

Body_pair_tracker::Body_pair_tracker(const Body& a, const Body& b,
                                     const Body_pair_options& options)
    : m_a(a), m_b(b), m_options(options), m_features_a(features_of(a)),
      m_features_b(features_of(b)) {}

bool Body_pair_tracker::is_farther(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) const {
  if (!(m_options.threshold > 0.0)) return false;
  return box_distance(transformed(m_a.hull_bbox(), X_WA), transformed(m_b.hull_bbox(), X_WB)) >
         m_options.threshold;
}

int Body_pair_tracker::feature_index(const Body& body, Element_kind kind, int element) const {
  switch (kind) {
    case Element_kind::Point: return 0;
    case Element_kind::Face: return element;
    case Element_kind::Curve: return static_cast<int>(body.faces.size()) + element;
  }
  return -1;
}

bool Body_pair_tracker::seed_from_global(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB,
                                         double tracked) {
  if (!m_hierarchy_a) {
    m_hierarchy_a = std::make_unique<Distance_hierarchy>(m_a);
    m_hierarchy_b = std::make_unique<Distance_hierarchy>(m_b);
  }
  const Distance_result g =
      extremal_distance(*m_hierarchy_a, X_WA, *m_hierarchy_b, X_WB, m_options.global, m_workspace);
  ++m_report.audits;
  if (g.element_a < 0 || g.element_b < 0) return false;
  if (!(g.upper_bound < tracked - g.tolerance_used)) return false;
  const Tracker_seed seed = tracker_seed(m_a, m_b, g);
  const int fa = feature_index(m_a, seed.kind_a, seed.element_a);
  const int fb = feature_index(m_b, seed.kind_b, seed.element_b);
  if (fa < 0 || fa >= static_cast<int>(m_features_a.size()) || fb < 0 ||
      fb >= static_cast<int>(m_features_b.size()))
    return false;
  for (Live& live : m_live)
    if (live.fa == fa && live.fb == fb) {
      live.tracker.reset(seed.params);  // another basin of the same feature pair
      return true;
    }
  m_live.push_back({fa, fb,
                    Extremal_tracker(m_features_a[fa], m_features_b[fb], seed.params,
                                     m_options.tracker)});
  return true;
}

void Body_pair_tracker::start(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) {
  m_live.clear();
  m_started = true;
  struct Seed {
    int fa, fb;
    Vec4 params;
    double distance;
  };
  std::vector<Seed> seeds;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < m_features_a.size(); ++i) {
    const Feature& A = m_features_a[i];
    const auto pa = sample_params(A, m_options.seed_samples);
    std::vector<Vec3> wa;
    for (const Vec4& p : pa) {
      Feature_point fp;
      evaluate_feature(A, X_WA, p.data(), fp, 0);
      wa.push_back(fp.p);
    }
    for (std::size_t j = 0; j < m_features_b.size(); ++j) {
      const Feature& B = m_features_b[j];
      const auto pb = sample_params(B, m_options.seed_samples);
      // Closest sample pair; among (near) ties the most central one, so that a continuum of
      // pairs (flat on flat) is seeded away from the edges.
      double d2 = std::numeric_limits<double>::infinity(), centrality = d2;
      std::size_t bi = 0, bj = 0;
      for (std::size_t jj = 0; jj < pb.size(); ++jj) {
        Feature_point fp;
        evaluate_feature(B, X_WB, pb[jj].data(), fp, 0);
        const double cb = off_centre(B, pb[jj]);
        for (std::size_t ii = 0; ii < wa.size(); ++ii) {
          const double e = (wa[ii] - fp.p).squaredNorm();
          const double c = cb + off_centre(A, pa[ii]);
          const bool tie = std::abs(e - d2) <= 1e-12 * (d2 + 1e-300);
          if ((!tie && e < d2) || (tie && c < centrality)) d2 = e, centrality = c, bi = ii, bj = jj;
        }
      }
      Vec4 start = Vec4::Zero();
      start.head(A.dimension()) = pa[bi].head(A.dimension());
      start.segment(A.dimension(), B.dimension()) = pb[bj].head(B.dimension());
      const Newton_result n =
          solve_pair_at_rest({&A, &X_WA, nullptr}, {&B, &X_WB, nullptr}, start);
      Pair_system s;
      build_pair_system({&A, &X_WA, nullptr}, {&B, &X_WB, nullptr}, n.params, s, false);
      const double d = s.d.norm();
      best = std::min(best, d);
      seeds.push_back({static_cast<int>(i), static_cast<int>(j), n.params, d});
    }
  }
  // Keep feature pairs whose boxes could still hold the minimum.
  for (const Seed& s : seeds) {
    const double lower = box_distance(world_box(m_features_a[s.fa], X_WA),
                                      world_box(m_features_b[s.fb], X_WB));
    if (lower > best + 1e-9 * (1.0 + best)) continue;
    m_live.push_back({s.fa, s.fb,
                      Extremal_tracker(m_features_a[s.fa], m_features_b[s.fb], s.params,
                                       m_options.tracker)});
  }
  // The certified global pair, where sampling missed it.
  if (seed_from_global(X_WA, X_WB, best)) ++m_report.reseeds;
}

const Pair_report& Body_pair_tracker::step(double t, const Rigid_pose_3& X_WA, const Twist_3& V_A,
                                           const Rigid_pose_3& X_WB, const Twist_3& V_B,
                                           double dt) {
  Pair_report& r = m_report;
  r.time = t;
  if (is_farther(X_WA, X_WB)) {
    r.status = Pair_status::Farther;
    r.distance = box_distance(transformed(m_a.hull_bbox(), X_WA), transformed(m_b.hull_bbox(), X_WB));
    r.point_a = r.point_b = r.normal = Vec3::Zero();
    r.feature_a = r.feature_b = -1;
    r.degeneracy = Degeneracy::None;
    r.trackers = 0;
    m_started = false;  // re-seed when the pair comes back within the threshold
    return r;
  }
  if (!m_started) start(X_WA, X_WB);
  ++m_steps;
  double best = std::numeric_limits<double>::infinity();
  for (Live& live : m_live) {
    const Track_result& tr = live.tracker.step(t, X_WA, V_A, X_WB, V_B, dt);
    if (tr.distance < best) {
      best = tr.distance;
      r.distance = tr.distance;
      r.point_a = tr.point_a;
      r.point_b = tr.point_b;
      r.normal = tr.normal;
      r.params = tr.params;
      r.feature_a = live.fa;
      r.feature_b = live.fb;
      r.degeneracy = tr.degeneracy;
      const double tol = m_options.contact_tolerance;
      // Contact and penetration matter most to a simulator; the degeneracy stays in
      // r.degeneracy whatever the status.
      r.status = tr.distance < -tol                           ? Pair_status::Penetrating
                 : tr.distance <= tol                         ? Pair_status::Contact
                 : tr.status == Track_status::Singular_fallback ? Pair_status::Fallback
                 : tr.status == Track_status::On_boundary     ? Pair_status::Boundary
                                                              : Pair_status::Tracking;
    }
  }
  r.trackers = static_cast<int>(m_live.size());
  if (m_options.audit_every > 0 && m_steps % m_options.audit_every == 0 &&
      seed_from_global(X_WA, X_WB, best))
    ++r.reseeds;
  return r;
}

}  // namespace extremal
