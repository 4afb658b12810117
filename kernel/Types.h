// Basic geometric types shared by every layer. Public API speaks CGAL (Point_3, Bbox_3);
// hot loops use fixed-size Eigen vectors, which is what Vec3 is for.
#pragma once

#include <algorithm>
#include <cmath>

#include <CGAL/Bbox_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace extremal {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point_3 = Kernel::Point_3;
using Vector_3 = Kernel::Vector_3;
using Bbox_3 = CGAL::Bbox_3;

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

inline Vec3 to_vec3(const Point_3& p) { return Vec3(p.x(), p.y(), p.z()); }
inline Vec3 to_vec3(const Vector_3& v) { return Vec3(v.x(), v.y(), v.z()); }
inline Point_3 to_point(const Vec3& v) { return Point_3(v.x(), v.y(), v.z()); }
inline Vector_3 to_vector(const Vec3& v) { return Vector_3(v.x(), v.y(), v.z()); }

// Euclidean distance between two boxes (0 if they overlap): a lower bound on the distance
// between anything they hold.
inline double box_distance(const Bbox_3& a, const Bbox_3& b) {
  double s = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double gap = std::max(a.min(i) - b.max(i), b.min(i) - a.max(i));
    if (gap > 0.0) s += gap * gap;
  }
  return std::sqrt(s);
}

inline Vec3 box_centre(const Bbox_3& b) {
  return Vec3(0.5 * (b.xmin() + b.xmax()), 0.5 * (b.ymin() + b.ymax()), 0.5 * (b.zmin() + b.zmax()));
}

// Length of a box's diagonal.
inline double box_diagonal(const Bbox_3& b) {
  return std::sqrt((b.xmax() - b.xmin()) * (b.xmax() - b.xmin()) +
                   (b.ymax() - b.ymin()) * (b.ymax() - b.ymin()) +
                   (b.zmax() - b.zmin()) * (b.zmax() - b.zmin()));
}

// Largest n.x over a box: its support function (n in the box's frame).
inline double box_support(const Bbox_3& b, const Vec3& n) {
  const Vec3 c = box_centre(b);
  const Vec3 h(0.5 * (b.xmax() - b.xmin()), 0.5 * (b.ymax() - b.ymin()), 0.5 * (b.zmax() - b.zmin()));
  return n.dot(c) + n.cwiseAbs().dot(h);
}

// Whether the point p (in the box's frame) lies in the closed box.
inline bool box_contains(const Bbox_3& b, const Vec3& p) {
  return p.x() >= b.xmin() && p.x() <= b.xmax() && p.y() >= b.ymin() && p.y() <= b.ymax() &&
         p.z() >= b.zmin() && p.z() <= b.zmax();
}

}  // namespace extremal
