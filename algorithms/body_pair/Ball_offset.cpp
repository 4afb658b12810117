#include "algorithms/body_pair/internal/Ball_offset.h"

#include <algorithm>
#include <cmath>

#include "algorithms/body_pair/Body_pair_tracker.h"
#include "algorithms/body_pair/internal/Body_pair_support.h"
#include "algorithms/body_pair/internal/Tuning.h"
#include "algorithms/distance/Solid_classification.h"
#include "kernel/Shapes.h"

namespace extremal::internal {

namespace {

// The number of parameters a report gives for its feature `f` of `model`'s body (faces and
// triangles 2, curves 1, a point 0).
int reported_dimension(const Tracking_model& model, int f) {
  const Body& body = model.body();
  if (body.is_point || f < 0) return 0;
  if (f < static_cast<int>(body.faces.size())) return 2;
  return f < static_cast<int>(body.faces.size() + body.curves.size()) ? 1 : 2;
}

// The parameters, among a grid over the face's domain, of the sample nearest to the world point
// p (the witness's first start).
Vec4 nearest_sample(const Feature& face, const Rigid_pose_3& X, const Vec3& p) {
  Vec4 best = Vec4::Zero();
  double least = HUGE_VAL;
  for (int i = 0; i <= k_witness_start_grid; ++i)
    for (int j = 0; j <= k_witness_start_grid; ++j) {
      const double q[2] = {face.lower(0) + (face.upper(0) - face.lower(0)) * i / k_witness_start_grid,
                           face.lower(1) + (face.upper(1) - face.lower(1)) * j / k_witness_start_grid};
      Feature_point f;
      evaluate_feature(face, X, q, f, 0);
      const double d = (f.p - p).squaredNorm();
      if (d < least) least = d, best = Vec4(q[0], q[1], 0.0, 0.0);
    }
  return best;
}

}  // namespace

Ball_offset::Ball_offset(std::shared_ptr<const Tracking_model> a,
                         std::shared_ptr<const Tracking_model> b, bool centres)
    : m_given{std::move(a), std::move(b)} {
  std::optional<Ball> ball[2];
  for (int side = 0; side < 2; ++side) {
    m_features[side] = features_of(m_given[side]->body());
    ball[side] = certified_ball(m_given[side]->body());
  }
  for (int side = 0; side < 2; ++side) {
    const Tracking_model& other = *m_given[1 - side];
    const bool signed_other = ball[1 - side] || other.body().is_point || other.closed();
    if (!centres || !ball[side] || !signed_other) continue;
    Side& s = m_side[side];
    s.radius = ball[side]->radius;
    s.centre = ball[side]->centre;
    s.point = std::make_unique<Body>(make_point_body(m_given[side]->body().name));
    s.model = std::make_shared<const Tracking_model>(*s.point);
    Tracker_options o;
    o.corrections = k_witness_corrections;
    o.correction_tolerance = k_witness_tolerance;
    s.witness = std::make_unique<Extremal_tracker>(
        s.at_witness, m_given[side]->primitives().front().feature, Vec4::Zero(), o);
  }
}

std::shared_ptr<const Tracking_model> Ball_offset::inner(int side) const {
  return m_side[side].radius > 0.0 ? m_side[side].model : m_given[side];
}

void Ball_offset::place(int side, const Rigid_pose_3& X_W, const Twist_3& V,
                        Rigid_pose_3& inner_X, Twist_3& inner_V) const {
  const Side& s = m_side[side];
  if (!(s.radius > 0.0)) {
    inner_X = X_W;
    inner_V = V;
    return;
  }
  inner_X = Rigid_pose_3(X_W.rotation(), X_W.apply_point(s.centre));
  inner_V.linear = V.velocity_at(inner_X.translation(), X_W);
  inner_V.angular = V.angular;
}

Error_budget Ball_offset::inner_budget(const Error_budget& given, const Rigid_pose_3& X_WA,
                                       const Rigid_pose_3& X_WB) {
  const Rigid_pose_3 relative = X_WA.inverse() * X_WB;
  double lower = 0.0;
  if (m_last_lower > -HUGE_VAL)
    lower = m_last_lower - approach_bound(m_given[0]->box(), m_given[1]->box(), m_last_relative,
                                          relative).closer;
  // (Relative 0: the inner distances are larger by the radii, their budget no larger.)
  return Error_budget{given.at(std::max(lower, 0.0)), 0.0};
}

void Ball_offset::report(const Pair_report& inner, const Body_pair_options& given,
                         const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB, Pair_report& out) {
  out = inner;
  const double radii = this->radii();
  // (Centres that coincide have no direction between them: any unit normal does.)
  if (inner.status != Pair_status::Farther && out.normal.squaredNorm() == 0.0) out.normal = Vec3::UnitZ();
  const Vec3 normal = out.normal;
  out.distance = inner.distance - radii;
  const double tol = given.contact_tolerance;
  if (inner.status == Pair_status::Farther) {
    // (The boxes of the centres less the radii bound the balls.)
    out.lower_bound = out.distance;
  } else {
    const Rigid_pose_3* X[2] = {&X_WA, &X_WB};
    Vec3* point[2] = {&out.point_a, &out.point_b};
    int* feature[2] = {&out.feature_a, &out.feature_b};
    int* edge[2] = {&out.edge_a, &out.edge_b};
    // A's parameters, then B's: the ball's on its face, the other's as the inner report gave.
    const int dims[2] = {m_side[0].radius > 0.0 ? 2 : reported_dimension(*m_given[0], inner.feature_a),
                         m_side[1].radius > 0.0 ? 2 : reported_dimension(*m_given[1], inner.feature_b)};
    Vec4 params = Vec4::Zero();
    const int inner_dim_a = m_side[0].radius > 0.0 ? 0 : dims[0];
    for (int c = 0; c < dims[0] && m_side[0].radius == 0.0; ++c) params[c] = inner.params[c];
    for (int c = 0; c < dims[1] && m_side[1].radius == 0.0; ++c)
      params[dims[0] + c] = inner.params[inner_dim_a + c];
    for (int side = 0; side < 2; ++side) {
      Side& s = m_side[side];
      if (!(s.radius > 0.0)) continue;
      // The ball's point facing the other body: from its centre against the normal (A to B)
      // for B, along it for A.
      const Vec3 outward = side == 0 ? normal : Vec3(-normal);
      *point[side] += s.radius * outward;
      *feature[side] = 0;
      *edge[side] = -1;
      // (From a point a radius out along the normal, whose foot on the ball is the witness: on
      // the surface itself the pair would be at contact, where its conditions degenerate.)
      const Rigid_pose_3 at(Mat3::Identity(), *point[side] + s.radius * outward);
      if (!s.witness_started) {
        s.witness->reset(nearest_sample(m_given[side]->primitives().front().feature, *X[side],
                                        at.translation()));
        s.witness_started = true;
      }
      const Track_result& w = s.witness->step(inner.time, at, Twist_3{}, *X[side], Twist_3{}, 1.0);
      params[side == 0 ? 0 : dims[0]] = w.params[0];
      params[(side == 0 ? 0 : dims[0]) + 1] = w.params[1];
    }
    out.params = params;
    const bool was_apart = inner.status != Pair_status::Contact && inner.status != Pair_status::Penetrating;
    out.status = out.distance < -tol   ? Pair_status::Penetrating
                 : out.distance <= tol ? Pair_status::Contact
                 : was_apart           ? inner.status
                                       : Pair_status::Tracking;
    out.lower_bound.reset();
    if (out.distance > tol) {
      if (inner.lower_bound) out.lower_bound = std::min(*inner.lower_bound - radii, out.distance);
      const bool certified =
          out.lower_bound && *out.lower_bound >= certified_floor(out.distance, given.tolerance);
      if (!certified) out.status = Pair_status::Uncertified;
      else if (out.status == Pair_status::Uncertified) out.status = Pair_status::Tracking;
    }
  }
  m_last_lower = out.lower_bound ? *out.lower_bound : -HUGE_VAL;
  m_last_relative = X_WA.inverse() * X_WB;
}

}  // namespace extremal::internal
