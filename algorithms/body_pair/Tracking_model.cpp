#include "algorithms/body_pair/Tracking_model.h"

#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "algorithms/body_pair/internal/Tuning.h"
#include "algorithms/distance/Solid_classification.h"
#include "kernel/Error.h"
#include "kernel/Nurbs_refinement.h"

#include <Eigen/Eigenvalues>

namespace extremal {

namespace {

bool overlaps(const Bbox_3& a, const Bbox_3& b) {
  for (int i = 0; i < 3; ++i)
    if (a.max(i) < b.min(i) || b.max(i) < a.min(i)) return false;
  return true;
}

// Parameters on side `side` (0 u_min, 1 u_max, 2 v_min, 3 v_max) of a surface at position s
// along the side.
void side_params(const Nurbs_surface_3& f, int side, double s, double out[2]) {
  switch (side) {
    case 0: out[0] = f.u_min(); out[1] = s; return;
    case 1: out[0] = f.u_max(); out[1] = s; return;
    case 2: out[0] = s; out[1] = f.v_min(); return;
    default: out[0] = s; out[1] = f.v_max(); return;
  }
}
double side_lo(const Nurbs_surface_3& f, int side) { return side < 2 ? f.v_min() : f.u_min(); }
double side_hi(const Nurbs_surface_3& f, int side) { return side < 2 ? f.v_max() : f.u_max(); }

// Position along side `side` of f nearest to p (samples, then Newton on the iso-curve).
double project_on_side(const Nurbs_surface_3& f, int side, const Vec3& p, double& dist) {
  const double lo = side_lo(f, side), hi = side_hi(f, side);
  const int along = side < 2 ? 1 : 0;  // the parameter that varies along the side
  double best_s = lo, best = std::numeric_limits<double>::infinity();
  Surface_point sp;
  double q[2];
  for (int i = 0; i <= 16; ++i) {
    const double s = std::min(lo + (hi - lo) * i / 16.0, hi);  // the sum can round past hi
    side_params(f, side, s, q);
    f.evaluate(q[0], q[1], sp, 0);
    const double d = (sp.p - p).squaredNorm();
    if (d < best) best = d, best_s = s;
  }
  double s = best_s;
  for (int it = 0; it < 20; ++it) {
    side_params(f, side, s, q);
    f.evaluate(q[0], q[1], sp, 2);
    const Vec3 d = sp.p - p;
    const Vec3& t1 = along == 0 ? sp.du : sp.dv;
    const Vec3& t2 = along == 0 ? sp.duu : sp.dvv;
    const double g = d.dot(t1), h = t1.squaredNorm() + d.dot(t2);
    if (!(h > 0.0)) break;
    const double sn = std::clamp(s - g / h, lo, hi);
    if (sn == s) break;
    s = sn;
  }
  side_params(f, side, s, q);
  f.evaluate(q[0], q[1], sp, 0);
  dist = (sp.p - p).norm();
  return s;
}

// Side `side` of f as a B-spline curve: its poles, weights and knots (the parameter along the
// side), when the knot vector across the side is clamped there (the side is then the row or
// column of poles on it). False otherwise.
struct Side_curve {
  std::vector<Point_3> poles;
  std::vector<double> weights, knots;
  int degree = 0;
};
bool side_curve(const Nurbs_surface_3& f, int side, Side_curve& out) {
  const bool u_fixed = side < 2;
  const std::vector<double>& across = u_fixed ? f.knots_u() : f.knots_v();
  const int p = u_fixed ? f.degree_u() : f.degree_v();
  const int n = u_fixed ? f.number_of_poles_u() : f.number_of_poles_v();
  const bool low = side % 2 == 0;
  for (int k = 0; k <= p; ++k)
    if (across[low ? k : n + k] != across[low ? 0 : n]) return false;
  const int row = low ? 0 : n - 1;
  const int m = u_fixed ? f.number_of_poles_v() : f.number_of_poles_u();
  out.poles.clear();
  out.weights.clear();
  for (int j = 0; j < m; ++j) {
    out.poles.push_back(u_fixed ? f.pole(row, j) : f.pole(j, row));
    out.weights.push_back(u_fixed ? f.weight(row, j) : f.weight(j, row));
  }
  out.knots = u_fixed ? f.knots_v() : f.knots_u();
  out.degree = u_fixed ? f.degree_v() : f.degree_u();
  return true;
}

// Certified bound on how far a point of side sf of f lies from side sg of g: when both sides
// are B-spline curves of the same degree and pole count whose knots agree up to an affine map
// (reversing or not) and whose weights are proportional, the two curves at matching
// parameters differ by a combination of the pole differences with nonnegative coefficients
// summing to one, so the largest pole difference bounds it. Infinity when not proven.
double side_gap(const Nurbs_surface_3& f, int sf, const Nurbs_surface_3& g, int sg) {
  Side_curve a, b;
  if (!side_curve(f, sf, a) || !side_curve(g, sg, b)) return HUGE_VAL;
  const int m = static_cast<int>(a.poles.size());
  if (a.degree != b.degree || m != static_cast<int>(b.poles.size()) ||
      a.knots.size() != b.knots.size())
    return HUGE_VAL;
  const int nk = static_cast<int>(a.knots.size());
  auto unit = [](const std::vector<double>& k, int i) {
    return (k[i] - k.front()) / (k.back() - k.front());
  };
  double best = HUGE_VAL;
  for (int reversed = 0; reversed < 2; ++reversed) {
    bool same = a.knots.back() > a.knots.front() && b.knots.back() > b.knots.front();
    for (int i = 0; i < nk && same; ++i) {
      const double kb = reversed ? 1.0 - unit(b.knots, nk - 1 - i) : unit(b.knots, i);
      same = std::abs(unit(a.knots, i) - kb) <= 1e-14;
    }
    if (!same) continue;
    double gap = 0.0;
    const double ratio = a.weights[0] / b.weights[reversed ? m - 1 : 0];
    for (int j = 0; j < m && same; ++j) {
      const int jb = reversed ? m - 1 - j : j;
      same = std::abs(a.weights[j] - ratio * b.weights[jb]) <= 1e-14 * a.weights[j];
      gap = std::max(gap, (to_vec3(a.poles[j]) - to_vec3(b.poles[jb])).norm());
    }
    if (same) best = std::min(best, gap);
  }
  return best;
}

// Parameter of curve c nearest to p.
double project_on_curve(const Nurbs_curve_3& c, const Vec3& p, double& dist) {
  const double lo = c.domain_min(), hi = c.domain_max();
  double best_t = lo, best = std::numeric_limits<double>::infinity();
  Curve_point cp;
  for (int i = 0; i <= 16; ++i) {
    const double t = std::min(lo + (hi - lo) * i / 16.0, hi);  // the sum can round past hi
    c.evaluate(t, cp, 0);
    const double d = (cp.p - p).squaredNorm();
    if (d < best) best = d, best_t = t;
  }
  double t = best_t;
  for (int it = 0; it < 20; ++it) {
    c.evaluate(t, cp, 2);
    const Vec3 d = cp.p - p;
    const double g = d.dot(cp.d1), h = cp.d1.squaredNorm() + d.dot(cp.d2);
    if (!(h > 0.0)) break;
    const double tn = std::clamp(t - g / h, lo, hi);
    if (tn == t) break;
    t = tn;
  }
  c.evaluate(t, cp, 0);
  dist = (cp.p - p).norm();
  return t;
}

}  // namespace

void Edge_on_face::map(double t, double out[2]) const {
  if (uv) {
    const double tt = std::clamp(t, uv->domain_min(), uv->domain_max());
    const Point_3 q = uv->point(tt);
    out[0] = q.x();
    out[1] = q.y();
    return;
  }
  out[0] = origin[0] + t * direction[0];
  out[1] = origin[1] + t * direction[1];
}

Tracking_model::Tracking_model(const Body& body) : m_body(body) {
  if (!body.mesh.empty()) {
    // A mesh: its hierarchy now; the primitives and the solver's hierarchy when a pair needs
    // them (a mesh against a NURBS body), so meshes against meshes and points cost only these.
    m_mesh = std::make_unique<Mesh_bvh>(body.mesh, body.name);
    m_box = m_mesh->box();
    m_closed = m_mesh->closed();
    return;
  }
  m_closed = body_closedness(body).closed;
  std::call_once(m_prepared, [this] { build_primitives(); });
}

void Tracking_model::prepare() const {
  // (Building fills members that are read-only once built: made once, by whichever thread.)
  std::call_once(m_prepared, [this] { const_cast<Tracking_model*>(this)->build_primitives(); });
}

void Tracking_model::build_primitives() {
  const Body& body = m_body;
  m_hierarchy = std::make_unique<Distance_hierarchy>(body);
  if (body.is_point) {
    Primitive p;
    p.kind = Primitive_kind::Point;
    p.index = 0;
    p.feature = Feature::point(Vec3::Zero());
    p.box = Point_3(0, 0, 0).bbox();
    p.global_element = m_hierarchy->element_of(Element_kind::Point, 0);
    m_links.point_primitive = 0;
    m_primitives.push_back(p);
  }
  m_links.face_primitive.assign(body.faces.size(), -1);
  for (std::size_t i = 0; i < body.faces.size(); ++i) {
    const Face& f = body.faces[i];
    Primitive p;
    p.kind = Primitive_kind::Face;
    p.index = static_cast<int>(i);
    p.feature = Feature::surface(f.surface);
    p.box = f.surface.hull_bbox();
    if (f.trim_region.is_trimmed()) p.trim = &f.trim_region;
    p.global_element = m_hierarchy->element_of(Element_kind::Face, p.index);
    m_links.face_primitive[i] = static_cast<int>(m_primitives.size());
    m_primitives.push_back(p);
  }
  m_links.curve_primitive.assign(body.curves.size(), -1);
  for (std::size_t i = 0; i < body.curves.size(); ++i) {
    Primitive p;
    p.kind = Primitive_kind::Curve;
    p.index = static_cast<int>(i);
    p.feature = Feature::curve(body.curves[i]);
    p.box = body.curves[i].hull_bbox();
    p.global_element = m_hierarchy->element_of(Element_kind::Curve, p.index);
    m_links.curve_primitive[i] = static_cast<int>(m_primitives.size());
    m_primitives.push_back(p);
  }
  add_brep_edges();
  add_mesh();
  match_patch_sides();
  build_tree();
  measure_flatness();
}

namespace {

// The largest distance of the points from their best plane (dimension 2) or line (dimension 1):
// the smallest principal direction's (or the two smaller ones') extent about the centroid.
double spread_off(const std::vector<Vec3>& points, int dimension) {
  if (points.empty()) return HUGE_VAL;
  Vec3 c = Vec3::Zero();
  for (const Vec3& p : points) c += p;
  c /= static_cast<double>(points.size());
  Mat3 cov = Mat3::Zero();
  for (const Vec3& p : points) cov += (p - c) * (p - c).transpose();
  const Eigen::SelfAdjointEigenSolver<Mat3> eigen(cov);
  if (eigen.info() != Eigen::Success) return HUGE_VAL;
  const Mat3 axes = eigen.eigenvectors();  // columns by increasing eigenvalue
  double off = 0.0;
  for (const Vec3& p : points) {
    const Vec3 d = p - c;
    const double across = dimension == 2 ? std::abs(axes.col(0).dot(d))
                                         : std::hypot(axes.col(0).dot(d), axes.col(1).dot(d));
    off = std::max(off, across);
  }
  return off;
}

}  // namespace

void Tracking_model::measure_flatness() {
  std::vector<Vec3> points;
  for (Primitive& p : m_primitives) {
    const int dim = p.feature.dimension();
    points.clear();
    if (dim == 0) {
      p.flatness = 0.0;
      continue;
    }
    if (p.kind == Primitive_kind::Triangle || p.kind == Primitive_kind::Mesh_edge) {
      p.flatness = 0.0;  // (a triangle is planar, a mesh edge straight)
      continue;
    }
    if (const Nurbs_surface_3* f = p.feature.surface())
      for (const Point_3& q : f->poles()) points.emplace_back(q.x(), q.y(), q.z());
    else if (const Nurbs_curve_3* c = p.feature.curve())
      for (const Point_3& q : c->poles()) points.emplace_back(q.x(), q.y(), q.z());
    const double off = spread_off(points, dim);
    // (The primitive lies in its control points' hull: within `off` of the plane or line.)
    p.flatness = off <= internal::k_flat_fraction * box_diagonal(p.box) ? off : HUGE_VAL;
  }
}

void Tracking_model::add_brep_edges() {
  const Body& body = m_body;
  m_links.edge_primitive.assign(body.edges.size(), -1);
  std::vector<std::pair<int, int>> face_edge;  // (face primitive, edge primitive)
  for (std::size_t k = 0; k < body.edges.size(); ++k) {
    const Edge& edge = body.edges[k];
    if (!edge.curve) continue;
    const double t0 = std::max(edge.t_min, edge.curve->domain_min());
    const double t1 = std::min(edge.t_max, edge.curve->domain_max());
    if (!(t0 < t1)) continue;
    Nurbs_curve_3 c = *edge.curve;
    if (t0 > c.domain_min()) c = split(c, t0).second;
    if (t1 < c.domain_max()) c = split(c, t1).first;
    m_own.curves.push_back(std::make_unique<Nurbs_curve_3>(std::move(c)));
    Primitive p;
    p.kind = Primitive_kind::Edge;
    p.index = static_cast<int>(k);
    p.feature = Feature::curve(*m_own.curves.back());
    p.box = m_own.curves.back()->hull_bbox();
    p.global_element =
        m_hierarchy->element_of(Element_kind::Curve, static_cast<int>(body.curves.size() + k));
    const int prim = static_cast<int>(m_primitives.size());
    p.first_link = static_cast<int>(m_links.edge_faces.size());
    for (const Edge_use& u : edge.uses) {
      if (u.face < 0 || u.face >= static_cast<int>(body.faces.size())) continue;
      const Face& f = body.faces[u.face];
      if (u.loop < 0 || u.loop >= static_cast<int>(f.trims.size())) continue;
      const Trim_loop& loop = f.trims[u.loop];
      if (u.curve < 0 || u.curve >= static_cast<int>(loop.curves.size())) continue;
      Edge_on_face e;
      e.face = m_links.face_primitive[u.face];
      e.uv = &loop.curves[u.curve].uv;
      m_links.edge_faces.push_back(e);
      face_edge.emplace_back(e.face, prim);
    }
    p.link_count = static_cast<int>(m_links.edge_faces.size()) - p.first_link;
    m_links.edge_primitive[k] = prim;
    m_primitives.push_back(p);
  }
  // Faces' edge lists (CSR).
  link_faces_to_edges(face_edge);
}

void Tracking_model::link_faces_to_edges(std::vector<std::pair<int, int>>& face_edge) {
  std::sort(face_edge.begin(), face_edge.end());
  face_edge.erase(std::unique(face_edge.begin(), face_edge.end()), face_edge.end());
  for (std::size_t i = 0; i < face_edge.size();) {
    Primitive& f = m_primitives[face_edge[i].first];
    f.first_link = static_cast<int>(m_links.face_edges.size());
    std::size_t j = i;
    for (; j < face_edge.size() && face_edge[j].first == face_edge[i].first; ++j)
      m_links.face_edges.push_back(face_edge[j].second);
    f.link_count = static_cast<int>(j - i);
    i = j;
  }
}

void Tracking_model::add_mesh() {
  const Triangle_mesh& mesh = m_body.mesh;
  if (mesh.empty()) return;
  const int nv = static_cast<int>(mesh.vertices.size());
  m_links.triangle_primitive.assign(mesh.triangles.size(), -1);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    for (int k : tri)
      if (k < 0 || k >= nv)
        throw Invalid_input("body '" + m_body.name + "': triangle " + std::to_string(t) +
                            " refers to vertex " + std::to_string(k) + " of " +
                            std::to_string(nv));
    const Point_3& p0 = mesh.vertices[tri[0]];
    const Point_3& p1 = mesh.vertices[tri[1]];
    const Point_3& p2 = mesh.vertices[tri[2]];
    const Point_3 p3 = p1 + (p2 - p0);
    // Poles (i along u, j along v): (0,0) p0, (0,1) p2, (1,0) p1, (1,1) p1 + p2 - p0.
    m_own.surfaces.push_back(std::make_unique<Nurbs_surface_3>(
        1, 1, 2, 2, std::vector<Point_3>{p0, p2, p1, p3}, std::vector<double>{0, 0, 1, 1},
        std::vector<double>{0, 0, 1, 1}));
    Primitive p;
    p.kind = Primitive_kind::Triangle;
    p.index = static_cast<int>(t);
    p.feature = Feature::surface(*m_own.surfaces.back());
    Bbox_3 box = p0.bbox() + p1.bbox() + p2.bbox();
    p.box = box;
    p.global_element = m_hierarchy->element_of(
        Element_kind::Face, static_cast<int>(m_body.faces.size() + t));
    m_links.triangle_primitive[t] = static_cast<int>(m_primitives.size());
    m_primitives.push_back(p);
  }
  // Unique edges, each a segment from its lower to its higher vertex index.
  struct Use {
    int a, b, triangle, local;
  };
  std::vector<Use> uses;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
      if (a == b) continue;
      uses.push_back({std::min(a, b), std::max(a, b), static_cast<int>(t), k});
    }
  std::sort(uses.begin(), uses.end(), [](const Use& x, const Use& y) {
    return x.a != y.a ? x.a < y.a : x.b != y.b ? x.b < y.b : x.triangle < y.triangle;
  });
  std::vector<std::pair<int, int>> face_edge;
  // Corner k of the triangle in its (u, v): p0 (0, 0), p1 (1, 0), p2 (0, 1).
  const double corner[3][2] = {{0, 0}, {1, 0}, {0, 1}};
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    while (j < uses.size() && uses[j].a == uses[i].a && uses[j].b == uses[i].b) ++j;
    const Point_3& pa = mesh.vertices[uses[i].a];
    const Point_3& pb = mesh.vertices[uses[i].b];
    m_own.curves.push_back(std::make_unique<Nurbs_curve_3>(
        1, std::vector<Point_3>{pa, pb}, std::vector<double>{0, 0, 1, 1}));
    Primitive p;
    p.kind = Primitive_kind::Mesh_edge;
    p.index = static_cast<int>(m_primitives.size());
    p.feature = Feature::curve(*m_own.curves.back());
    p.box = pa.bbox() + pb.bbox();
    const int prim = static_cast<int>(m_primitives.size());
    p.first_link = static_cast<int>(m_links.edge_faces.size());
    for (std::size_t k = i; k < j; ++k) {
      const Use& u = uses[k];
      const auto& tri = mesh.triangles[u.triangle];
      // Local corners of the segment's start (vertex a) and end (vertex b).
      int ca = -1, cb = -1;
      for (int c = 0; c < 3; ++c) {
        if (tri[c] == u.a && ca < 0) ca = c;
        if (tri[c] == u.b && cb < 0) cb = c;
      }
      Edge_on_face e;
      e.face = m_links.triangle_primitive[u.triangle];
      e.origin[0] = corner[ca][0];
      e.origin[1] = corner[ca][1];
      e.direction[0] = corner[cb][0] - corner[ca][0];
      e.direction[1] = corner[cb][1] - corner[ca][1];
      m_links.edge_faces.push_back(e);
      face_edge.emplace_back(e.face, prim);
    }
    p.link_count = static_cast<int>(m_links.edge_faces.size()) - p.first_link;
    m_primitives.push_back(p);
    i = j;
  }
  link_faces_to_edges(face_edge);
}

void Tracking_model::match_patch_sides() {
  // Untrimmed faces without B-rep edges (generated multi-patch bodies): a side whose boundary
  // curve coincides with another face's side continues there.
  struct Side_box {
    Bbox_3 box;
    int face, side;
  };
  std::vector<Side_box> sides;
  double size = 0.0;
  for (const Primitive& p : m_primitives)
    if (p.kind == Primitive_kind::Face) size = std::max(size, box_diagonal(p.box));
  const double tol = 1e-7 * std::max(size, 1e-300);
  Surface_point sp;
  for (std::size_t i = 0; i < m_primitives.size(); ++i) {
    const Primitive& p = m_primitives[i];
    if (p.kind != Primitive_kind::Face || p.trim || p.link_count > 0) continue;
    const Nurbs_surface_3& f = *p.feature.surface();
    for (int side = 0; side < 4; ++side) {
      if ((side < 2 && f.is_closed_u()) || (side >= 2 && f.is_closed_v())) continue;
      if (p.feature.collapsed_edges() & (1u << side)) continue;
      Bbox_3 box;
      double q[2];
      for (int k = 0; k <= 8; ++k) {
        side_params(f, side,
                    std::min(side_lo(f, side) + (side_hi(f, side) - side_lo(f, side)) * k / 8.0,
                             side_hi(f, side)),
                    q);
        f.evaluate(q[0], q[1], sp, 0);
        box += Bbox_3(sp.p.x() - tol, sp.p.y() - tol, sp.p.z() - tol, sp.p.x() + tol,
                      sp.p.y() + tol, sp.p.z() + tol);
      }
      sides.push_back({box, static_cast<int>(i), side});
    }
  }
  if (sides.size() < 2) return;
  // Explicit ids: box_self_intersection_d copies the boxes, so ids cannot be their addresses.
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, int>;
  std::vector<Box> boxes;
  boxes.reserve(sides.size());
  for (std::size_t k = 0; k < sides.size(); ++k) boxes.emplace_back(sides[k].box, static_cast<int>(k));
  std::vector<std::pair<int, int>> candidates;
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& x, const Box& y) {
    candidates.emplace_back(x.info(), y.info());
  });
  std::sort(candidates.begin(), candidates.end());
  // Two sides match when points along each lie on the other (to the tolerance).
  auto lies_on = [&](const Side_box& from, const Side_box& to) {
    const Nurbs_surface_3& f = *m_primitives[from.face].feature.surface();
    const Nurbs_surface_3& g = *m_primitives[to.face].feature.surface();
    double q[2];
    for (int k = 0; k <= 6; ++k) {
      side_params(f, from.side,
                  std::min(side_lo(f, from.side) + (side_hi(f, from.side) - side_lo(f, from.side)) * k / 6.0,
                           side_hi(f, from.side)),
                  q);
      f.evaluate(q[0], q[1], sp, 0);
      double dist;
      project_on_side(g, to.side, sp.p, dist);
      if (!(dist <= tol)) return false;
    }
    return true;
  };
  for (const auto& [x, y] : candidates) {
    const Side_box& a = sides[x];
    const Side_box& b = sides[y];
    if (a.face == b.face) continue;
    Primitive& pa = m_primitives[a.face];
    Primitive& pb = m_primitives[b.face];
    if (pa.side_neighbour[a.side] >= 0 || pb.side_neighbour[b.side] >= 0) continue;
    if (!lies_on(a, b) || !lies_on(b, a)) continue;
    pa.side_neighbour[a.side] = b.face;
    pa.side_neighbour_side[a.side] = b.side;
    pb.side_neighbour[b.side] = a.face;
    pb.side_neighbour_side[b.side] = a.side;
    pa.side_gap[a.side] = pb.side_gap[b.side] =
        side_gap(*pa.feature.surface(), a.side, *pb.feature.surface(), b.side);
    m_matched_sides += 2;
  }
}

void Tracking_model::build_tree() {
  std::vector<int> ids(m_primitives.size());
  std::iota(ids.begin(), ids.end(), 0);
  if (!m_mesh)  // (a mesh's box is its hierarchy's, read by pairs already)
    for (const Primitive& p : m_primitives) m_box += p.box;
  if (ids.empty()) throw Invalid_input("body '" + m_body.name + "' has nothing to track");
  m_tree.reserve(2 * ids.size());
  // Recursive median split on the longest axis of the centres.
  struct Builder {
    Tracking_model& m;
    std::vector<int>& ids;
    int build(int begin, int end) {
      const int index = static_cast<int>(m.m_tree.size());
      m.m_tree.emplace_back();
      Bbox_3 box, centres;
      for (int k = begin; k < end; ++k) {
        box += m.m_primitives[ids[k]].box;
        const Vec3 c = box_centre(m.m_primitives[ids[k]].box);
        centres += Bbox_3(c.x(), c.y(), c.z(), c.x(), c.y(), c.z());
      }
      m.m_tree[index].box = box;
      if (end - begin == 1) {
        m.m_tree[index].primitive = ids[begin];
        return index;
      }
      int axis = 0;
      for (int a = 1; a < 3; ++a)
        if (centres.max(a) - centres.min(a) > centres.max(axis) - centres.min(axis)) axis = a;
      const int mid = (begin + end) / 2;
      std::nth_element(ids.begin() + begin, ids.begin() + mid, ids.begin() + end, [&](int a, int b) {
        return box_centre(m.m_primitives[a].box)[axis] < box_centre(m.m_primitives[b].box)[axis];
      });
      const int l = build(begin, mid);
      const int r = build(mid, end);
      m.m_tree[index].left = l;
      m.m_tree[index].right = r;
      return index;
    }
  } builder{*this, ids};
  builder.build(0, static_cast<int>(ids.size()));
}

int Tracking_model::primitive_of(Element_kind kind, int index) const {
  prepare();
  switch (kind) {
    case Element_kind::Point: return m_links.point_primitive;
    case Element_kind::Face: {
      const int nf = static_cast<int>(m_links.face_primitive.size());
      if (index >= 0 && index < nf) return m_links.face_primitive[index];
      if (index >= nf && index - nf < static_cast<int>(m_links.triangle_primitive.size()))
        return m_links.triangle_primitive[index - nf];
      return -1;
    }
    case Element_kind::Curve: {
      const int nc = static_cast<int>(m_links.curve_primitive.size());
      if (index >= 0 && index < nc) return m_links.curve_primitive[index];
      if (index >= nc && index - nc < static_cast<int>(m_links.edge_primitive.size()))
        return m_links.edge_primitive[index - nc];
      return -1;
    }
  }
  return -1;
}

void Tracking_model::collect(const Bbox_3& query, bool with_mesh_edges, std::vector<int>& out) const {
  prepare();
  // Iterative descent with a fixed stack (the tree is balanced: depth ~ log2 n).
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = m_tree[stack[--top]];
    if (!overlaps(n.box, query)) continue;
    if (n.primitive >= 0) {
      if (with_mesh_edges || m_primitives[n.primitive].kind != Primitive_kind::Mesh_edge)
        out.push_back(n.primitive);
      continue;
    }
    stack[top++] = n.left;
    stack[top++] = n.right;
  }
}

const int* Tracking_model::edges_of(int f, int& count) const {
  prepare();
  const Primitive& p = m_primitives[f];
  count = p.is_surface() ? p.link_count : 0;
  return count ? m_links.face_edges.data() + p.first_link : nullptr;
}

const Edge_on_face* Tracking_model::faces_of(int e, int& count) const {
  prepare();
  const Primitive& p = m_primitives[e];
  count = p.feature.dimension() == 1 ? p.link_count : 0;
  return count ? m_links.edge_faces.data() + p.first_link : nullptr;
}

bool Tracking_model::contains(int primitive, const double* q) const {
  prepare();
  const Primitive& p = m_primitives[primitive];
  if (p.kind == Primitive_kind::Triangle) return q[0] + q[1] <= 1.0 + 1e-12;
  if (p.trim) return p.trim->contains(q[0], q[1]);
  return true;
}

bool Tracking_model::map_across_side(int f, int side, const double* params, double out[2]) const {
  prepare();
  const Primitive& p = m_primitives[f];
  const int n = p.side_neighbour[side];
  if (n < 0) return false;
  Surface_point sp;
  p.feature.surface()->evaluate(params[0], params[1], sp, 0);
  const Nurbs_surface_3& g = *m_primitives[n].feature.surface();
  const int nside = p.side_neighbour_side[side];
  double dist;
  const double s = project_on_side(g, nside, sp.p, dist);
  if (!(dist <= 1e-6 * std::max(box_diagonal(m_box), 1e-300))) return false;
  side_params(g, nside, s, out);
  return true;
}

int Tracking_model::nearest_edge(int f, const Vec3& p, double& t, const Vec3* toward) const {
  prepare();
  int count = 0;
  const int* edges = edges_of(f, count);
  int best = -1;
  double best_d = std::numeric_limits<double>::infinity();
  // Ties (with `toward`): at a corner every edge through it projects p onto its end. Taking the
  // first could hand the point to an edge along which the distance rises, whose face then
  // hands it straight back (a face-edge ping-pong at every step). Edges within `tie` of the
  // nearest are told apart by the slope of the squared distance to `toward` along them.
  const double tie = 1e-7 * box_diagonal(m_box);
  double best_slope = HUGE_VAL;
  for (int k = 0; k < count; ++k) {
    const Nurbs_curve_3& c = *m_primitives[edges[k]].feature.curve();
    double d;
    const double te = project_on_curve(c, p, d);
    if (!toward) {
      if (d < best_d) best_d = d, best = edges[k], t = te;
      continue;
    }
    if (!(d <= best_d + tie)) continue;
    Curve_point cp;
    c.evaluate(te, cp, 1);
    const double speed = cp.d1.norm();
    // Rate of change per unit length, moving along the edge from te; from an end the point
    // can only move into the edge, from inside (or the joint of a closed edge) either way.
    const double rate = speed > 0.0 ? (cp.p - *toward).dot(cp.d1) / speed : 0.0;
    const double span = c.domain_max() - c.domain_min();
    const bool at_lo = te <= c.domain_min() + 1e-12 * span;
    const bool at_hi = te >= c.domain_max() - 1e-12 * span;
    const double slope =
        c.is_closed() ? -std::abs(rate) : at_lo ? rate : at_hi ? -rate : -std::abs(rate);
    if (best < 0 || d < best_d - tie || slope < best_slope) {
      best = edges[k];
      t = te;
      best_slope = slope;
    }
    best_d = std::min(best_d, d);
  }
  return best;
}

}  // namespace extremal
