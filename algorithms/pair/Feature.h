// A feature is the part of a body a tracker works on: a point (0 parameters), a curve (1) or a
// surface patch (2), given in the body frame. It refers to geometry owned by a Body; the body
// must outlive it.
#pragma once

#include "kernel/Nurbs_curve_3.h"
#include "kernel/Nurbs_surface_3.h"
#include "kernel/Rigid_pose_3.h"
#include "kernel/Types.h"

namespace extremal {

class Feature {
 public:
  enum class Kind { Point, Curve, Surface };

  static Feature point(const Vec3& p_A) { return Feature(Kind::Point, nullptr, nullptr, p_A); }
  static Feature curve(const Nurbs_curve_3& c) { return Feature(Kind::Curve, &c, nullptr, Vec3::Zero()); }
  static Feature surface(const Nurbs_surface_3& s) {
    return Feature(Kind::Surface, nullptr, &s, Vec3::Zero());
  }

  Kind kind() const { return m_kind; }
  int dimension() const { return m_kind == Kind::Point ? 0 : m_kind == Kind::Curve ? 1 : 2; }
  const Nurbs_curve_3* curve() const { return m_curve; }
  const Nurbs_surface_3* surface() const { return m_surface; }
  const Vec3& point_in_body() const { return m_point; }

  double lower(int i) const;
  double upper(int i) const;
  bool is_closed(int i) const;
  // +1 or -1: see Nurbs_surface_3::outward_sign (curves and points: +1).
  int outward_sign() const { return m_surface ? m_surface->outward_sign() : 1; }

  // Edges of a surface that collapse to a point (poles of spheres, apexes): bit 0 the u_min
  // edge, 1 u_max, 2 v_min, 3 v_max.
  unsigned collapsed_edges() const { return m_collapsed; }
  // Diagonal of the control-point box in the body frame (0 for a point).
  double size() const { return m_size; }

 private:
  Feature(Kind k, const Nurbs_curve_3* c, const Nurbs_surface_3* s, const Vec3& p);
  Kind m_kind;
  const Nurbs_curve_3* m_curve;
  const Nurbs_surface_3* m_surface;
  Vec3 m_point;
  unsigned m_collapsed = 0;
  double m_size = 0.0;
};

// A feature evaluated at parameters and placed in the world: point, first derivatives d[i]
// and second derivatives dd[i][j] along its parameters (world vectors).
struct Feature_point {
  Vec3 p = Vec3::Zero();
  Vec3 d[2] = {Vec3::Zero(), Vec3::Zero()};
  Vec3 dd[2][2] = {{Vec3::Zero(), Vec3::Zero()}, {Vec3::Zero(), Vec3::Zero()}};
};

// Evaluates `f` at `params` (dimension() of them) under pose X_WA. `order` as in
// Nurbs_surface_3::evaluate. No heap allocation.
// `hint` as in Nurbs_surface_3::evaluate_placed_rows (surfaces only; may be null).
void evaluate_feature(const Feature& f, const Rigid_pose_3& X_WA, const double* params,
                      Feature_point& out, int order = 2, Span_hint* hint = nullptr);

// The outward direction (not unit) of surface f at q, fp its point there with second
// derivatives and `cross` its outward cross product of the tangents: `cross`, or on a
// collapsed edge (a pole: Feature::collapsed_edges), where one tangent vanishes, its limit.
Vec3 outward_direction(const Feature& f, const Feature_point& fp, const double* q, const Vec3& cross);

}  // namespace extremal
