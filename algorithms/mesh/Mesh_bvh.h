// A triangle mesh in a body-frame bounding-volume hierarchy of oriented boxes, built once:
// closest points to a point, the sign of a point against a closed mesh (angle-weighted
// pseudo-normals), and the lower bound between two posed boxes that a traversal of two
// hierarchies prunes with (Mesh_front.h). Each leaf is one triangle; the corners are kept in
// leaf order, so that a subtree's triangles are read from one block.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "algorithms/distance/Triangle_distance.h"
#include "kernel/Body.h"
#include "kernel/Rigid_pose_3.h"
#include "kernel/Types.h"

namespace extremal {

// An oriented box: centre, axes (the columns of `axes`, orthonormal) and half extents along them.
struct Obb {
  Vec3 centre = Vec3::Zero();
  Mat3 axes = Mat3::Identity();
  Vec3 half = Vec3::Zero();
};

// A lower bound on the distance between box a (frame A) and box b (frame B), B placed in A's
// frame by (R, t): the largest gap between the boxes' projections on the 15 axes of the
// separating-axis test, and between their bounding balls (each a valid bound: projecting on a
// unit direction or onto balls cannot increase distances). 0 when they may meet.
// Stops early, with a bound at least `enough`, once one axis gives that much.
double obb_lower_bound(const Obb& a, const Obb& b, const Mat3& R, const Vec3& t,
                       double enough = HUGE_VAL);

// A lower bound on the distance between triangle t and box b, both in one frame: the largest
// gap of their projections on the box's axes, the triangle's normal and the line from the
// triangle's centroid to the box's centre. 0 when they may meet. Stops early, with a bound at
// least `enough`, once one axis gives that much.
double triangle_box_lower_bound(const Vec3 t[3], const Vec3& centre, const Mat3& axes,
                                const Vec3& half, double enough = HUGE_VAL);

struct Mesh_point {
  double distance = HUGE_VAL;  // from the query point, >= 0
  int triangle = -1;           // index into the mesh's triangles
  Vec3 point = Vec3::Zero();   // body frame
  double uv[2] = {0, 0};       // p0 + u (p1 - p0) + v (p2 - p0)
  Triangle_feature feature = Triangle_feature::Face;
  int feature_index = 0;       // the edge or vertex (0..2)
};

// Closest point of triangle (p0, p1, p2) to q, with its feature (Ericson's Voronoi regions).
Mesh_point closest_on_triangle_feature(const Vec3& q, const Vec3& p0, const Vec3& p1,
                                       const Vec3& p2);

class Mesh_bvh {
 public:
  // A node is named by a reference: >= 0 an inner node (its index), < 0 the leaf of slot
  // -ref - 1, one triangle, whose box is made when asked (so a mesh holds n - 1 boxes).
  struct Node {
    Obb box;
    int child[2] = {0, 0};  // references
  };
  static bool is_leaf(int ref) { return ref < 0; }
  static int leaf_slot(int ref) { return -ref - 1; }

  // Throws Invalid_input naming `name` on a triangle that refers to no vertex. The mesh is
  // copied into leaf order (the caller's may go).
  Mesh_bvh(const Triangle_mesh& mesh, const std::string& name);

  // The root's reference (a leaf for a mesh of one triangle).
  int root() const { return m_nodes.empty() ? -1 : 0; }
  const Node& node(int ref) const { return m_nodes[static_cast<std::size_t>(ref)]; }
  int inner_count() const { return static_cast<int>(m_nodes.size()); }
  // A node's box: an inner node's, or its triangle's (along its longest edge and its normal).
  Obb box(int ref) const;
  int triangle_count() const { return static_cast<int>(m_order.size()); }
  // The mesh triangle in leaf slot s, and its corners (body frame).
  int triangle_of_slot(int s) const { return m_order[static_cast<std::size_t>(s)]; }
  const Vec3* corners(int slot) const { return m_corners.data() + 3 * static_cast<std::size_t>(slot); }
  int slot_of_triangle(int t) const { return m_slot[static_cast<std::size_t>(t)]; }
  // The corners of mesh triangle t.
  const Vec3* triangle(int t) const { return corners(m_slot[static_cast<std::size_t>(t)]); }
  const Bbox_3& box() const { return m_box; }

  // Every edge has two triangles that run it in opposite directions: the mesh encloses a
  // volume, its normals (p1 - p0) x (p2 - p0) all outward or all inward (flipped here so that
  // they are outward). Otherwise `reason` names an edge that breaks it.
  bool closed() const { return m_closed; }
  const std::string& closedness_reason() const { return m_reason; }

  // The closest point of the mesh to body-frame point p among those closer than `upper`
  // (distance infinity, triangle -1 when none is).
  Mesh_point closest_point(const Vec3& p, double upper = HUGE_VAL) const;
  // Closed meshes: whether p lies inside, from the closest point's angle-weighted
  // pseudo-normal (its face's, edge's or vertex's): (p - c) . n < 0. Exact for points off the
  // surface (Baerentzen and Aanaes 2005); a point on the surface counts as outside.
  bool inside(const Vec3& p, const Mesh_point& closest) const;
  bool inside(const Vec3& p) const { return inside(p, closest_point(p)); }
  // The outward unit normal of triangle t's plane.
  Vec3 face_normal(int t) const;

  // Bytes held (nodes, corners, orders, adjacency and pseudo-normals).
  std::size_t memory_bytes() const;

 private:
  void build(const Triangle_mesh& mesh);
  void find_adjacency(const Triangle_mesh& mesh, const std::string& name);

  std::vector<Node> m_nodes;
  std::vector<Vec3> m_corners;  // 3 per leaf slot
  std::vector<int> m_order;     // mesh triangle of each leaf slot
  std::vector<int> m_slot;      // leaf slot of each mesh triangle
  // Closed meshes: for each triangle's edge k (from corner k to k + 1), the triangle across
  // it; each vertex's angle-weighted pseudo-normal; each triangle's corners' vertex ids.
  std::vector<std::array<int, 3>> m_across;
  std::vector<std::array<int, 3>> m_vertex_ids;
  std::vector<Vec3> m_vertex_normals;
  Bbox_3 m_box;
  bool m_closed = false;
  bool m_flipped = false;  // the mesh's normals pointed inward: corners reordered
  std::string m_reason;
};

}  // namespace extremal
