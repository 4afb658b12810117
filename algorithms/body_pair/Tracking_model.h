// A body prepared for tracking against other bodies (docs/design.md): its
// primitives (faces, curves, B-rep edges, a point; a mesh's triangles and their edges), their
// body-frame boxes in a bounding-volume tree for the broad phase, and the adjacency a tracked
// point follows when it leaves a primitive:
//   - across a B-rep edge: face -> edge (the trim boundary in 3D) -> the face on the other side,
//     parameters mapped through each face's trim curve uv(t) (the edge parameter t is shared);
//   - across a patch side of an untrimmed multi-patch body without B-rep (generated bodies):
//     sides matched geometrically (their boundary curves coincide), parameters mapped by
//     projecting the point on the neighbour's side;
//   - a mesh: each triangle is a flat patch (the parallelogram spanned by its corners, limited
//     to u + v <= 1) with its three edges as segments, shared by the adjacent triangles.
// Built once per body; a query or a step transforms boxes, it never rebuilds them.
#pragma once

#include <array>
#include <cmath>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "algorithms/pair/Feature.h"
#include "algorithms/distance/Global_distance.h"
#include "algorithms/mesh/Mesh_bvh.h"
#include "kernel/Body.h"

namespace extremal {

enum class Primitive_kind {
  Face,       // Body::faces[index]
  Curve,      // Body::curves[index]
  Edge,       // Body::edges[index]'s 3D curve over [t_min, t_max]
  Point,      // a point body's origin
  Triangle,   // Body::mesh.triangles[index]: p0 + u (p1 - p0) + v (p2 - p0), u, v >= 0, u + v <= 1
  Mesh_edge,  // a segment between two mesh vertices, t in [0, 1]
};

struct Primitive {
  Primitive_kind kind = Primitive_kind::Face;
  int index = -1;
  Feature feature = Feature::point(Vec3::Zero());
  Bbox_3 box;  // body frame, of the control points (encloses the primitive)
  const Trim_region* trim = nullptr;  // a trimmed face's region (null: the whole domain)
  // The global solver's element (Distance_hierarchy ids) for seeding and audits.
  int global_element = -1;
  // Surfaces: the primitive across each side (u_min, u_max, v_min, v_max), or -1.
  std::array<int, 4> side_neighbour{{-1, -1, -1, -1}};
  std::array<int, 4> side_neighbour_side{{-1, -1, -1, -1}};  // which side of the neighbour
  // Certified bound on how far a point of each matched side lies from the neighbour's side
  // (the same curve up to the pole differences; infinity when not proven): a minimum there is
  // the neighbour's too, within this gap.
  std::array<double, 4> side_gap{{HUGE_VAL, HUGE_VAL, HUGE_VAL, HUGE_VAL}};
  // Surfaces: their bounding edges; edges: the faces that use them (ranges into the model's
  // link lists).
  int first_link = 0, link_count = 0;
  // How far the primitive lies from a plane (faces, triangles), a line (curves, edges) or a
  // point (the point body: 0), from its control points; infinity when it is not that flat
  // (Tuning's k_flat_fraction of its size). A flat primitive against a flat one, or against a
  // convex body, has one basin of distance (flat_single_basin).
  double flatness = HUGE_VAL;

  bool is_surface() const { return feature.dimension() == 2; }
  bool is_mesh() const { return kind == Primitive_kind::Triangle || kind == Primitive_kind::Mesh_edge; }
};

// How an edge lies on one face that uses it: uv(t) on the face, from the face's trim curve or,
// for a mesh edge, the affine map origin + t * direction in the triangle's (u, v).
struct Edge_on_face {
  int face = -1;  // primitive index of the face (or triangle)
  const Nurbs_curve_3* uv = nullptr;
  double origin[2] = {0, 0}, direction[2] = {0, 0};
  void map(double t, double out[2]) const;
};

class Tracking_model {
 public:
  // Throws Invalid_input for an empty body. The body must outlive the model.
  explicit Tracking_model(const Body& body);
  Tracking_model(const Tracking_model&) = delete;
  Tracking_model& operator=(const Tracking_model&) = delete;

  const Body& body() const { return m_body; }
  // A mesh body's hierarchy of triangles (null for other bodies).
  const Mesh_bvh* mesh() const { return m_mesh.get(); }
  // The primitives, their tree and adjacency, and the certified solver's hierarchy: built with
  // the model for NURBS and point bodies, on first use for a mesh (thread-safe).
  void prepare() const;
  const std::vector<Primitive>& primitives() const {
    prepare();
    return m_primitives;
  }
  const Distance_hierarchy& hierarchy() const {
    prepare();
    return *m_hierarchy;
  }
  // The primitive of a global result's element (kind and Body index as in Distance_result).
  int primitive_of(Element_kind kind, int index) const;
  // Box of the whole body, body frame.
  const Bbox_3& box() const { return m_box; }
  bool has_mesh() const { return m_mesh != nullptr; }
  // Whether the body encloses a volume (body_closedness: a closed shell or mesh), decided once.
  bool closed() const { return m_closed; }
  // Number of patch sides matched geometrically (multi-patch bodies without B-rep).
  int matched_sides() const {
    prepare();
    return m_matched_sides;
  }

  // Appends to `out` the primitives whose body-frame box overlaps `query` (body frame),
  // skipping mesh edges when `with_mesh_edges` is false. No allocation beyond `out`'s growth.
  void collect(const Bbox_3& query, bool with_mesh_edges, std::vector<int>& out) const;

  // Edges of face primitive f (each a primitive index).
  const int* edges_of(int f, int& count) const;
  // Faces along edge primitive e.
  const Edge_on_face* faces_of(int e, int& count) const;

  // Whether parameters of a primitive lie on the body (inside the trim or triangle).
  bool contains(int primitive, const double* params) const;

  // Across a patch side: the point at `params` of surface primitive f on side `side` maps to
  // `out` on the neighbour (side_neighbour[side]). Returns false when the projection fails.
  bool map_across_side(int f, int side, const double* params, double out[2]) const;
  // The edge of face f nearest to the body-frame point p, with the edge parameter; -1 if f has
  // no edges. With `toward` (body frame: the other body's witness), edges that tie at p (a
  // corner of the face) are told apart by which one the distance to `toward` descends along
  // from p: the one a point leaving the face at that corner slides on.
  int nearest_edge(int f, const Vec3& p, double& t, const Vec3* toward = nullptr) const;

 private:
  void build_primitives();
  void add_brep_edges();
  void add_mesh();
  void match_patch_sides();
  void build_tree();
  // Primitive::flatness of every primitive.
  void measure_flatness();
  // Sorts (face primitive, edge primitive) links and stores them per face (CSR).
  void link_faces_to_edges(std::vector<std::pair<int, int>>& face_edge);

  const Body& m_body;
  std::unique_ptr<Distance_hierarchy> m_hierarchy;
  std::unique_ptr<Mesh_bvh> m_mesh;
  mutable std::once_flag m_prepared;
  std::vector<Primitive> m_primitives;
  // Geometry the model made itself, owned here: edges cut to their trim range, and a mesh's
  // triangles and edges as bilinear patches and segments (primitives point into these).
  struct Owned {
    std::vector<std::unique_ptr<Nurbs_surface_3>> surfaces;
    std::vector<std::unique_ptr<Nurbs_curve_3>> curves;
  } m_own;
  // Which primitive each of the body's entities became, and the face-edge adjacency (CSR).
  struct Links {
    std::vector<int> face_edges;             // links of faces: edge primitives
    std::vector<Edge_on_face> edge_faces;    // links of edges: faces
    std::vector<int> face_primitive, curve_primitive, edge_primitive, triangle_primitive;
    int point_primitive = -1;
  } m_links;
  struct Node {
    Bbox_3 box;
    int left = -1, right = -1, primitive = -1;
  };
  std::vector<Node> m_tree;
  Bbox_3 m_box;
  bool m_closed = false;
  int m_matched_sides = 0;
};

}  // namespace extremal
