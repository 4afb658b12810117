// Exact closest points between triangles and points (mesh bodies): closed forms, no iteration.
#pragma once

#include "kernel/Types.h"

namespace extremal {

struct Triangle_closest {
  double distance = 0.0;          // >= 0; 0 when the triangles meet
  Vec3 point_a = Vec3::Zero(), point_b = Vec3::Zero();
  // Witness coordinates in each triangle: p = p0 + u (p1 - p0) + v (p2 - p0).
  double uv_a[2] = {0, 0}, uv_b[2] = {0, 0};
};

// Where on a triangle a closest point lies (its Voronoi feature): the face, an edge (0: p0 p1,
// 1: p1 p2, 2: p2 p0) or a vertex (0, 1, 2).
enum class Triangle_feature : unsigned char { Face, Edge, Vertex };

struct Triangle_point {
  Vec3 point = Vec3::Zero();
  double uv[2] = {0, 0};  // p0 + u (p1 - p0) + v (p2 - p0)
  Triangle_feature feature = Triangle_feature::Face;
  int feature_index = 0;  // the edge or vertex (0..2)
};

// Closest point of triangle (p0, p1, p2) to q, with its feature (Ericson's Voronoi regions).
Triangle_point closest_on_triangle_region(const Vec3& q, const Vec3& p0, const Vec3& p1,
                                          const Vec3& p2);

// Closest point of triangle (p0, p1, p2) to q; writes its (u, v) and returns it.
Vec3 closest_on_triangle(const Vec3& q, const Vec3& p0, const Vec3& p1, const Vec3& p2,
                         double uv[2]);

// Closest points c1 of segment [p1, q1] and c2 of [p2, q2] (Ericson, Real-Time Collision
// Detection 5.1.9); returns their squared distance.
double segment_segment_squared(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2,
                               Vec3& c1, Vec3& c2);

// Closest points of two triangles (exact up to rounding): the minimum over the six
// vertex-triangle and nine edge-edge pairs, or a common point when they meet.
Triangle_closest triangle_distance(const Vec3 a[3], const Vec3 b[3]);

}  // namespace extremal
