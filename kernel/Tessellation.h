// Triangle meshes of bodies at a guaranteed chordal deviation, with the project's own kernel.
//
// Each face's patch is sampled on a tensor grid in its (u, v) parameters and every grid cell is
// cut into two triangles. The grid lines run through every knot, and within each Bezier span
// (split further where that makes the bound tighter) the spacing hu x hv satisfies
//
//     (hu^2 M_uu + 2 hu hv M_uv + hv^2 M_vv) / 8 <= deflection,
//
// with M_uu, M_uv, M_vv upper bounds on |S_uu|, |S_uv|, |S_vv| over the span (from the Bezier
// coefficients of the second derivatives; for a rational span, of the polynomials w^3 S_uu, ...
// over the smallest weight cubed). The left side bounds the distance between a point of a
// triangle and the surface point at the same parameters (the error of linear interpolation over
// any triangle inside an hu x hv cell: by Taylor's theorem it is at most half the barycentric
// mean of the second directional derivative along each corner's offset, and the offsets' u and
// v spreads are at most hu^2 / 4 and hv^2 / 4), so every point of every triangle lies within
// `deflection` of the surface. Vertices are exact surface points.
//
// A trimmed face's grid cells are clipped by its trim, marching-squares style: cells inside are
// kept whole, cells the trim crosses keep the polygon of their inside corners and of the points
// where the trim crosses their edges (found by bisection, on the trim to its tolerance), cut
// into triangles; a triangle whose centroid is outside the trim is dropped. The border is thus
// a polyline through points of the trim: between two of them it cuts off (or, where the face
// is concave, takes in) the trim curve's sagitta over a cell, and a part of the face that
// slips between grid nodes (thinner than a cell) is lost. A trimmed face's cells are kept short
// enough on the surface for that to stay small (see plan_face in Tessellation.cpp). The
// deflection bound above holds for these triangles too: each lies inside one cell.
// Triangles follow the face's outward normal (Nurbs_surface_3::outward_sign: the B-rep face
// orientation for imported solids). Vertices are shared within a face, including along closed
// seams and collapsed sides (poles), so a sphere or a torus face gives a closed mesh; faces do
// not share vertices with each other, so a multi-face body's mesh is not watertight across its
// edges.
#pragma once

#include <array>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include "kernel/Body.h"
#include "kernel/Error.h"
#include "kernel/Rigid_pose_3.h"

namespace extremal {

constexpr std::size_t k_max_triangles_cap = 1'000'000'000;

struct Tessellation_options {
  // Largest distance from a point of the mesh to the surface, in body units; finite and > 0.
  double deflection = 1e-3;
  // Cap on the triangles of the output mesh (all calls that append to it): past it
  // Tessellation_too_large is thrown before memory runs out. At most k_max_triangles_cap (vertex
  // indices are int).
  std::size_t max_triangles = 20'000'000;
};

// The cap was exceeded. `triangles` is, when the plan alone exceeds the cap many times over
// (estimated(): nothing was built), the grid triangles of the faces planned so far (a lower
// bound on the whole grid's); otherwise the triangles kept when the cap was crossed.
class Tessellation_too_large : public Invalid_input {
 public:
  Tessellation_too_large(const std::string& what, double triangles, bool estimated)
      : Invalid_input(what), m_triangles(triangles), m_estimated(estimated) {}
  double triangles() const { return m_triangles; }
  bool estimated() const { return m_estimated; }

 private:
  double m_triangles;
  bool m_estimated;
};

struct Tessellation {
  // In the frame the bodies were placed in; triangles counter-clockwise seen from outside.
  Triangle_mesh mesh;
  // Per vertex: the face it lies on (index into `face_body`/`face_index`) and its (u, v);
  // (0, 0) for vertices copied from a mesh body.
  std::vector<int> vertex_face;
  std::vector<std::array<double, 2>> vertex_uv;
  // Per triangle: the face it came from, as for vertex_face (-1 for a mesh body's triangle).
  std::vector<int> triangle_face;
  // Faces numbered across the bodies tessellated: body and face index of each.
  std::vector<int> face_body, face_index;
  int faces = 0;          // faces tessellated (with or without triangles)
  double grid_cells = 0;  // cells of every face's grid (before trimming)
};

// Appends the mesh of `body`, placed by `placement` (e.g. body.placement for the file frame), to
// `out`: its faces tessellated as above, a mesh body's triangles copied; curves and point bodies
// give nothing. `body_index` is recorded in out.face_body. Throws Tessellation_too_large when
// out.mesh would exceed options.max_triangles, Precondition_violation for a bad deflection.
void tessellate(const Body& body, const Rigid_pose_3& placement, int body_index,
                const Tessellation_options& options, Tessellation& out);

}  // namespace extremal
