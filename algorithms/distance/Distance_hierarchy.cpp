#include "algorithms/distance/Distance_hierarchy.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>

#include "algorithms/distance/internal/Bezier_net.h"
#include "kernel/Error.h"
#include "kernel/Nurbs_refinement.h"

namespace extremal {

const char* to_string(Element_kind k) {
  switch (k) {
    case Element_kind::Face: return "face";
    case Element_kind::Curve: return "curve";
    case Element_kind::Point: return "point";
  }
  return "?";
}

namespace {

// The interior knot values of direction `dir` (0: u) along which the surface may fold: a knot of
// multiplicity at least the degree makes it only C0 there, and it folds unless every row of
// poles across the line turns no corner at the pole the surface passes through (then it is
// tangent-continuous, as at the double knots of a rational circle, and an extremum on the line
// has a zero derivative on both sides). A collapsed row (a pole) turns no corner.
std::vector<double> fold_lines(const Nurbs_surface_3& s, int dir) {
  const std::vector<double>& knots = dir == 0 ? s.knots_u() : s.knots_v();
  const int degree = dir == 0 ? s.degree_u() : s.degree_v();
  const int across = dir == 0 ? s.number_of_poles_v() : s.number_of_poles_u();
  const double lo = dir == 0 ? s.u_min() : s.v_min(), hi = dir == 0 ? s.u_max() : s.v_max();
  auto pole = [&](int along, int row) -> Vec3 {
    const Point_3& p = dir == 0 ? s.pole(along, row) : s.pole(row, along);
    return Vec3(p.x(), p.y(), p.z());
  };
  std::vector<double> folds;
  for (std::size_t i = 0; i < knots.size();) {
    std::size_t j = i;
    while (j < knots.size() && knots[j] == knots[i]) ++j;
    const int multiplicity = static_cast<int>(j - i);
    if (knots[i] > lo && knots[i] < hi && multiplicity >= degree) {
      bool fold = multiplicity > degree;
      const int at = static_cast<int>(i) - 1;  // the pole the surface passes through there
      for (int r = 0; r < across && !fold; ++r) {
        const Vec3 in = pole(at, r) - pole(at - 1, r), out = pole(at + 1, r) - pole(at, r);
        if (in == Vec3::Zero() && out == Vec3::Zero()) continue;
        fold = !(in.dot(out) > 0.0) || in.cross(out).norm() > 1e-13 * in.norm() * out.norm();
      }
      if (fold) folds.push_back(knots[i]);
    }
    i = j;
  }
  return folds;
}

Bbox_3 box_of(const Eigen::Vector4d* h, int n) {
  Bbox_3 b;
  for (int k = 0; k < n; ++k) {
    const Vec3 c = h[k].head<3>() / h[k][3];
    b += Bbox_3(c.x(), c.y(), c.z(), c.x(), c.y(), c.z());
  }
  return b;
}

double box_half_diagonal(const Bbox_3& b) {
  return 0.5 * Vec3(b.xmax() - b.xmin(), b.ymax() - b.ymin(), b.zmax() - b.zmin()).norm();
}

}  // namespace

Distance_hierarchy::Distance_hierarchy(const Body& body) : m_name(body.name) {
  if (body.is_empty())
    throw Invalid_input("body '" + body.name + "' has no point, face or curve to measure from");
  auto add_piece = [&](int element, int dim, int nu, int nv, const double lo[2],
                       const double hi[2], const auto& hom) {
    Piece p;
    p.element = element;
    p.dimension = dim;
    p.nu = nu;
    p.nv = nv;
    p.lo[0] = lo[0];
    p.lo[1] = lo[1];
    p.hi[0] = hi[0];
    p.hi[1] = hi[1];
    p.offset = static_cast<int>(m_poles.size());
    m_poles.insert(m_poles.end(), hom.begin(), hom.end());
    p.box = box_of(m_poles.data() + p.offset, nu * nv);
    m_pieces.push_back(p);
  };
  if (body.is_point) {
    Element e;
    e.kind = Element_kind::Point;
    e.index = 0;
    e.feature = Feature::point(Vec3::Zero());
    m_elements.push_back(e);
    m_trims.emplace_back();
    const double zero[2] = {0.0, 0.0};
    const std::vector<Eigen::Vector4d> one = {Eigen::Vector4d(0, 0, 0, 1)};
    add_piece(0, 0, 1, 1, zero, zero, one);
  }
  // Faces, then a mesh body's triangles as flat degree 1 x 1 patches (corners p0, p1, p2, p2).
  std::vector<Nurbs_surface_3> triangles;
  triangles.reserve(body.mesh.triangles.size());
  for (const auto& t : body.mesh.triangles) {
    const Point_3& p0 = body.mesh.vertices.at(t[0]);
    const Point_3& p1 = body.mesh.vertices.at(t[1]);
    const Point_3& p2 = body.mesh.vertices.at(t[2]);
    triangles.emplace_back(1, 1, 2, 2, std::vector<Point_3>{p0, p2, p1, p2},
                           std::vector<double>{0, 0, 1, 1}, std::vector<double>{0, 0, 1, 1});
  }
  const std::size_t face_count = body.faces.size() + triangles.size();
  for (std::size_t i = 0; i < face_count; ++i) {
    const bool is_face = i < body.faces.size();
    const Nurbs_surface_3& s = is_face ? body.faces[i].surface : triangles[i - body.faces.size()];
    if (s.degree_u() + 1 > internal::k_max_net_side || s.degree_v() + 1 > internal::k_max_net_side) {
      std::ostringstream os;
      os << "body '" << body.name << "' face " << i << ": degree " << s.degree_u() << " x "
         << s.degree_v() << " is above the global distance solver's limit of "
         << internal::k_max_net_side - 1;
      throw Invalid_input(os.str());
    }
    m_surfaces.push_back(std::make_unique<Nurbs_surface_3>(s));
    Element e;
    e.kind = Element_kind::Face;
    e.index = static_cast<int>(i);
    e.feature = Feature::surface(*m_surfaces.back());
    m_trims.emplace_back();
    if (is_face && body.faces[i].trim_region.is_trimmed()) {
      const Trim_region& tr = body.faces[i].trim_region;
      m_trims.back() = tr;
      e.trimmed = true;
      const double band = tr.tolerance();
      e.trim_lo[0] = tr.u_min() - band;
      e.trim_lo[1] = tr.v_min() - band;
      e.trim_hi[0] = tr.u_max() + band;
      e.trim_hi[1] = tr.v_max() + band;
    }
    const int element = static_cast<int>(m_elements.size());
    m_elements.push_back(e);
    const Bezier_patches bp = extract_bezier(s);
    for (const Nurbs_surface_3& piece : bp.patches) {
      const double lo[2] = {piece.u_min(), piece.v_min()};
      const double hi[2] = {piece.u_max(), piece.v_max()};
      add_piece(element, 2, piece.degree_u() + 1, piece.degree_v() + 1, lo, hi,
                piece.homogeneous_poles());
    }
  }
  for (std::size_t i = 0; i < body.curves.size(); ++i) {
    const Nurbs_curve_3& c = body.curves[i];
    if (c.degree() + 1 > internal::k_max_net_side) {
      std::ostringstream os;
      os << "body '" << body.name << "' curve " << i << ": degree " << c.degree()
         << " is above the global distance solver's limit of " << internal::k_max_net_side - 1;
      throw Invalid_input(os.str());
    }
    m_curves.push_back(std::make_unique<Nurbs_curve_3>(c));
    Element e;
    e.kind = Element_kind::Curve;
    e.index = static_cast<int>(i);
    e.feature = Feature::curve(*m_curves.back());
    const int element = static_cast<int>(m_elements.size());
    m_elements.push_back(e);
    m_trims.emplace_back();
    for (const Nurbs_curve_3& piece : extract_bezier(c)) {
      const double lo[2] = {piece.domain_min(), 0.0};
      const double hi[2] = {piece.domain_max(), 0.0};
      add_piece(element, 1, piece.degree() + 1, 1, lo, hi, piece.homogeneous_poles());
    }
  }
  // B-rep edges: the trim boundaries in 3D, restricted to the edge's parameter range.
  for (std::size_t k = 0; k < body.edges.size(); ++k) {
    const Edge& edge = body.edges[k];
    if (!edge.curve) continue;  // degenerate (its point lies on the faces' pieces) or no curve
    Nurbs_curve_3 c = *edge.curve;
    const double t0 = std::max(edge.t_min, c.domain_min());
    const double t1 = std::min(edge.t_max, c.domain_max());
    if (!(t0 < t1)) continue;
    if (t0 > c.domain_min()) c = split(c, t0).second;
    if (t1 < c.domain_max()) c = split(c, t1).first;
    if (c.degree() + 1 > internal::k_max_net_side) {
      std::ostringstream os;
      os << "body '" << body.name << "' edge " << k << ": degree " << c.degree()
         << " is above the global distance solver's limit of " << internal::k_max_net_side - 1;
      throw Invalid_input(os.str());
    }
    m_curves.push_back(std::make_unique<Nurbs_curve_3>(std::move(c)));
    Element e;
    e.kind = Element_kind::Curve;
    e.index = static_cast<int>(body.curves.size() + k);
    e.feature = Feature::curve(*m_curves.back());
    const int element = static_cast<int>(m_elements.size());
    m_elements.push_back(e);
    m_trims.emplace_back();
    for (const Nurbs_curve_3& piece : extract_bezier(*m_curves.back())) {
      const double lo[2] = {piece.domain_min(), 0.0};
      const double hi[2] = {piece.domain_max(), 0.0};
      add_piece(element, 1, piece.degree() + 1, 1, lo, hi, piece.homogeneous_poles());
    }
  }
  // Centres and axes of symmetry of B-rep faces and curves (not of mesh triangles).
  {
    Bbox_3 all;
    for (const Piece& p : m_pieces) all += p.box;
    const double tol = symmetry_tolerance(all);
    for (Element& e : m_elements) {
      Symmetry s;
      if (e.kind == Element_kind::Face && e.index < static_cast<int>(body.faces.size()))
        s = find_symmetry(*e.feature.surface());
      else if (e.kind == Element_kind::Curve)
        s = find_symmetry(*e.feature.curve());
      if (s.any()) e.symmetry = symmetry_index(s, tol);
    }
  }
  // Interior knot lines where a face may fold (see reaches_kink).
  m_kinks.resize(m_elements.size());
  for (std::size_t k = 0; k < m_elements.size(); ++k) {
    const Nurbs_surface_3* s = m_elements[k].feature.surface();
    if (m_elements[k].kind != Element_kind::Face || s == nullptr) continue;
    for (int dir = 0; dir < 2; ++dir) m_kinks[k][dir] = fold_lines(*s, dir);
  }
  // Open sides (see Element::open_sides). A face's edges carry its boundary when every edge
  // that bounds it became a curve element or is degenerate (a pole). An edge the file gives no
  // usable 3D curve for carries nothing: a face it bounds keeps its trim boundary open, or an
  // extremum there would be dropped with the sub-patches that lead to it.
  std::vector<int> edge_state(body.faces.size(), 0);  // 0 no edges, 1 all carried, 2 some not
  for (std::size_t k = 0; k < body.edges.size(); ++k) {
    const Edge& edge = body.edges[k];
    bool carried = !edge.curve && edge.degenerate;
    if (edge.curve) {
      const double t0 = std::max(edge.t_min, edge.curve->domain_min());
      const double t1 = std::min(edge.t_max, edge.curve->domain_max());
      carried = t0 < t1;
    }
    for (const Edge_use& use : edge.uses) {
      if (use.face < 0 || use.face >= static_cast<int>(edge_state.size())) continue;
      int& st = edge_state[use.face];
      st = !carried ? 2 : std::max(st, 1);
    }
  }
  for (Element& e : m_elements) {
    const Feature& f = e.feature;
    if (e.kind == Element_kind::Point) continue;
    if (e.kind == Element_kind::Curve) {
      e.open_sides = f.is_closed(0) ? 0u : 3u;
      continue;
    }
    const bool face = e.index < static_cast<int>(body.faces.size());
    if (face && edge_state[e.index] == 1) continue;  // every boundary is a curve element
    if (e.trimmed) {
      e.open_sides = 0x1Fu;
      continue;
    }
    // Collapsed edges stay open: an apex is a boundary point of the geometry.
    for (int dir = 0; dir < 2; ++dir)
      if (!f.is_closed(dir)) e.open_sides |= 3u << (2 * dir);
  }
  if (m_pieces.empty())
    throw Invalid_input("body '" + body.name + "' has no point, face or curve to measure from");
  // Pieces were added element by element: record each element's range and its lookup.
  for (auto& e : m_elements) e.piece_count = 0;
  for (int p = static_cast<int>(m_pieces.size()) - 1; p >= 0; --p) {
    Element& e = m_elements[m_pieces[p].element];
    e.first_piece = p;
    ++e.piece_count;
  }
  m_face_element.assign(body.faces.size() + body.mesh.triangles.size(), -1);
  m_curve_element.assign(body.curves.size() + body.edges.size(), -1);
  for (std::size_t k = 0; k < m_elements.size(); ++k) {
    const Element& e = m_elements[k];
    if (e.kind == Element_kind::Face) m_face_element[e.index] = static_cast<int>(k);
    if (e.kind == Element_kind::Curve) m_curve_element[e.index] = static_cast<int>(k);
  }
  m_leaf_of_piece.assign(m_pieces.size(), -1);
  std::vector<int> ids(m_pieces.size());
  std::iota(ids.begin(), ids.end(), 0);
  m_tree.reserve(2 * m_pieces.size());
  build_tree(ids, 0, static_cast<int>(ids.size()));
}

int Distance_hierarchy::symmetry_index(const Symmetry& s, double tol) {
  for (std::size_t k = 0; k < m_symmetries.size(); ++k) {
    const Symmetry& t = m_symmetries[k];
    if (t.kind == s.kind && (t.point - s.point).norm() <= tol &&
        t.direction.cross(s.direction).norm() <= 1e-9)
      return static_cast<int>(k);
  }
  m_symmetries.push_back(s);
  return static_cast<int>(m_symmetries.size()) - 1;
}

bool Distance_hierarchy::on_body(int e, const double* q) const {
  const Element& el = m_elements[e];
  if (el.kind != Element_kind::Face || !el.trimmed) return true;
  const Nurbs_surface_3& s = *el.feature.surface();
  return q[0] >= s.u_min() && q[0] <= s.u_max() && q[1] >= s.v_min() && q[1] <= s.v_max() &&
         m_trims[e].contains(q[0], q[1]);
}

int Distance_hierarchy::element_of(Element_kind kind, int index) const {
  switch (kind) {
    case Element_kind::Point:
      return !m_elements.empty() && m_elements.front().kind == Element_kind::Point ? 0 : -1;
    case Element_kind::Face:
      return index >= 0 && index < static_cast<int>(m_face_element.size()) ? m_face_element[index]
                                                                           : -1;
    case Element_kind::Curve:
      return index >= 0 && index < static_cast<int>(m_curve_element.size())
                 ? m_curve_element[index]
                 : -1;
  }
  return -1;
}

bool Distance_hierarchy::reaches_kink(int e, const double* lo, const double* hi) const {
  const auto& kinks = m_kinks[static_cast<std::size_t>(e)];
  for (int dir = 0; dir < 2; ++dir) {
    const std::vector<double>& t = kinks[dir];
    const auto it = std::lower_bound(t.begin(), t.end(), lo[dir]);
    if (it != t.end() && *it <= hi[dir]) return true;
  }
  return false;
}

bool Distance_hierarchy::reaches_uncarried(int e, const double* lo, const double* hi,
                                           unsigned open) const {
  if (open & 0x10u) return true;
  const Feature& f = m_elements[static_cast<std::size_t>(e)].feature;
  unsigned touch = 0;
  for (int k = 0; k < f.dimension(); ++k) {
    if (lo[k] <= f.lower(k)) touch |= 1u << (2 * k);
    if (hi[k] >= f.upper(k)) touch |= 2u << (2 * k);
  }
  return (touch & open) != 0u || reaches_kink(e, lo, hi);
}

bool Distance_hierarchy::may_hold_trimmed(int e, const double* lo, const double* hi) const {
  const Element& el = m_elements[e];
  if (el.kind != Element_kind::Face || !el.trimmed) return true;
  if (hi[0] < el.trim_lo[0] || lo[0] > el.trim_hi[0] || hi[1] < el.trim_lo[1] ||
      lo[1] > el.trim_hi[1])
    return false;
  return !m_trims[e].box_outside(lo[0], lo[1], hi[0], hi[1]);
}

int Distance_hierarchy::build_tree(std::vector<int>& ids, int begin, int end) {
  const int index = static_cast<int>(m_tree.size());
  m_tree.emplace_back();
  Bbox_3 box, centres;
  for (int k = begin; k < end; ++k) {
    box += m_pieces[ids[k]].box;
    const Vec3 c = box_centre(m_pieces[ids[k]].box);
    centres += Bbox_3(c.x(), c.y(), c.z(), c.x(), c.y(), c.z());
  }
  m_tree[index].box = box;
  m_tree[index].centre = box_centre(box);
  m_tree[index].radius = box_half_diagonal(box);
  if (end - begin == 1) {
    m_tree[index].piece = ids[begin];
    m_leaf_of_piece[ids[begin]] = index;
    return index;
  }
  int axis = 0;
  const double ext[3] = {centres.xmax() - centres.xmin(), centres.ymax() - centres.ymin(),
                         centres.zmax() - centres.zmin()};
  if (ext[1] > ext[axis]) axis = 1;
  if (ext[2] > ext[axis]) axis = 2;
  const int mid = (begin + end) / 2;
  std::nth_element(ids.begin() + begin, ids.begin() + mid, ids.begin() + end, [&](int a, int b) {
    return box_centre(m_pieces[a].box)[axis] < box_centre(m_pieces[b].box)[axis];
  });
  const int left = build_tree(ids, begin, mid);
  const int right = build_tree(ids, mid, end);
  m_tree[index].left = left;
  m_tree[index].right = right;
  return index;
}

}  // namespace extremal
