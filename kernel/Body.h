// A rigid body: the patches (faces) and curves that bound it, in its own frame.
//
// An imported CAD body also carries its B-rep: each face's trim loops (parameter-space curves
// that reference the body's edges), the edges (3D curves with the faces that share them) and
// where it was placed in the file. A mesh body carries triangles instead of faces.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "kernel/Nurbs_curve_3.h"
#include "kernel/Nurbs_surface_3.h"
#include "kernel/Rigid_pose_3.h"
#include "kernel/Trim_region.h"
#include "kernel/Types.h"

namespace extremal {

// One face of a body: its surface and the kind of surface it came from ("sphere", "plane",
// "bspline", ...), which `extremal info` reports.
struct Face {
  Face(Nurbs_surface_3 s, std::string k) : surface(std::move(s)), kind(std::move(k)) {}

  Nurbs_surface_3 surface;
  std::string kind;

  // Trim loops in the surface's parameter space (empty: the whole patch domain is the face) and
  // the point-in-face test built from them. Call update_trim_region() after changing `trims`.
  std::vector<Trim_loop> trims;
  Trim_region trim_region;
  void update_trim_region(double tolerance = 0.0) { trim_region = Trim_region(trims, tolerance); }
  // (u, v) in the patch domain and inside the trim (the On_boundary band included).
  bool contains(double u, double v) const {
    return u >= surface.u_min() && u <= surface.u_max() && v >= surface.v_min() &&
           v <= surface.v_max() && trim_region.contains(u, v);
  }

  // Largest distance between `surface` and the geometry it was read from, in body units: 0 when
  // the conversion is exact (B-splines, planes, quadrics, tori, revolved and extruded conics and
  // B-splines), the measured deviation when the NURBS is an approximation (offsets, ...).
  double approximation_error = 0.0;
  // Where it came from in the file (e.g. "STEP #1234 ADVANCED_FACE", "surf 1"), for messages.
  std::string source;
};

// Where an edge appears: face index, loop index in that face's trims, curve index in the loop.
struct Edge_use {
  int face = -1;
  int loop = -1;
  int curve = -1;
};

// An edge of the B-rep: its 3D curve and the faces it bounds. Two uses make a manifold edge
// (the patch transition runs across it), one a free edge of an open shell; a seam edge of a
// closed patch lists the same face twice. Every use's Trim_curve::uv runs over the same
// parameter range [t_min, t_max] as `curve`; with `same_parameter`, uv(t) on the face is the
// point curve(t) (to `tolerance`), so t maps a point across the edge.
struct Edge {
  // Body frame; empty for a degenerate edge, or when the file gives no usable 3D curve.
  std::optional<Nurbs_curve_3> curve;
  // A degenerate edge (a pole or an apex: its trim curves map to one point). An edge without a
  // curve that is not degenerate is a trim boundary that no curve element carries.
  bool degenerate = false;
  double t_min = 0.0, t_max = 0.0;
  bool same_parameter = true;
  // The file's edge tolerance in body units, raised to the measured gap between uv(t) mapped on
  // each face and curve(t) when the file is looser than it declares.
  double tolerance = 0.0;
  std::vector<Edge_use> uses;
};

// Triangles in the body frame (a mesh body); vertex indices into `vertices`.
struct Triangle_mesh {
  std::vector<Point_3> vertices;
  std::vector<std::array<int, 3>> triangles;
  bool empty() const { return triangles.empty(); }
};

struct Body {
  std::string name;
  // A point body is just its origin (a probe, a tool tip): no faces, no curves.
  bool is_point = false;
  std::vector<Face> faces;
  std::vector<Nurbs_curve_3> curves;

  // B-rep adjacency (imported bodies; empty for shape specs).
  std::vector<Edge> edges;
  // Mesh bodies: triangles instead of faces.
  Triangle_mesh mesh;
  // Placement of the body frame in the file (or scene) frame: p_file = placement(p_body). An
  // assembly instance keeps its part's geometry in the body frame and its location here.
  Rigid_pose_3 placement;
  // Name as the file gives it (product or instance name, file name for single-body files);
  // `name` is made unique among the bodies of one file.
  std::string source_name;

  // Box of every face's and curve's control points, in the body frame.
  Bbox_3 hull_bbox() const;
  // Tight box of the trimmed faces, curves and mesh, in the body frame: edge curves and
  // surfaces sampled inside the trims, extremes polished by Newton steps.
  Bbox_3 trimmed_bbox() const;
  // The same box of the body placed by X (computed on the placed geometry, so it stays tight
  // under rotation), e.g. trimmed_bbox(placement) in the file frame.
  Bbox_3 trimmed_bbox(const Rigid_pose_3& X) const;
  bool is_empty() const { return !is_point && faces.empty() && curves.empty() && mesh.empty(); }
};

}  // namespace extremal
