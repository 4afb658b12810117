// Tracks the extremal pair between two bodies made of several features (faces, curves or a
// point): one Extremal_tracker per candidate feature pair, the pair's answer the minimum over
// them, with feature ids.
#pragma once

#include <vector>

#include <memory>

#include "algorithms/Extremal_tracker.h"
#include "algorithms/Global_distance.h"
#include "kernel/Body.h"

namespace extremal {

enum class Pair_status {
  Tracking,     // apart, tracked
  Contact,      // touching: |distance| within the contact tolerance
  Penetrating,  // distance below minus the contact tolerance
  Boundary,     // apart, the pair on a patch edge or corner
  Farther,      // beyond the threshold: not tracked
  Fallback,     // degenerate geometry: damped step (Pair_report::degeneracy says why)
};
const char* to_string(Pair_status s);

struct Pair_report {
  double time = 0.0;
  double distance = 0.0;  // signed where the geometry has an outward side
  Vec3 point_a = Vec3::Zero(), point_b = Vec3::Zero(), normal = Vec3::Zero();
  int feature_a = -1, feature_b = -1;  // face index (curves follow the faces)
  Vec4 params = Vec4::Zero();
  Pair_status status = Pair_status::Tracking;
  Degeneracy degeneracy = Degeneracy::None;
  int trackers = 0;  // live feature-pair trackers
  int audits = 0, reseeds = 0;  // global audits so far and the trackers they seeded
};

struct Body_pair_options {
  // Scenes correct the pair when one step's linearisation falls short (see
  // Tracker_options::corrections).
  Tracker_options tracker = [] {
    Tracker_options o;
    o.corrections = 10;
    return o;
  }();
  double threshold = 0.0;  // > 0: pairs whose boxes are farther apart are not tracked
  double contact_tolerance = 1e-9;  // |distance| at or below this is contact
  int seed_samples = 16;   // samples per surface direction when seeding (32 per curve)
  // Steps between audits by the certified global solver (0 = never): when the global minimum
  // has moved to another feature pair, a tracker is seeded there.
  int audit_every = 0;
  // The certified solver's request for the start and the audits.
  Distance_request global = [] {
    Distance_request r;
    r.absolute_tolerance = 1e-7;
    r.relative_tolerance = 1e-7;
    r.max_nodes = 50000;
    return r;
  }();
};

class Body_pair_tracker {
 public:
  // The bodies must outlive the tracker.
  Body_pair_tracker(const Body& a, const Body& b, const Body_pair_options& options = {});

  // Converged solve at rest at poses X_WA, X_WB: a tracker on the certified global pair, plus
  // one per other feature pair whose sampled and Newton-polished minimum can compete. Called by
  // the first step if not before.
  void start(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB);

  const Pair_report& step(double t, const Rigid_pose_3& X_WA, const Twist_3& V_A,
                          const Rigid_pose_3& X_WB, const Twist_3& V_B, double dt);

  const std::vector<Feature>& features_a() const { return m_features_a; }
  const std::vector<Feature>& features_b() const { return m_features_b; }

 private:
  struct Live {
    int fa, fb;
    Extremal_tracker tracker;
  };
  bool is_farther(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) const;
  // Feature index of a global result's element on side A or B.
  int feature_index(const Body& body, Element_kind kind, int element) const;
  // Runs the global solver; seeds (or re-seeds) the tracker of its feature pair when it beats
  // `tracked` by more than its tolerance. Returns true if it seeded.
  bool seed_from_global(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB, double tracked);

  const Body& m_a;
  const Body& m_b;
  Body_pair_options m_options;
  std::vector<Feature> m_features_a, m_features_b;
  std::vector<Live> m_live;
  std::unique_ptr<Distance_hierarchy> m_hierarchy_a, m_hierarchy_b;  // built at the first start
  Distance_workspace m_workspace;
  bool m_started = false;
  long m_steps = 0;
  Pair_report m_report;
};

// The features of a body: its faces, then its curves; a point body is its origin.
std::vector<Feature> features_of(const Body& body);

// Lower bound on the distance between two boxes (0 if they overlap).
double box_distance(const Bbox_3& a, const Bbox_3& b);

}  // namespace extremal
