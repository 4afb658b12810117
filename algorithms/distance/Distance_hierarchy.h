// The prepared form of a body for the certified global distance (Global_distance.h): its
// faces' and curves' Bezier pieces, their control nets and boxes in the body frame, and a
// bounding-volume tree over them.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "algorithms/pair/Feature.h"
#include "algorithms/distance/Symmetry.h"
#include "kernel/Body.h"
#include "kernel/Trim_region.h"
#include "kernel/Types.h"

namespace extremal {

// What part of a body a witness point lies on.
enum class Element_kind { Face, Curve, Point };
const char* to_string(Element_kind k);

// The prepared form of a body for global distance queries: its faces' and curves' Bezier pieces
// with their control nets and boxes in the body frame, and a bounding-volume tree over them.
// Built once per body, reused for every pose and query; it owns copies of the geometry, so the
// Body need not outlive it. Move-only (its features point into its own storage).
class Distance_hierarchy {
 public:
  struct Element {
    Element_kind kind = Element_kind::Face;
    // Face: into Body::faces, or faces.size() + t for triangle t of Body::mesh (a mesh body's
    // triangles are flat degree 1 x 1 patches). Curve: into Body::curves, or curves.size() + k
    // for the 3D curve of B-rep edge k (Body::edges, restricted to [t_min, t_max]). Point: 0.
    int index = -1;
    Feature feature = Feature::point(Vec3::Zero());  // refers to the geometry owned here
    // Face with trim loops: only parameters inside the trim (Face::contains) are on the body;
    // the trim's parameter box [trim_lo, trim_hi] (with the On_boundary band) holds them all.
    bool trimmed = false;
    double trim_lo[2] = {0, 0}, trim_hi[2] = {0, 0};
    // Where a minimum of the element may lie on its domain boundary with no other element
    // carrying it: bit 0 the lower and bit 1 the upper end of the first parameter, bits 2 and
    // 3 of the second (clear for a wrapping direction, or a face whose edges are all curve
    // elements here); bit 4: a trim boundary no curve element carries.
    unsigned open_sides = 0;
    // Its Bezier pieces: pieces()[first_piece .. first_piece + piece_count).
    int first_piece = 0, piece_count = 0;
    // Its centre or axis of rotational symmetry: an index into symmetries(), -1 for none
    // (mesh triangles and points have none).
    int symmetry = -1;
  };
  struct Piece {  // one Bezier piece, body frame
    int element = -1;
    int dimension = 2;    // 0 point, 1 curve, 2 surface
    int nu = 1, nv = 1;   // control net size (degree + 1 per direction; 1 if unused)
    double lo[2] = {0, 0}, hi[2] = {0, 0};  // parameter box
    int offset = 0;       // first homogeneous pole in poles()
    Bbox_3 box;           // of the Cartesian control points
  };
  struct Tree_node {
    Bbox_3 box;            // body frame
    Vec3 centre = Vec3::Zero();
    double radius = 0.0;   // ball around centre that holds the box
    int left = -1, right = -1;
    int piece = -1;        // leaf: the piece it holds
  };

  // Throws Invalid_input for an empty body (no point, face or curve).
  explicit Distance_hierarchy(const Body& body);
  Distance_hierarchy(Distance_hierarchy&&) = default;
  Distance_hierarchy& operator=(Distance_hierarchy&&) = default;
  Distance_hierarchy(const Distance_hierarchy&) = delete;
  Distance_hierarchy& operator=(const Distance_hierarchy&) = delete;

  const std::string& name() const { return m_name; }
  const std::vector<Element>& elements() const { return m_elements; }
  const std::vector<Piece>& pieces() const { return m_pieces; }
  const std::vector<Tree_node>& tree() const { return m_tree; }  // root at 0
  const Eigen::Vector4d* poles() const { return m_poles.data(); }
  // The elements' distinct centres and axes of symmetry, body frame (a cylinder's side and
  // caps share their axis).
  const std::vector<Symmetry>& symmetries() const { return m_symmetries; }
  // Box of all control points, body frame.
  const Bbox_3& box() const { return m_tree.front().box; }
  // Whether parameters q of element e lie on the body: inside the patch domain and the trim for
  // a face, inside the domain for a curve; always for the point.
  bool on_body(int e, const double* q) const;
  // False only when the parameter box [lo, hi] of a piece of element e holds no point of the
  // trimmed face (Trim_region::box_outside): such nodes can be dropped.
  bool may_hold_trimmed(int e, const double* lo, const double* hi) const;
  // Whether the parameter box [lo, hi] of element e reaches one of its face's interior C0 knot
  // lines (a knot of multiplicity at least the degree, where the surface may fold: a faceted
  // degree-1 direction, a crease inside one patch). An extremum on such a line leaves the
  // gradient non-zero on both sides of it.
  bool reaches_kink(int e, const double* lo, const double* hi) const;
  // Whether the parameter box [lo, hi] of element e reaches a place where an extremum needs no
  // vanishing gradient and no curve element carries it: a trim boundary without curve
  // elements (bit 4 of `open`), a side of the domain in `open` (Element::open_sides, which a
  // caller may narrow), or a fold inside the face. The gradient arguments that drop sub-patches
  // (holds_no_minimum, holds_no_maximum) may drop only those that reach none.
  bool reaches_uncarried(int e, const double* lo, const double* hi, unsigned open) const;
  // The element of a body's face, curve (B-rep edges after Body::curves) or point, or -1 when
  // it has none (a degenerate edge).
  int element_of(Element_kind kind, int index) const;
  // The tree leaf holding piece p.
  int leaf_of_piece(int p) const { return m_leaf_of_piece[p]; }

 private:
  int build_tree(std::vector<int>& piece_ids, int begin, int end);
  // The index of s in m_symmetries, added unless one within `tol` is there.
  int symmetry_index(const Symmetry& s, double tol);

  std::string m_name;
  // Owned geometry (Elements' features point here; unique_ptr keeps addresses stable).
  std::vector<std::unique_ptr<Nurbs_surface_3>> m_surfaces;
  std::vector<std::unique_ptr<Nurbs_curve_3>> m_curves;
  std::vector<Trim_region> m_trims;  // per element; untrimmed for curves, points, bare faces
  // Per element and parameter direction: the interior C0 knot values, sorted (faces only).
  std::vector<std::array<std::vector<double>, 2>> m_kinks;
  std::vector<Element> m_elements;
  std::vector<Symmetry> m_symmetries;
  std::vector<Piece> m_pieces;
  std::vector<Eigen::Vector4d, Eigen::aligned_allocator<Eigen::Vector4d>> m_poles;
  std::vector<Tree_node> m_tree;
  std::vector<int> m_leaf_of_piece;
  std::vector<int> m_face_element, m_curve_element;  // by Body face / curve index, -1 if none
};

}  // namespace extremal
