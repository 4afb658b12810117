// A tensor-product NURBS surface patch: a grid of control points (CGAL Point_3) with weights,
// two knot vectors and two degrees.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/StdVector>

#include "kernel/Types.h"

namespace extremal {

// Point and partial derivatives of a surface at one parameter pair.
struct Surface_point {
  Surface_point() = default;
  // Leaves every vector unset, for a caller that has evaluate() write them (a hot path):
  // only the orders evaluated are then defined.
  struct Unset {};
  explicit Surface_point(Unset) : p(), du(), dv(), duu(), duv(), dvv() {}

  Vec3 p = Vec3::Zero();
  Vec3 du = Vec3::Zero();
  Vec3 dv = Vec3::Zero();
  Vec3 duu = Vec3::Zero();
  Vec3 duv = Vec3::Zero();
  Vec3 dvv = Vec3::Zero();
};

enum class Parameter_direction { U, V };

// The knot spans (indices of their first knots) an evaluation found, for the next one near it.
struct Span_hint {
  int u = -1, v = -1;
};

class Nurbs_surface_3 {
 public:
  // Control points in row-major order: pole (i, j), i along u (0..n_u-1), j along v, is
  // poles[i * n_v + j]. `weights` empty means polynomial. Throws Invalid_input naming the
  // problem (counts, knots, weights, coordinates).
  Nurbs_surface_3(int degree_u, int degree_v, int n_u, int n_v, std::vector<Point_3> poles,
                  std::vector<double> knots_u, std::vector<double> knots_v,
                  std::vector<double> weights = {});

  int degree_u() const { return m_degree_u; }
  int degree_v() const { return m_degree_v; }
  int number_of_poles_u() const { return m_n_u; }
  int number_of_poles_v() const { return m_n_v; }
  const std::vector<Point_3>& poles() const { return m_poles; }
  const Point_3& pole(int i, int j) const { return m_poles[i * m_n_v + j]; }
  const std::vector<double>& weights() const { return m_weights; }
  double weight(int i, int j) const { return m_weights[i * m_n_v + j]; }
  const std::vector<double>& knots_u() const { return m_knots_u; }
  const std::vector<double>& knots_v() const { return m_knots_v; }
  bool is_rational() const { return m_rational; }

  double u_min() const { return m_knots_u[m_degree_u]; }
  double u_max() const { return m_knots_u[m_n_u]; }
  double v_min() const { return m_knots_v[m_degree_v]; }
  double v_max() const { return m_knots_v[m_n_v]; }

  // Closed in a direction: the opposite domain edges coincide, so a tracked parameter may wrap
  // across the seam. Detected at construction (edges equal to 1e-12 of the patch size).
  bool is_closed_u() const { return m_closed_u; }
  bool is_closed_v() const { return m_closed_v; }
  void set_closed(bool closed_u, bool closed_v) {
    m_closed_u = closed_u;
    m_closed_v = closed_v;
  }

  // +1 when f_u x f_v points out of the solid this patch bounds, -1 when it points in.
  int outward_sign() const { return m_outward_sign; }
  void set_outward_sign(int sign) { m_outward_sign = sign >= 0 ? 1 : -1; }

  // Point and partial derivatives up to `order` (0, 1 or 2) at (u, v) in the domain, knots and
  // ends included. No heap allocation; a polynomial patch skips the quotient rule.
  void evaluate(double u, double v, Surface_point& out, int order = 2) const;
  // The same in the frame where the patch is placed by x -> rotation x + translation (the
  // world, for a body's pose): cheaper than evaluating and then rotating each derivative.
  void evaluate_placed(double u, double v, const Mat3& rotation, const Vec3& translation,
                       Surface_point& out, int order = 2) const;
  // The same values as rows of four doubles: p, du, dv, duu, duv, dvv (lane 3 unspecified, rows
  // above `order` untouched). For a caller with its own layout (the tracker's feature points):
  // the fast kernel writes the rows directly, one copy fewer on the tracker's hot path.
  // `hint`, when given, holds the knot spans the caller's last evaluation found and receives
  // this one's: a tracker moves by small steps and mostly stays in its spans, where the span
  // search and the domain checks are skipped (a stale or foreign hint only costs the search).
  void evaluate_placed_rows(double u, double v, const Mat3& rotation, const Vec3& translation,
                            double (&rows)[6][4], int order = 2,
                            Span_hint* hint = nullptr) const;
  Point_3 point(double u, double v) const;
  // Unit outward normal (f_u x f_v times outward_sign); zero where f_u x f_v vanishes, that is
  // falls below 1e-12 |coordinates| size / (u width * v width), the level rounding leaves at
  // collapsed edges such as sphere poles.
  Vec3 outward_normal(const Surface_point& sp) const;

  // Axis-aligned box of the control points; contains the patch since weights are positive.
  Bbox_3 hull_bbox() const;

  using Homogeneous = std::vector<Eigen::Vector4d, Eigen::aligned_allocator<Eigen::Vector4d>>;
  const Homogeneous& homogeneous_poles() const { return m_hom; }
  static Nurbs_surface_3 from_homogeneous(int degree_u, int degree_v, int n_u, int n_v,
                                          const Homogeneous& poles, std::vector<double> knots_u,
                                          std::vector<double> knots_v);

 private:
  // R (column-major 3 x 3) and t, or both nullptr for the patch's own frame. When `rows` is
  // not null and the placed fast kernel runs, it writes there instead of `out` (returns true).
  // `hint` as in evaluate_placed_rows (may be null).
  bool evaluate_in_frame(double u, double v, const double* R, const double* t, Surface_point& out,
                         int order, double* rows = nullptr, Span_hint* hint = nullptr) const;

  int m_degree_u, m_degree_v;
  int m_n_u, m_n_v;
  std::vector<Point_3> m_poles;
  std::vector<double> m_weights;
  std::vector<double> m_knots_u, m_knots_v;
  Homogeneous m_hom;
  bool m_rational = false;
  bool m_closed_u = false, m_closed_v = false;
  int m_outward_sign = 1;
  double m_normal_floor = 0.0;
};

}  // namespace extremal
