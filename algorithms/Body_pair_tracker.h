// Tracks the extremal pair between two bodies made of several features (faces, curves or a
// point): one Extremal_tracker per candidate feature pair, the pair's answer the minimum over
// them, with feature ids.
#pragma once

#include <vector>

#include "algorithms/Extremal_tracker.h"
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
};

class Body_pair_tracker {
 public:
  // The bodies must outlive the tracker.
  Body_pair_tracker(const Body& a, const Body& b, const Body_pair_options& options = {});

  // Converged solve at rest at poses X_WA, X_WB: seeds one tracker per feature pair that can
  // hold the minimum and converges it. Called by the first step if not before.
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

  const Body& m_a;
  const Body& m_b;
  Body_pair_options m_options;
  std::vector<Feature> m_features_a, m_features_b;
  std::vector<Live> m_live;
  bool m_started = false;
  Pair_report m_report;
};

// The features of a body: its faces, then its curves; a point body is its origin.
std::vector<Feature> features_of(const Body& body);

// Lower bound on the distance between two boxes (0 if they overlap).
double box_distance(const Bbox_3& a, const Bbox_3& b);

}  // namespace extremal
