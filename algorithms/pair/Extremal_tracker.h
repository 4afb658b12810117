// Tracks the extremal pair between two moving features (the seed's feedback-linearising
// controller, docs/design.md, "The seed's method"): U = M^-1 (-K Phi - b), parameters
// integrated from U, the conditions recomputed from the geometry at every step (the seed's
// Figure 4 variant). Near contact the normal form of the conditions takes over so the pair
// passes through contact into penetration; on patch edges the pair continues as the reduced
// problem; degenerate geometry falls back to damped least squares.
#pragma once

#include "algorithms/pair/Feature.h"
#include "algorithms/pair/Pair_geometry.h"

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
  // The normal form is used while |d| is below this fraction of the smaller feature size (and
  // left above twice that): the hand-over band around contact.
  double contact_band = 0.05;
  // The distance's sign from B's outward normal wherever B's witness is an interior point of a
  // surface (else as below): for an open sheet A against a solid B, whose inside the sheet's
  // normal does not tell (a solid apart behind a sheet read minus its distance).
  // Body_pair_tracker sets it itself from the bodies' closedness.
  bool sign_from_b = false;

  static Tracker_options with_gain(double k) {
    Tracker_options o;
    o.gain.setConstant(k);
    return o;
  }
};

enum class Track_status {
  Tracking,           // regular step
  On_boundary,        // some parameter sits on a patch edge: the reduced problem is tracked
  Singular_fallback,  // M singular: damped least squares (see Degeneracy for why)
};
const char* to_string(Track_status s);

// What made M singular when the tracker fell back.
enum class Degeneracy {
  None,
  Pole,        // a collapsed edge of the parametrisation (f_u = 0 or f_v = 0)
  Parallel,    // parallel tangent planes at distance: flat on flat, equal curvature
  Coincident,  // the surfaces coincide at the pair
  Singular,    // anything else
};
const char* to_string(Degeneracy d);

struct Track_result {
  double time = 0.0;
  // Signed extremal distance: positive apart, zero at tangential contact, negative inside (the
  // local maximum penetration depth). Its sign comes from A's outward normal when A is a
  // surface, else from B's (B's first with Tracker_options::sign_from_b); between curves and
  // points it is |f - h|.
  double distance = 0.0;
  Vec3 point_a = Vec3::Zero();  // witness on A, world
  Vec3 point_b = Vec3::Zero();  // witness on B, world
  Vec3 normal = Vec3::Zero();   // unit, from A to B: point_b - point_a = distance * normal
  Vec4 params = Vec4::Zero();   // [A's..., B's...] at which the result was evaluated
  Vec4 projection_errors = Vec4::Zero();
  Vec4 normalised_errors = Vec4::Zero();  // Phi_k / (|d| |tangent_k|)
  int iterations = 0;  // linear solves spent in this step
  int corrections = 0;  // of them, corrections at the start of the step (Tracker_options)
  Track_status status = Track_status::Tracking;
  Degeneracy degeneracy = Degeneracy::None;
  bool normal_form = false;  // the contact (normal) form of the conditions was active
  // In the normal form: the largest |n_R . t_j| / |t_j| over the free parameters of the side
  // opposite the reference surface R (the cosine between R's normal and a tangent there,
  // zero once the normals are parallel); 0 in the projection form. Unlike the projection
  // errors it is defined at d = 0, where the normal form runs.
  double alignment_error = 0.0;
  // In the normal form: the largest |normalised_errors| over the reference surface's own
  // parameters (zero once d lies along its normal); 0 in the projection form.
  double reference_error = 0.0;
  // In the normal form: the largest |d . t_j| / (|d| |t_j|) over the free parameters of the
  // side opposite the reference (zero once that side's witness is the foot of d there; a
  // parameter held on an edge carries no such condition); 0 in the projection form or at d = 0.
  double other_error = 0.0;
  unsigned on_edge = 0u;  // bit k: parameter k on a patch edge (poles excluded)
};

class Extremal_tracker {
 public:
  // `initial` holds the starting parameters (anywhere in the domains). The features must
  // outlive the tracker. Throws Precondition_violation on a negative or non-finite gain,
  // substeps < 1 or corrections < 0.
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
  // Parameter velocity U at `params`; `twists` null means at rest (a Newton correction).
  // Records the degeneracy when it had to damp.
  void control(const Vec4& params, const Rigid_pose_3& X_WA, const Twist_3* V_A,
               const Rigid_pose_3& X_WB, const Twist_3* V_B, double gain_dt, Vec4& U,
               Degeneracy& degeneracy);
  // The form for a pair at `params` whose parameters on patch edges are `on_edge` (edge_mask).
  Formulation choose_form(unsigned on_edge, const Vec4& params) const;
  // Whether a parameter of side 0 (A) or 1 (B) lies within `fraction` of its range from a pole.
  bool near_pole(int side, const Vec4& params, double fraction) const;
  // Sets m_reference_at_pole for the pair at `params` (with hysteresis).
  void update_reference_at_pole(const Vec4& params);
  // Bit k set when parameter k sits on a patch edge (poles excluded).
  unsigned edge_mask(const Vec4& params) const;
  // Signed |d| for the system last built, at `params`, whose edge_mask is `on_edge`.
  double signed_distance(unsigned on_edge, const Vec4& params) const;
  Degeneracy classify_singular() const;
  // For the system last built at `params`, in the normal form or inside in the projection
  // form: the held parameters (of `on_edge`, lower bounds in `lower`) of the side opposite the
  // reference whose witness would rise above the reference's tangent plane off its edge.
  unsigned held_by_height(unsigned on_edge, unsigned lower, const Vec4& params) const;
  // A parameter that crossed a collapsed edge (a pole) continues on the other side of it.
  void cross_poles(Vec4& x) const;
  // In the normal form: moves parameters that sit on a pole just off it.
  void leave_poles(Vec4& x) const;
  // Clamps `params` into the domain; bit k set when parameter k sits on a patch edge (a bound
  // that is not a pole).
  unsigned clamp_to_edges(Vec4& params) const;
  int correct(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB, Degeneracy& degeneracy);
  // The result for the system last built, at m_params, whose edge_mask is `on_edge`.
  void fill_result(double t, double signed_dist, unsigned on_edge);

  Feature m_a, m_b;
  Tracker_options m_options;
  Parameter_domain m_domain;
  Vec4 m_params;
  Vec4 m_max_change;       // largest parameter change per step
  double m_band = 0.0;     // |d| below which the normal form is used
  Formulation m_normal_form = Formulation::Projection;  // the normal form this pair can use
  bool m_in_band = false;  // hysteresis state of the hand-over
  // The normal form's reference surface has its witness at a pole: the other one is the
  // reference (choose_form).
  bool m_reference_at_pole = false;
  // Bit k: parameter k's lower (upper) bound is a pole, not an edge.
  unsigned m_pole_lower = 0, m_pole_upper = 0;
  Pair_system m_system;
  Track_result m_result;
  // Of the last control(): the edge mask of its parameters and the signed distance there.
  unsigned m_last_on_edge = 0;
  double m_last_signed = 0.0;
};

}  // namespace extremal
