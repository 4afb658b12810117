#include "algorithms/body_pair/internal/Pair_context.h"

#include <algorithm>
#include <cmath>

#include "algorithms/body_pair/internal/Body_pair_support.h"
#include "algorithms/body_pair/internal/Tuning.h"
#include "algorithms/distance/Solid_classification.h"

namespace extremal {

namespace internal {

const char* to_string(Body_kind k) {
  switch (k) {
    case Body_kind::Solid: return "solid";
    case Body_kind::Open_sheet: return "open sheet";
    case Body_kind::Curve: return "curve";
    case Body_kind::Point: return "point";
    case Body_kind::Closed_mesh: return "closed mesh";
    case Body_kind::Open_mesh: return "open mesh";
  }
  return "?";
}

namespace {

Body_kind kind_of(const Tracking_model& m) {
  const Body& b = m.body();
  if (b.is_point) return Body_kind::Point;
  if (m.has_mesh()) return m.closed() ? Body_kind::Closed_mesh : Body_kind::Open_mesh;
  if (b.faces.empty()) return Body_kind::Curve;
  return m.closed() ? Body_kind::Solid : Body_kind::Open_sheet;
}

}  // namespace

Pair_kind Pair_kind::of(const Tracking_model& A, const Tracking_model& B) {
  Pair_kind k;
  k.a = kind_of(A);
  k.b = kind_of(B);
  k.sign = !k.closed(0) && k.closed(1) ? Sign_policy::Normal_of_closed_b : Sign_policy::Normal_of_a;
  return k;
}

namespace {

// The options with the trackers' sign policy of the pair's kind.
Body_pair_options signed_options(const Body_pair_options& o, const Pair_kind& kind) {
  Body_pair_options out = o;
  out.tracker.sign_from_b = kind.sign == Sign_policy::Normal_of_closed_b;
  return out;
}

}  // namespace

Pair_context::Pair_context(std::shared_ptr<const Tracking_model> a,
                           std::shared_ptr<const Tracking_model> b, const Body_pair_options& o)
    : model_a(std::move(a)), model_b(std::move(b)),
      options(signed_options(o, Pair_kind::of(*model_a, *model_b))),
      kind(Pair_kind::of(*model_a, *model_b)) {
  now.budget = o.tolerance;
}

double Pair_context::length() const {
  return std::max(box_diagonal(model_a->box()), box_diagonal(model_b->box()));
}

double Pair_context::reach_margin() const {
  if (options.broad_margin > 0.0) return options.broad_margin;
  // (A point's box has no size: the other body's sets the margin.)
  const double a = box_diagonal(model_a->box()), b = box_diagonal(model_b->box());
  return k_default_broad_margin * (a > 0.0 && b > 0.0 ? std::min(a, b) : std::max(a, b));
}

bool Pair_context::convex() {
  if (m_made.convex < 0)
    m_made.convex = is_certified_convex(model_a->body()) && is_certified_convex(model_b->body());
  return m_made.convex == 1;
}

bool Pair_context::convex_body(int side) {
  signed char& c = m_made.convex_body[side];
  if (c < 0) c = is_certified_convex(model(side).body()) ? 1 : 0;
  return c == 1;
}

bool Pair_context::flat_single_basin(int pa, int pb, double d) {
  const double fa = primitive(0, pa).flatness, fb = primitive(1, pb).flatness;
  const double budget = k_flat_budget * now.budget.at(d);
  if (fa < HUGE_VAL && fb < HUGE_VAL) return fa + fb <= budget;
  if (fa < HUGE_VAL) return fa <= budget && convex_body(1);
  if (fb < HUGE_VAL) return fb <= budget && convex_body(0);
  return false;
}

bool Pair_context::single_basin_locatable(int pa, int pb, double d) {
  if (!flat_single_basin(pa, pb, d)) return false;
  const Primitive& A = primitive(0, pa);
  const Primitive& B = primitive(1, pb);
  // (Two flat primitives of dimension 1 or 2 may be parallel: a continuum of minima.)
  const bool a_curved = !(A.flatness < HUGE_VAL), b_curved = !(B.flatness < HUGE_VAL);
  return A.feature.dimension() == 0 || B.feature.dimension() == 0 || a_curved || b_curved;
}

double Pair_context::depth_tolerance(double depth) const {
  return std::max(options.overlap.absolute_tolerance,
                  options.overlap.relative_tolerance * std::abs(depth));
}

double Pair_context::boxes_bound() {
  if (m_made.boxes_bound_at == now.steps) return m_made.boxes_bound;
  // In A's frame: B's box is placed by X_AB. Along n, A reaches box_support(A, n) and B
  // reaches down to -box_support(B, -R^T n) - n.t; the overlap is their difference.
  const Bbox_3& a = model_a->box();
  const Bbox_3& b = model_b->box();
  const Mat3 R = now.relative.rotation();
  const Vec3 t = now.relative.translation();
  double least = HUGE_VAL;
  for (int frame = 0; frame < 2; ++frame)
    for (int axis = 0; axis < 3; ++axis)
      for (const double sign : {1.0, -1.0}) {
        const Vec3 n = sign * (frame == 0 ? Vec3(Vec3::Unit(axis)) : Vec3(R.col(axis)));
        least = std::min(least, box_support(a, n) + box_support(b, -(R.transpose() * n)) - n.dot(t));
      }
  m_made.boxes_bound = least + depth_tolerance(least);
  m_made.boxes_bound_at = now.steps;
  return m_made.boxes_bound;
}

}  // namespace internal
}  // namespace extremal
