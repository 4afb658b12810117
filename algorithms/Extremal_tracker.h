// Tracks the extremal pair between two moving features (the seed's feedback-linearising
// controller, ../shared/DESIGN.md section 1): U = M^-1 (-K Phi - b), parameters integrated
// from U, Phi recomputed from the geometry at every step (the seed's Figure 4 variant).
#pragma once

#include "algorithms/Feature.h"
#include "algorithms/Pair_geometry.h"

namespace extremal {

enum class Integrator { Euler, Rk4 };

struct Tracker_options {
  // Gain K in 1/s per parameter (A's first, then B's). A zero entry means 1/dt for that
  // step, which makes one Euler step a Newton step plus the motion feed-forward.
  Vec4 gain = Vec4::Zero();
  int substeps = 1;  // integration substeps per step
  Integrator integrator = Integrator::Euler;
  // Newton corrections at time t before reporting, made only while some normalised projection
  // error exceeds `correction_tolerance`. Where one linearised step per frame is not enough
  // (the pair sweeping past a pole of the parametrisation, a sudden jump in the motion) they
  // keep the reported pair exact; 0 gives the seed's pure controller.
  int corrections = 0;
  double correction_tolerance = 1e-7;

  static Tracker_options with_gain(double k) {
    Tracker_options o;
    o.gain.setConstant(k);
    return o;
  }
};

enum class Track_status {
  Tracking,           // regular step
  Singular_jacobian,  // M singular or not finite: parameters kept from the last good step
};
const char* to_string(Track_status s);

struct Track_result {
  double time = 0.0;
  double distance = 0.0;        // |f - h| at the current parameters
  Vec3 point_a = Vec3::Zero();  // witness on A, world
  Vec3 point_b = Vec3::Zero();  // witness on B, world
  Vec3 normal = Vec3::Zero();   // unit, from A to B: point_b - point_a = distance * normal
  Vec4 params = Vec4::Zero();   // [A's..., B's...] at which the result was evaluated
  Vec4 projection_errors = Vec4::Zero();
  Vec4 normalised_errors = Vec4::Zero();  // Phi_k / (|d| |tangent_k|)
  int iterations = 0;  // linear solves spent in this step
  Track_status status = Track_status::Tracking;
};

class Extremal_tracker {
 public:
  // `initial` holds the starting parameters (anywhere in the domains). The features must
  // outlive the tracker. Throws Precondition_violation on a negative or non-finite gain or
  // substeps < 1.
  Extremal_tracker(const Feature& a, const Feature& b, const Vec4& initial,
                   const Tracker_options& options = {});

  // One step: evaluates the pair at the poses and twists of time t (the result describes time
  // t), then integrates the parameters over [t, t + dt] (twists held constant over the step).
  // dt must be > 0. No heap allocation.
  [[nodiscard]] const Track_result& step(double t, const Rigid_pose_3& X_WA, const Twist_3& V_A,
                                         const Rigid_pose_3& X_WB, const Twist_3& V_B, double dt);

  // Evaluates the pair at the current parameters without moving them.
  [[nodiscard]] const Track_result& evaluate(double t, const Rigid_pose_3& X_WA,
                                             const Rigid_pose_3& X_WB);

  const Vec4& params() const { return m_params; }
  void reset(const Vec4& params);
  const Feature& feature_a() const { return m_a; }
  const Feature& feature_b() const { return m_b; }
  const Tracker_options& options() const { return m_options; }

 private:
  // Parameter velocity U at `params` for poses and twists; false if M is singular.
  bool control(const Vec4& params, const Rigid_pose_3& X_WA, const Twist_3& V_A,
               const Rigid_pose_3& X_WB, const Twist_3& V_B, double dt, Vec4& U);
  void fill_result(double t);
  // Newton corrections at rest at the given poses (see Tracker_options::corrections); returns
  // how many were made.
  int correct(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB);

  Feature m_a, m_b;
  Tracker_options m_options;
  Parameter_domain m_domain;
  Vec4 m_params;
  Vec4 m_max_change;  // largest parameter change per step
  Pair_system m_system;
  Track_result m_result;
};

}  // namespace extremal
