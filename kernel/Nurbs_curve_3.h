// A NURBS curve in 3D: control points (CGAL Point_3) with weights, a knot vector and a degree.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/StdVector>

#include "kernel/Types.h"

namespace extremal {

// Point and derivatives of a curve at one parameter.
struct Curve_point {
  Vec3 p = Vec3::Zero();
  Vec3 d1 = Vec3::Zero();  // dC/dt
  Vec3 d2 = Vec3::Zero();  // d2C/dt2
};

class Nurbs_curve_3 {
 public:
  // `weights` empty means polynomial (all weights 1). Throws Invalid_input naming the problem.
  Nurbs_curve_3(int degree, std::vector<Point_3> poles, std::vector<double> knots,
                std::vector<double> weights = {});

  int degree() const { return m_degree; }
  int number_of_poles() const { return static_cast<int>(m_poles.size()); }
  const std::vector<Point_3>& poles() const { return m_poles; }
  const std::vector<double>& weights() const { return m_weights; }
  const std::vector<double>& knots() const { return m_knots; }
  bool is_rational() const { return m_rational; }

  double domain_min() const { return m_knots[m_degree]; }
  double domain_max() const { return m_knots[m_poles.size()]; }
  // Closed: the curve returns to its start point, so a tracked parameter may wrap.
  bool is_closed() const { return m_closed; }
  void set_closed(bool closed) { m_closed = closed; }

  // Point and derivatives up to `order` (0, 1 or 2) at t in the domain. No heap allocation.
  void evaluate(double t, Curve_point& out, int order = 2) const;
  Point_3 point(double t) const;

  // Axis-aligned box of the control points; contains the curve since weights are positive.
  Bbox_3 hull_bbox() const;

  // Homogeneous control points (w x, w y, w z, w), the form every algorithm works on.
  using Homogeneous = std::vector<Eigen::Vector4d, Eigen::aligned_allocator<Eigen::Vector4d>>;
  const Homogeneous& homogeneous_poles() const { return m_hom; }
  static Nurbs_curve_3 from_homogeneous(int degree, const Homogeneous& poles,
                                        std::vector<double> knots);

 private:
  int m_degree;
  std::vector<Point_3> m_poles;
  std::vector<double> m_weights;
  std::vector<double> m_knots;
  Homogeneous m_hom;
  bool m_rational = false;
  bool m_closed = false;
};

}  // namespace extremal
