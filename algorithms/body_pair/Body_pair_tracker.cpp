#include "algorithms/body_pair/Body_pair_tracker.h"

#include "algorithms/body_pair/internal/Ball_pair.h"
#include "algorithms/body_pair/internal/Mesh_pair_stage.h"
#include "algorithms/body_pair/internal/Stage_engine.h"
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

// Bit for bit: a pose the answer was made at, not one near it.
bool same_pose(const Rigid_pose_3& x, const Rigid_pose_3& y) {
  return x.rotation() == y.rotation() && x.translation() == y.translation();
}

std::unique_ptr<internal::Pair_engine> engine_for(std::shared_ptr<const Tracking_model> a,
                                                  std::shared_ptr<const Tracking_model> b,
                                                  const Body_pair_options& options) {
  if (internal::Mesh_pair_stage::takes(*a, *b))
    return std::make_unique<internal::Mesh_pair_stage>(std::move(a), std::move(b), options);
  if (internal::Ball_pair::takes(*a, *b))
    return std::make_unique<internal::Ball_pair>(std::move(a), std::move(b), options);
  return std::make_unique<internal::Stage_engine>(std::move(a), std::move(b), options);
}

}  // namespace

// The facade: the pose gate in front of the pair's engine, and the one mapping from its answer
// to the report.
struct Body_pair_tracker::Impl {
  Impl(std::shared_ptr<const Tracking_model> a, std::shared_ptr<const Tracking_model> b,
       const Body_pair_options& o)
      : options(o), models{a, b}, features{features_of(a->body()), features_of(b->body())},
        engine(engine_for(std::move(a), std::move(b), o)) {}

  const Body_pair_options options;
  const std::shared_ptr<const Tracking_model> models[2];
  const std::vector<Feature> features[2];
  const std::unique_ptr<internal::Pair_engine> engine;
  // The last report made (made_any) at A's pose and the relative pose it was made at, and the
  // one carried from it while the relative pose stays the same.
  Pair_report made, carried;
  bool made_any = false;
  Rigid_pose_3 made_pose_a, made_relative;
  long computed_steps = 0;  // steps the engine answered
  mutable Pair_statistics statistics;  // (assembled when asked)
};

Body_pair_tracker::Body_pair_tracker(const Body& a, const Body& b, const Body_pair_options& options)
    : Body_pair_tracker(std::make_shared<const Tracking_model>(a),
                        std::make_shared<const Tracking_model>(b), options) {}

Body_pair_tracker::Body_pair_tracker(std::shared_ptr<const Tracking_model> a,
                                     std::shared_ptr<const Tracking_model> b,
                                     const Body_pair_options& options) {
  EXTREMAL_PRECONDITION_MSG(options.own_basin_gap >= 0.0 && options.own_basin_gap < 1.0,
                            "Body_pair_options::own_basin_gap must be >= 0 and < 1");
  m = std::make_unique<Impl>(std::move(a), std::move(b), options);
}

Body_pair_tracker::~Body_pair_tracker() = default;
Body_pair_tracker::Body_pair_tracker(Body_pair_tracker&&) noexcept = default;
Body_pair_tracker& Body_pair_tracker::operator=(Body_pair_tracker&&) noexcept = default;

const Pair_statistics& Body_pair_tracker::statistics() const {
  Pair_statistics& s = m->statistics;
  s = Pair_statistics{};
  m->engine->add_statistics(s);
  s.computed_steps = m->computed_steps;
  return s;
}
double Body_pair_tracker::audit_time_us() const { return m->engine->audit_time_us(); }
const std::vector<Feature>& Body_pair_tracker::features_a() const { return m->features[0]; }
const std::vector<Feature>& Body_pair_tracker::features_b() const { return m->features[1]; }
const Tracking_model& Body_pair_tracker::model_a() const { return *m->models[0]; }
const Tracking_model& Body_pair_tracker::model_b() const { return *m->models[1]; }

void Body_pair_tracker::start(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) {
  m->engine->start(X_WA, X_WB);
}

const Pair_report& Body_pair_tracker::step(double t, const Rigid_pose_3& X_WA, const Twist_3& V_A,
                                           const Rigid_pose_3& X_WB, const Twist_3& V_B,
                                           double dt) {
  Impl& s = *m;
  // The pose gate, for every engine. A relative pose bit for bit the one the last answer was
  // made at keeps that answer, carried along in the world by the bodies' common motion (any
  // other change is a new step: a tolerance here would be a hole in the certificate). Tests
  // BodyScenes.BodiesAtTheSameRelativePoseKeepTheirAnswer, BodyScenes.AnUlpOfMotionIsAStep.
  const Rigid_pose_3 relative = X_WA.inverse() * X_WB;
  if (s.made_any && s.made.status != Pair_status::Farther && same_pose(relative, s.made_relative)) {
    Pair_report& r = s.carried;
    r = s.made;
    r.time = t;
    if (!same_pose(X_WA, s.made_pose_a)) {
      const Rigid_pose_3 M = X_WA * s.made_pose_a.inverse();
      r.point_a = M.apply_point(s.made.point_a);
      r.point_b = M.apply_point(s.made.point_b);
      r.normal = M.rotation() * s.made.normal;
    }
    return r;
  }
  s.made_any = true;
  s.made_pose_a = X_WA;
  s.made_relative = relative;
  // A pair whose boxes lie beyond the threshold: `farther`, not tracked (the engine starts
  // again when it comes back).
  if (s.options.threshold > 0.0) {
    const double bound = s.engine->box_bound(X_WA, X_WB);
    if (bound > s.options.threshold) {
      s.engine->farther(bound, relative);
      s.made = internal::farther_report(t, bound);
      return s.made;
    }
  }
  ++s.computed_steps;
  const internal::Pair_answer& a = s.engine->step({t, dt, X_WA, V_A, X_WB, V_B, s.options.tolerance});
  s.made = internal::report_of(a, t, s.options.contact_tolerance, s.options.tolerance);
  return s.made;
}

}  // namespace extremal
