#include "algorithms/distance/Penetration_depth.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <queue>
#include <sstream>
#include <utility>
#include <vector>

#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>
#include <Eigen/Dense>

#include "algorithms/pair/Feature.h"
#include "algorithms/pair/Pair_geometry.h"
#include "algorithms/distance/internal/Bezier_net.h"
#include "algorithms/distance/internal/Time_budget.h"
#include "kernel/Error.h"
#include "kernel/Shapes.h"

namespace extremal {

const char* to_string(Signed_distance_status s) {
  switch (s) {
    case Signed_distance_status::Converged: return "converged";
    case Signed_distance_status::Touching: return "touching";
    case Signed_distance_status::Penetrating: return "penetrating";
    case Signed_distance_status::Budget_exhausted: return "budget_exhausted";
    case Signed_distance_status::Resolution_limit: return "resolution_limit";
    case Signed_distance_status::Containment_unknown: return "containment_unknown";
  }
  return "?";
}

const char* to_string(Overlap_kind k) {
  switch (k) {
    case Overlap_kind::None: return "none";
    case Overlap_kind::Surfaces_meet: return "surfaces_meet";
    case Overlap_kind::A_inside_B: return "a_inside_b";
    case Overlap_kind::B_inside_A: return "b_inside_a";
  }
  return "?";
}


using internal::corner_params;
using internal::corner_pole;
using internal::Hom;

// ---- Hull signed distance: branch and bound over the direction sphere ----------------------

namespace {

// Points of the cube [-1, 1]^3 on face `face`, turned by a fixed generic rotation: CAD parts
// have kinks of overlap(n) (hull faces and edges) along coordinate planes, which would
// otherwise run along cell boundaries, where no cell straddles them and every bound stays one
// sided (first order).
Vec3 cube_point(int face, double u, double v) {
  static const Mat3 turn = Eigen::Quaterniond(0.8733, 0.3104, 0.2647, 0.2634).normalized().toRotationMatrix();
  Vec3 x;
  const int k = face / 2;
  x[k] = (face % 2) ? -1.0 : 1.0;
  x[(k + 1) % 3] = u;
  x[(k + 2) % 3] = v;
  return turn * x;
}

double angle_between(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// min over unit n within angle alpha of c of n.d.
double cone_min(const Vec3& d, const Vec3& c, double alpha) {
  const double dn = d.norm();
  if (!(dn > 0.0)) return 0.0;
  const double t = angle_between(c, d) + alpha;
  return t >= M_PI ? -dn : dn * std::cos(t);
}

// Every point y of conv(A - B) bounds overlap(n) = max over conv(A - B) of n.x from below,
// so over a cone the best bound from real differences d_i is the max over y in conv{d_i} of
// cone_min(y), a concave function of y (|y| cos(angle + alpha) = cos(alpha) c.y -
// sin(alpha) |y - c (c.y)|): Frank-Wolfe iterations with exact line searches. At a kink of
// overlap (a hull edge or face: the support point jumps) a convex combination of the support
// differences on both sides is parallel to the optimum, which keeps the bound second order.
double hull_cone_min(const Vec3* d, int count, const Vec3& c, double alpha, Vec3* arg = nullptr) {
  int start = 0;
  double best = -HUGE_VAL;
  for (int i = 0; i < count; ++i) {
    const double v = cone_min(d[i], c, alpha);
    if (v > best) {
      best = v;
      start = i;
    }
  }
  if (arg) *arg = d[start];
  if (count < 2) return best;
  Vec3 y = d[start];
  const double ca = std::cos(alpha), sa = std::sin(alpha);
  for (int it = 0; it < 24; ++it) {
    const Vec3 t = y - c * c.dot(y);
    const double tn = t.norm();
    const Vec3 g = ca * c - (tn > 0.0 ? Vec3(sa * t / tn) : Vec3::Zero());
    int vertex = 0;
    double top = -HUGE_VAL;
    for (int i = 0; i < count; ++i)
      if (g.dot(d[i]) > top) {
        top = g.dot(d[i]);
        vertex = i;
      }
    if (!(top > g.dot(y) + 1e-15 * (std::abs(top) + 1.0))) break;
    // Ternary search of the concave cone_min on the segment [y, d_vertex].
    double a = 0.0, b = 1.0;
    for (int k = 0; k < 40; ++k) {
      const double m1 = a + (b - a) / 3.0, m2 = b - (b - a) / 3.0;
      if (cone_min(y + m1 * (d[vertex] - y), c, alpha) < cone_min(y + m2 * (d[vertex] - y), c, alpha))
        a = m1;
      else
        b = m2;
    }
    const Vec3 next = y + 0.5 * (a + b) * (d[vertex] - y);
    const double v = cone_min(next, c, alpha);
    if (!(v > best)) break;
    best = v;
    y = next;
    if (arg) *arg = y;
  }
  return best;
}

struct Direction_cell {
  int face = 0;
  double u0 = -1, u1 = 1, v0 = -1, v1 = 1;
  Vec3 c = Vec3::UnitZ();
  double alpha = 0.0;
  double lower = -HUGE_VAL;
  Vec3 d = Vec3::Zero();
  bool has_d = false;
};
struct Lower_greater {
  bool operator()(const Direction_cell& a, const Direction_cell& b) const { return a.lower > b.lower; }
};

struct Direction_eval {
  Vec3 n = Vec3::UnitZ();
  Support_bound a, b;
  double upper() const { return a.upper + b.upper; }
  bool has_points() const { return a.element >= 0 && b.element >= 0; }
  Vec3 d() const { return a.point - b.point; }
};

// A point of face element e (placed by X_W) at the world point x, if the face passes through
// it: Newton's projection from `start`, accepted within `tol` and inside the trim.
bool face_point_at(const Distance_hierarchy& H, const Rigid_pose_3& X_W, int e, const Vec3& x,
                   const std::array<double, 2>& start, double tol, std::array<double, 2>& q) {
  const auto& el = H.elements()[e];
  if (el.kind != Element_kind::Face) return false;
  const Feature target = Feature::point(x);
  const Rigid_pose_3 identity;
  const Newton_result r = solve_pair_at_rest({&el.feature, &X_W, nullptr}, {&target, &identity, nullptr},
                                             Vec4(start[0], start[1], 0.0, 0.0));
  const double uv[2] = {r.params[0], r.params[1]};
  if (!H.on_body(e, uv)) return false;
  Feature_point fp;
  evaluate_feature(el.feature, X_W, uv, fp, 0);
  if (!((fp.p - x).norm() <= tol)) return false;
  q = {uv[0], uv[1]};
  return true;
}

bool lexicographic_less(const Vec3& a, const Vec3& b) {
  return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
}

// A face of a hull's plane that does not depend on how the hull triangulated it: CGAL's
// convex_hull_3 splits a face of several coplanar vertices (a box's hull of differences) in an
// order that follows memory addresses, which would make the search, and so the last digits of
// its bounds, differ from run to run. Of the hull's vertices in the plane of `face` (within
// rounding), sorted, the first triple whose triangle holds the plane's point nearest the origin
// replaces it; `normal` and `nearest` are taken from it. Faces of up to k_plane_vertices
// vertices only (beyond, the face stays as found).
void canonical_face(const CGAL::Surface_mesh<Point_3>& hull, const Vec3& centroid, Vec3& normal,
                    double& nearest, Vec3 face[3]) {
  constexpr int k_plane_vertices = 16;
  double size = 0.0;
  for (auto v : hull.vertices()) size = std::max(size, to_vec3(hull.point(v)).cwiseAbs().maxCoeff());
  const double eps = 1e-12 * std::max(size, 1e-300);
  std::vector<Vec3> on_plane;
  for (auto v : hull.vertices()) {
    const Vec3 x = to_vec3(hull.point(v));
    if (std::abs(normal.dot(x) - nearest) <= eps) on_plane.push_back(x);
  }
  if (on_plane.size() <= 3 || on_plane.size() > k_plane_vertices) return;
  std::sort(on_plane.begin(), on_plane.end(), lexicographic_less);
  const Vec3 target = nearest * normal;
  const int n = static_cast<int>(on_plane.size());
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      for (int k = j + 1; k < n; ++k) {
        const Vec3 &a = on_plane[static_cast<std::size_t>(i)], &b = on_plane[static_cast<std::size_t>(j)],
                   &c = on_plane[static_cast<std::size_t>(k)];
        Vec3 m = (b - a).cross(c - a);
        const double area2 = m.norm();
        if (!(area2 > eps * size)) continue;  // (nearly) collinear
        m /= area2;
        // Barycentric coordinates of the target in the triangle, by signed sub-areas.
        const double wa = m.dot((b - target).cross(c - target)) / area2;
        const double wb = m.dot((c - target).cross(a - target)) / area2;
        const double wc = 1.0 - wa - wb;
        const double slack = -1e-12;
        if (wa < slack || wb < slack || wc < slack) continue;
        if (m.dot(a - centroid) < 0.0) m = -m;
        normal = m;
        nearest = m.dot(a);
        face[0] = a;
        face[1] = b;
        face[2] = c;
        return;
      }
}

// The witnesses of a direction's depth (out.distance set): the support points of A along e.n
// and of B against it, their elements and parameters, the normal e.n.
void set_witnesses(const Distance_hierarchy& HA, const Rigid_pose_3& X_WA,
                   const Distance_hierarchy& HB, const Rigid_pose_3& X_WB,
                   const Direction_eval& e, Signed_distance_result& out) {
  out.point_a = e.a.point;
  out.point_b = e.b.point;
  out.normal = e.n;
  auto fill = [](const Distance_hierarchy& H, const Support_bound& s, Element_kind& kind, int& element,
                 int& face, std::array<double, 2>& params) {
    const auto& el = H.elements()[s.element];
    kind = el.kind;
    element = el.kind == Element_kind::Point ? 0 : el.index;
    face = el.kind == Element_kind::Face ? el.index : -1;
    params = s.params;
  };
  fill(HA, e.a, out.kind_a, out.element_a, out.face_a, out.params_a);
  fill(HB, e.b, out.kind_b, out.element_b, out.face_b, out.params_b);
  // A flat support face (a plane along n) attains h at every point: the pair found may be a
  // corner of one face and a point of the other, with point_b - point_a far from s n. Where
  // the support face passes through the other witness moved by -s along n, that point is
  // the witness: the pair is then aligned with the normal (a contact point and its depth).
  const double scale = std::max({1.0, out.point_a.norm(), out.point_b.norm()});
  const double tol = 1e-9 * scale;
  const Vec3 gap = out.point_b - out.point_a - out.distance * out.normal;
  if (gap.norm() > tol) {
    std::array<double, 2> q;
    const Vec3 on_a = out.point_b - out.distance * out.normal;
    const Vec3 on_b = out.point_a + out.distance * out.normal;
    if (face_point_at(HA, X_WA, e.a.element, on_a, out.params_a, tol, q)) {
      out.point_a = on_a;
      out.params_a = q;
    } else if (face_point_at(HB, X_WB, e.b.element, on_b, out.params_b, tol, q)) {
      out.point_b = on_b;
      out.params_b = q;
    }
  }
}

}  // namespace

Signed_distance_result hull_signed_distance(const Distance_hierarchy& HA, const Rigid_pose_3& X_WA,
                                            const Distance_hierarchy& HB, const Rigid_pose_3& X_WB,
                                            const Signed_distance_request& request) {
  EXTREMAL_PRECONDITION(request.absolute_tolerance > 0.0 && request.relative_tolerance >= 0.0);
  EXTREMAL_PRECONDITION(request.max_cells > 0 && request.max_seconds >= 0.0);
  const auto start = std::chrono::steady_clock::now();
  Signed_distance_result out;
  const double scale = HA.tree().front().radius + HB.tree().front().radius +
                       X_WA.apply_point(HA.tree().front().centre).norm() +
                       X_WB.apply_point(HB.tree().front().centre).norm();
  const double abs_tol = std::max(request.absolute_tolerance, 4e-15 * scale);
  Support_request sreq;
  sreq.tolerance = std::max(0.2 * abs_tol, 1e-15 * scale);

  auto evaluate = [&](const Vec3& n) {
    Direction_eval e;
    e.n = n;
    e.a = support_bound(HA, X_WA, n, sreq);
    e.b = support_bound(HB, X_WB, -n, sreq);
    out.supports += 2;
    return e;
  };

  Direction_eval best;
  double U = HUGE_VAL;
  // Real differences near the best direction (a ring of the latest), for the hull bounds.
  constexpr int k_ring = 8;
  Vec3 ring[k_ring];
  int ring_count = 0, ring_next = 0;
  auto remember = [&](const Direction_eval& e) {
    if (!e.has_points()) return;
    ring[ring_next] = e.d();
    ring_next = (ring_next + 1) % k_ring;
    ring_count = std::min(ring_count + 1, k_ring);
  };
  double best_upper = HUGE_VAL;  // of `best`; U also counts directions with no real point
  auto consider = [&](const Direction_eval& e) {
    U = std::min(U, e.upper());
    if (e.has_points() && e.upper() < best_upper) {
      best_upper = e.upper();
      best = e;
      remember(e);
    }
  };
  // The vertices of the expanding polytope's last face (see below), kept apart from the ring.
  constexpr int k_anchors = 11;
  Vec3 anchors[k_anchors];
  int anchor_count = 0;
  // Lower bound over a cone from the ring and anchors plus up to two more differences.
  auto cone_bound = [&](const Vec3& c, double alpha, const Vec3* extra, int extra_count) {
    Vec3 d[k_ring + k_anchors + 5];
    int n = 0;
    for (int i = 0; i < ring_count; ++i) d[n++] = ring[i];
    for (int i = 0; i < anchor_count; ++i) d[n++] = anchors[i];
    for (int i = 0; i < extra_count; ++i) d[n++] = extra[i];
    return n > 0 ? hull_cone_min(d, n, c, alpha) : -HUGE_VAL;
  };
  std::vector<Vec3> samples;  // support differences of the initial cells (real points of A - B)
  auto make_cell = [&](int face, double u0, double u1, double v0, double v1, const Direction_cell* parent) {
    Direction_cell c;
    c.face = face;
    c.u0 = u0;
    c.u1 = u1;
    c.v0 = v0;
    c.v1 = v1;
    c.c = cube_point(face, 0.5 * (u0 + u1), 0.5 * (v0 + v1)).normalized();
    double alpha = 0.0;
    for (int k = 0; k < 4; ++k)
      alpha = std::max(alpha, angle_between(c.c, cube_point(face, (k & 1) ? u1 : u0, (k & 2) ? v1 : v0)));
    c.alpha = alpha * (1.0 + 1e-12) + 1e-15;
    const Direction_eval e = evaluate(c.c);
    ++out.cells;
    consider(e);
    c.lower = parent ? parent->lower : -HUGE_VAL;
    Vec3 extra[2];
    int extra_count = 0;
    if (e.has_points()) {
      c.d = e.d();
      c.has_d = true;
      extra[extra_count++] = c.d;
      if (!parent) samples.push_back(c.d);
    }
    if (parent && parent->has_d) extra[extra_count++] = parent->d;
    c.lower = std::max(c.lower, cone_bound(c.c, c.alpha, extra, extra_count));
    return c;
  };

  std::priority_queue<Direction_cell, std::vector<Direction_cell>, Lower_greater> heap;
  std::vector<Direction_cell> initial;
  const int split0 = 4;
  for (int f = 0; f < 6; ++f)
    for (int i = 0; i < split0; ++i)
      for (int j = 0; j < split0; ++j) {
        const double u0 = -1.0 + 2.0 * i / split0, u1 = -1.0 + 2.0 * (i + 1) / split0;
        const double v0 = -1.0 + 2.0 * j / split0, v1 = -1.0 + 2.0 * (j + 1) / split0;
        initial.push_back(make_cell(f, u0, u1, v0, v1, nullptr));
      }

  // Newton polish of the best direction on the sphere: the gradient of overlap is the
  // tangential part of p - q; its Hessian by differences of gradients.
  if (best.has_points()) {
    Direction_eval cur = best;
    for (int it = 0; it < 12; ++it) {
      const Vec3 n = cur.n;
      const Vec3 e1 = n.unitOrthogonal(), e2 = n.cross(e1);
      auto gradient = [&](const Direction_eval& e, const Vec3& v) {
        const double len = v.norm();
        const Vec3 m = v / len;
        const Vec3 dn1 = (e1 - m * m.dot(e1)) / len, dn2 = (e2 - m * m.dot(e2)) / len;
        return Eigen::Vector2d(e.d().dot(dn1), e.d().dot(dn2));
      };
      const Eigen::Vector2d g0 = gradient(cur, n);
      const double delta = 1e-6;
      Eigen::Matrix2d Hm;
      bool ok = true;
      for (int j = 0; j < 2; ++j) {
        const Vec3 v = n + delta * (j == 0 ? e1 : e2);
        const Direction_eval ej = evaluate(v.normalized());
        if (!ej.has_points()) {
          ok = false;
          break;
        }
        Hm.col(j) = (gradient(ej, v) - g0) / delta;
      }
      if (!ok) break;
      Hm = 0.5 * (Hm + Hm.transpose()).eval();
      const Eigen::LLT<Eigen::Matrix2d> llt(Hm);
      if (llt.info() != Eigen::Success) break;
      Eigen::Vector2d step = -llt.solve(g0);
      if (!step.allFinite()) break;
      if (step.norm() > 0.3) step *= 0.3 / step.norm();
      const Direction_eval next = evaluate((n + step[0] * e1 + step[1] * e2).normalized());
      if (!next.has_points() || !(next.upper() < cur.upper())) break;
      cur = next;
      consider(cur);
      if (step.norm() < 1e-12) break;
    }
  }
  // Expanding polytope (as EPA): P = conv(samples) lies in K = conv(A - B), whose support
  // function is overlap. When the origin is inside P, the face of P nearest to it gives a
  // direction n_f; the support of K along n_f either lies on that face (n_f is optimal to the
  // tolerance) or is a new vertex. This finds the optimum at kinks of overlap (hull edges and
  // faces, continua of support points) where Newton's method does not apply; its last face's
  // vertices span a difference parallel to the optimum, which the cone bounds then use.
  if (best.has_points() && samples.size() >= 4) {
    std::vector<Point_3> pts;
    for (const Vec3& d : samples) pts.emplace_back(d.x(), d.y(), d.z());
    for (int i = 0; i < ring_count; ++i) pts.emplace_back(ring[i].x(), ring[i].y(), ring[i].z());
    Vec3 last_face[3] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
    bool have_face = false;
    int stalled = 0;  // iterations without a better upper bound (a continuum of optima)
    for (int it = 0; it < 100 && stalled < 25; ++it) {
      CGAL::Surface_mesh<Point_3> hull;
      CGAL::convex_hull_3(pts.begin(), pts.end(), hull);
      if (hull.number_of_faces() < 4) break;
      Vec3 centroid = Vec3::Zero();
      for (auto v : hull.vertices()) centroid += to_vec3(hull.point(v));
      centroid /= static_cast<double>(hull.number_of_vertices());
      double nearest = HUGE_VAL;
      Vec3 normal = Vec3::Zero(), face[3] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
      for (auto f : hull.faces()) {
        Vec3 x[3];
        int k = 0;
        for (auto v : CGAL::vertices_around_face(hull.halfedge(f), hull))
          if (k < 3) x[k++] = to_vec3(hull.point(v));
        // In sorted order: the face's normal then has the same rounding whichever vertex the
        // hull's halfedge starts at (see canonical_face).
        std::sort(x, x + 3, lexicographic_less);
        Vec3 m = (x[1] - x[0]).cross(x[2] - x[0]);
        if (!(m.norm() > 0.0)) continue;
        m.normalize();
        if (m.dot(x[0] - centroid) < 0.0) m = -m;
        const double offset = m.dot(x[0]);
        if (offset < nearest) {
          nearest = offset;
          normal = m;
          face[0] = x[0];
          face[1] = x[1];
          face[2] = x[2];
        }
      }
      if (!(nearest > 0.0) || !(normal.norm() > 0.0)) break;  // origin not inside P
      canonical_face(hull, centroid, normal, nearest, face);
      for (int k = 0; k < 3; ++k) last_face[k] = face[k];
      have_face = true;
      const Direction_eval at = evaluate(normal);
      const double before = U;
      consider(at);
      stalled = U < before ? 0 : stalled + 1;
      if (!at.has_points()) break;
      if (normal.dot(at.d()) - nearest <= 0.25 * abs_tol) break;
      pts.emplace_back(at.d().x(), at.d().y(), at.d().z());
    }
    if (have_face)
      for (const Vec3& x : last_face) anchors[anchor_count++] = x;
  }
  // Visits the directions a small step from n along both senses of two orthogonal tangents
  // (n by value: visiting may move `best`, whose direction is often the argument).
  auto around = [&](const Vec3 n, double step, auto&& visit) {
    const Vec3 e1 = n.unitOrthogonal(), e2 = n.cross(e1);
    for (const Vec3& t : {e1, Vec3(-e1), e2, Vec3(-e2)})
      visit(evaluate((n + step * t).normalized()));
  };
  auto consider_and_remember = [&](const Direction_eval& side) {
    consider(side);
    remember(side);
  };
  // Differences on every side of the best direction: where overlap has a kink there, the
  // support points on either side span the optimum.
  if (best.has_points()) {
    const Vec3 n = best.n;  // the same direction for both steps, as consider() may move best
    for (double step : {1e-5, 1e-3}) around(n, step, consider_and_remember);
  }
  // Then along the hull: the point y of conv(differences) best aligned with the best direction
  // (the largest bound over a small cone about it) points at the optimum of overlap, also at a
  // kink, where Newton does not apply.
  for (int it = 0; it < 12 && best.has_points(); ++it) {
    Vec3 d[k_ring];
    for (int i = 0; i < ring_count; ++i) d[i] = ring[i];
    Vec3 y;
    hull_cone_min(d, ring_count, best.n, 1e-3, &y);
    if (!(y.norm() > 0.0)) break;
    const Vec3 n = y.normalized();
    if ((n - best.n).norm() < 1e-14) break;
    const double before = U;
    consider_and_remember(evaluate(n));
    around(n, 1e-6, consider_and_remember);
    if (!(U < before)) break;
  }
  // Anchors: differences on both sides of the final best direction in two orthogonal
  // directions (a kink there is spanned by them), kept for every cell's bound.
  if (best.has_points()) {
    const Vec3 n = best.n;  // the same direction for both steps, as consider() may move best
    for (double step : {1e-6, 1e-4})
      around(n, step, [&](const Direction_eval& side) {
        consider(side);
        if (side.has_points() && anchor_count < k_anchors) anchors[anchor_count++] = side.d();
      });
  }
  for (Direction_cell& c : initial) {
    const Vec3 own[1] = {c.d};
    c.lower = std::max(c.lower, cone_bound(c.c, c.alpha, own, c.has_d ? 1 : 0));
    if (c.lower <= U) heap.push(c);
  }

  Signed_distance_status status = Signed_distance_status::Penetrating;
  double tol = abs_tol;
  while (!heap.empty()) {
    Direction_cell top = heap.top();
    tol = std::max(abs_tol, request.relative_tolerance * std::abs(U));
    if (U - top.lower <= tol) break;
    // Tighten lazily with the best pair found since the cell was made.
    const Vec3 own[1] = {top.d};
    const double tightened = cone_bound(top.c, top.alpha, own, top.has_d ? 1 : 0);
    if (tightened > top.lower) {
      heap.pop();
      top.lower = tightened;
      if (top.lower <= U) heap.push(top);
      continue;
    }
    if (out.cells >= request.max_cells) {
      status = Signed_distance_status::Budget_exhausted;
      break;
    }
    if (request.max_seconds > 0.0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >
            request.max_seconds) {
      status = Signed_distance_status::Budget_exhausted;
      break;
    }
    if (top.alpha < 1e-13) {
      status = Signed_distance_status::Resolution_limit;
      break;
    }
    heap.pop();
    const double um = 0.5 * (top.u0 + top.u1), vm = 0.5 * (top.v0 + top.v1);
    Direction_cell children[4] = {make_cell(top.face, top.u0, um, top.v0, vm, &top),
                                  make_cell(top.face, um, top.u1, top.v0, vm, &top),
                                  make_cell(top.face, top.u0, um, vm, top.v1, &top),
                                  make_cell(top.face, um, top.u1, vm, top.v1, &top)};
    // Siblings' differences too: where a kink of overlap crosses the parent, siblings on
    // either side of it span the differences in between.
    Vec3 family[5];
    int family_count = 0;
    for (const Direction_cell& c : children)
      if (c.has_d) family[family_count++] = c.d;
    if (top.has_d) family[family_count++] = top.d;
    for (Direction_cell& c : children) {
      c.lower = std::max(c.lower, cone_bound(c.c, c.alpha, family, family_count));
      if (c.lower <= U) heap.push(c);
    }
  }
  const double L = heap.empty() ? U : std::min(U, heap.top().lower);
  out.status = status;
  out.lower_bound = -U;
  out.upper_bound = -L;
  out.tolerance_used = tol;
  if (best.has_points()) {
    out.distance = std::clamp(-(best.a.lower + best.b.lower), out.lower_bound, out.upper_bound);
    set_witnesses(HA, X_WA, HB, X_WB, best, out);
  } else {
    // No real point on a body (every sampled support outside the trims): only the upper
    // bounds on h hold, so s has a lower bound and no upper bound.
    out.distance = out.lower_bound;
    out.upper_bound = HUGE_VAL;
    out.status = Signed_distance_status::Budget_exhausted;
  }
  return out;
}

// ---- Signed distance -----------------------------------------------------------------------

namespace {

// One real point of each face (up to 32 spread over the body), curve and point element, world.
std::vector<Vec3> sample_points(const Distance_hierarchy& H, const Rigid_pose_3& X_W) {
  std::vector<Vec3> out;
  const auto& elements = H.elements();
  const int n = static_cast<int>(elements.size());
  const int stride = std::max(1, n / 32);
  for (int e = 0; e < n; e += stride) {
    const auto& el = elements[e];
    bool found = false;
    for (int p = el.first_piece; p < el.first_piece + el.piece_count && !found; ++p) {
      const auto& pc = H.pieces()[p];
      const int corners = pc.dimension == 2 ? 4 : pc.dimension == 1 ? 2 : 1;
      for (int k = 0; k < corners && !found; ++k) {
        double q[2];
        corner_params(pc.lo, pc.hi, k, q);
        if (pc.dimension < 2) q[1] = 0.0;
        if (!H.on_body(pc.element, q)) continue;
        const Hom& P = H.poles()[pc.offset + corner_pole(pc.nu, pc.nv, k)];
        out.push_back(X_W.apply_point(P.head<3>() / P[3]));
        found = true;
      }
    }
  }
  return out;
}

// A body with no side to be inside of, whatever it meets: a point, or a body without faces
// that is not closed (curves only, an open mesh).
bool sideless(const Body& body, bool closed) {
  return body.is_point || (!closed && body.faces.empty());
}

// The parameters on the ball's face (its only element, of H) of its world point x: Newton's
// projection from the nearest of a grid of samples. False if it does not converge there.
bool ball_params(const Distance_hierarchy& H, const Rigid_pose_3& X_W, const Vec3& x,
                 std::array<double, 2>& q) {
  constexpr int k_grid = 8;
  const Feature& f = H.elements().front().feature;
  std::array<double, 2> start{{f.lower(0), f.lower(1)}};
  double least = HUGE_VAL;
  for (int i = 0; i <= k_grid; ++i)
    for (int j = 0; j <= k_grid; ++j) {
      const double uv[2] = {f.lower(0) + (f.upper(0) - f.lower(0)) * i / k_grid,
                            f.lower(1) + (f.upper(1) - f.lower(1)) * j / k_grid};
      Feature_point fp;
      evaluate_feature(f, X_W, uv, fp, 0);
      const double d = (fp.p - x).squaredNorm();
      if (d < least) least = d, start = {uv[0], uv[1]};
    }
  return face_point_at(H, X_W, 0, x, start, 1e-9 * std::max(1.0, x.norm()), q);
}

Signed_distance_status from_distance_status(Distance_status s) {
  switch (s) {
    case Distance_status::Budget_exhausted: return Signed_distance_status::Budget_exhausted;
    case Distance_status::Resolution_limit: return Signed_distance_status::Resolution_limit;
    case Distance_status::Touching: return Signed_distance_status::Touching;
    default: return Signed_distance_status::Converged;
  }
}

}  // namespace

Overlap_test overlap_of(const Distance_result& apart, const Distance_hierarchy& HA,
                        const Rigid_pose_3& X_WA, bool closed_a, const Distance_hierarchy& HB,
                        const Rigid_pose_3& X_WB, bool closed_b) {
  Overlap_test out;
  if (apart.status == Distance_status::Intersecting || apart.status == Distance_status::Touching) {
    out.kind = Overlap_kind::Surfaces_meet;
    return out;
  }
  if (!(apart.lower_bound > 0.0)) return out;
  auto inside = [&](const Distance_hierarchy& inner, const Rigid_pose_3& X_in,
                    const Distance_hierarchy& outer, const Rigid_pose_3& X_out) {
    const Bbox_3 box = transformed(outer.box(), X_out);  // holds the outer body
    for (const Vec3& x : sample_points(inner, X_in)) {
      if (!CGAL::do_overlap(to_point(x).bbox(), box)) continue;  // outside: winding number 0
      const Winding_number w = winding_number(outer, X_out, x, apart.lower_bound);
      out.winding_cells += w.cells;
      if (!w.determined) out.unknown = true;
      if (w.inside()) return true;
    }
    return false;
  };
  if (closed_b && inside(HA, X_WA, HB, X_WB)) out.kind = Overlap_kind::A_inside_B;
  else if (closed_a && inside(HB, X_WB, HA, X_WA)) out.kind = Overlap_kind::B_inside_A;
  return out;
}

Signed_distance_result directional_signed_distance(const Distance_hierarchy& HA,
                                                   const Rigid_pose_3& X_WA,
                                                   const Distance_hierarchy& HB,
                                                   const Rigid_pose_3& X_WB, const Vec3& n_W,
                                                   const Signed_distance_request& request) {
  EXTREMAL_PRECONDITION(request.absolute_tolerance > 0.0 && request.relative_tolerance >= 0.0);
  EXTREMAL_PRECONDITION(n_W.allFinite() && n_W.norm() > 0.0);
  const double scale = HA.tree().front().radius + HB.tree().front().radius +
                       X_WA.apply_point(HA.tree().front().centre).norm() +
                       X_WB.apply_point(HB.tree().front().centre).norm();
  Support_request sreq;
  sreq.tolerance = std::max(0.5 * std::max(request.absolute_tolerance,
                                           request.relative_tolerance * scale),
                            1e-15 * scale);
  Direction_eval e;
  e.n = n_W.normalized();
  e.a = support_bound(HA, X_WA, e.n, sreq);
  e.b = support_bound(HB, X_WB, -e.n, sreq);
  Signed_distance_result out;
  out.supports = 2;
  out.tolerance_used = 2.0 * sreq.tolerance;
  out.lower_bound = -e.upper();
  out.normal = e.n;
  if (!e.has_points()) {
    out.distance = out.lower_bound;
    out.upper_bound = HUGE_VAL;
    out.status = Signed_distance_status::Budget_exhausted;
    return out;
  }
  out.upper_bound = -(e.a.lower + e.b.lower);
  out.distance = out.upper_bound;
  out.status = e.a.converged && e.b.converged ? Signed_distance_status::Penetrating
                                              : Signed_distance_status::Budget_exhausted;
  set_witnesses(HA, X_WA, HB, X_WB, e, out);
  return out;
}

bool inside_body(const Distance_hierarchy& H, const Rigid_pose_3& X_W, const Vec3& x_W,
                 double surface_tolerance, bool* on_surface) {
  // The clearance the winding number needs: the certified distance from x to the surface.
  static const Body point = make_point_body();
  static const Distance_hierarchy HP(point);
  Distance_request request;
  request.absolute_tolerance = 1e-9;
  request.relative_tolerance = 1e-3;
  request.max_nodes = 20000;
  const Distance_result r =
      extremal_distance(HP, Rigid_pose_3(Mat3::Identity(), x_W), H, X_W, request);
  const bool on = r.is_certified() && r.upper_bound <= surface_tolerance;
  if (on_surface != nullptr) *on_surface = on;
  if (on || !(r.lower_bound > 0.0)) return false;
  return winding_number(H, X_W, x_W, r.lower_bound).inside();
}

double signed_box_bound(const Bbox_3& a, const Bbox_3& b) {
  const double apart = box_distance(a, b);
  if (apart > 0.0) return apart;
  double overlap = HUGE_VAL;
  for (int k = 0; k < 3; ++k)
    overlap = std::min({overlap, a.max(k) - b.min(k), b.max(k) - a.min(k)});
  return -overlap;
}

Signed_distance_result signed_distance(const Body& A, const Distance_hierarchy& HA,
                                       const Rigid_pose_3& X_WA, const Body& B,
                                       const Distance_hierarchy& HB, const Rigid_pose_3& X_WB,
                                       const Signed_distance_request& request) {
  EXTREMAL_PRECONDITION(request.absolute_tolerance > 0.0 && request.relative_tolerance >= 0.0);
  EXTREMAL_PRECONDITION(request.max_cells > 0 && request.max_seconds >= 0.0 &&
                        request.total_seconds >= 0.0);
  const internal::Time_budget budget(request.total_seconds);
  Distance_request dreq = request.apart;
  dreq.absolute_tolerance = request.absolute_tolerance;
  dreq.relative_tolerance = request.relative_tolerance;
  dreq.max_seconds = budget.limit_for(request.apart.max_seconds);
  const Distance_result r = extremal_distance(HA, X_WA, HB, X_WB, dreq);
  const Closedness closed_a = body_closedness(A), closed_b = body_closedness(B);
  const Overlap_test test = overlap_of(r, HA, X_WA, closed_a.closed, HB, X_WB, closed_b.closed);
  const Overlap_kind overlap = test.kind;
  const bool unknown = test.unknown;
  const long winding_cells = test.winding_cells;

  // A ball against a closed body it overlaps (one not certified convex, where the hulls'
  // depth is already the translation distance).
  std::optional<Ball> ball_a, ball_b;
  if (overlap != Overlap_kind::None) {
    if (closed_b.closed && !is_certified_convex(B)) ball_a = certified_ball(A);
    if (!ball_a && closed_a.closed && !is_certified_convex(A)) ball_b = certified_ball(B);
  }

  Signed_distance_result out;
  if (overlap == Overlap_kind::Surfaces_meet &&
      (sideless(A, closed_a.closed) || sideless(B, closed_b.closed)) &&
      (A.is_point || B.is_point || (!closed_a.closed && !closed_b.closed))) {
    // No inside to be deep in (a point on a surface; a curve, a point or an open mesh meeting a
    // body that is not closed): the distance, 0 where they meet, unsigned. Test
    // Overlap.ACurveThroughASheetIsUnsignedAndZeroWhileItPiercesIt.
    out.status = r.is_certified() ? Signed_distance_status::Touching : from_distance_status(r.status);
    out.distance = r.distance;
    out.lower_bound = r.lower_bound;
    out.upper_bound = r.upper_bound;
    out.point_a = r.point_a;
    out.point_b = r.point_b;
    out.normal = r.normal;
    out.kind_a = r.kind_a;
    out.kind_b = r.kind_b;
    out.element_a = r.element_a;
    out.element_b = r.element_b;
    out.face_a = r.face_a;
    out.face_b = r.face_b;
    out.params_a = r.params_a;
    out.params_b = r.params_b;
    out.tolerance_used = r.tolerance_used;
  } else if (ball_a || ball_b) {
    // A ball is as deep as its centre's signed distance less its radius (Minkowski): the
    // centre's signed distance as a point's, the ball's witness moved from the centre along
    // the normal by the radius. Test Overlap.ABallInAClosedMeshReadsItsCentresSignedDistanceLessItsRadius.
    static const Body centre = make_point_body("centre");
    static const Distance_hierarchy HC(centre);
    const bool on_a = ball_a.has_value();
    const Ball& ball = on_a ? *ball_a : *ball_b;
    const Vec3 c = (on_a ? X_WA : X_WB).apply_point(ball.centre);
    const Rigid_pose_3 X_WC(Mat3::Identity(), c);
    Signed_distance_request centre_request = request;
    centre_request.total_seconds = budget.limit_for(request.total_seconds);
    out = on_a ? signed_distance(centre, HC, X_WC, B, HB, X_WB, centre_request)
               : signed_distance(A, HA, X_WA, centre, HC, X_WC, centre_request);
    out.distance -= ball.radius;
    out.lower_bound -= ball.radius;
    out.upper_bound -= ball.radius;
    // point_b - point_a = distance * normal, with the normal from A to B.
    const Vec3 witness = on_a ? Vec3(c + ball.radius * out.normal) : Vec3(c - ball.radius * out.normal);
    const Distance_hierarchy& H = on_a ? HA : HB;
    const Rigid_pose_3& X_W = on_a ? X_WA : X_WB;
    std::array<double, 2> q{{0.0, 0.0}};
    if (!ball_params(H, X_W, witness, q)) q = {0.0, 0.0};
    (on_a ? out.point_a : out.point_b) = witness;
    (on_a ? out.kind_a : out.kind_b) = Element_kind::Face;
    (on_a ? out.element_a : out.element_b) = 0;
    (on_a ? out.face_a : out.face_b) = 0;
    (on_a ? out.params_a : out.params_b) = q;
    if (out.is_certified())
      out.status = out.lower_bound >= -out.tolerance_used ? Signed_distance_status::Touching
                                                          : Signed_distance_status::Penetrating;
    out.depth_is_translation_distance = false;
  } else if (overlap == Overlap_kind::None) {
    out.status = from_distance_status(r.status);
    if (unknown && out.status == Signed_distance_status::Converged)
      out.status = Signed_distance_status::Containment_unknown;
    out.distance = r.distance;
    out.lower_bound = r.lower_bound;
    out.upper_bound = r.upper_bound;
    out.point_a = r.point_a;
    out.point_b = r.point_b;
    out.normal = r.normal;
    out.kind_a = r.kind_a;
    out.kind_b = r.kind_b;
    out.element_a = r.element_a;
    out.element_b = r.element_b;
    out.face_a = r.face_a;
    out.face_b = r.face_b;
    out.params_a = r.params_a;
    out.params_b = r.params_b;
    out.tolerance_used = r.tolerance_used;
    // Containment undecided, or an apart query that stopped before it showed the surfaces
    // apart: the bodies may overlap, and only their boxes bound s from below.
    if (unknown || (!out.is_certified() && !(r.lower_bound > 0.0)))
      out.lower_bound = std::min(out.lower_bound, signed_box_bound(transformed(HA.box(), X_WA),
                                                                   transformed(HB.box(), X_WB)));
  } else if ((overlap == Overlap_kind::A_inside_B && A.is_point) ||
             (overlap == Overlap_kind::B_inside_A && B.is_point)) {
    // A point inside a closed body is as deep as its distance to the surface, the translation
    // that takes it out: minus the certified distance, with its bounds (not the hull's depth,
    // deeper in a non-convex body). Test PenetrationDepth.PointInsideANonConvexPartIsItsDistanceToTheSurface.
    out.status = r.is_certified() ? Signed_distance_status::Penetrating : from_distance_status(r.status);
    out.distance = -r.distance;
    out.lower_bound = -r.upper_bound;
    out.upper_bound = -r.lower_bound;
    out.point_a = r.point_a;
    out.point_b = r.point_b;
    out.normal = -r.normal;  // (point_b - point_a = distance * normal)
    out.kind_a = r.kind_a;
    out.kind_b = r.kind_b;
    out.element_a = r.element_a;
    out.element_b = r.element_b;
    out.face_a = r.face_a;
    out.face_b = r.face_b;
    out.params_a = r.params_a;
    out.params_b = r.params_b;
    out.tolerance_used = r.tolerance_used;
    out.depth_is_translation_distance = true;
  } else {
    Signed_distance_request depth = request;
    depth.max_seconds = budget.limit_for(request.max_seconds);
    out = hull_signed_distance(HA, X_WA, HB, X_WB, depth);
    out.depth_is_translation_distance = is_certified_convex(A) && is_certified_convex(B);
    if (overlap == Overlap_kind::Surfaces_meet && r.status == Distance_status::Touching &&
        out.status == Signed_distance_status::Penetrating && out.lower_bound >= -out.tolerance_used)
      out.status = Signed_distance_status::Touching;
  }
  out.overlap = overlap;
  out.closed_a = closed_a;
  out.closed_b = closed_b;
  out.apart = r;
  out.winding_cells = winding_cells;
  return out;
}

Signed_distance_result signed_distance(const Body& A, const Rigid_pose_3& X_WA, const Body& B,
                                       const Rigid_pose_3& X_WB, const Signed_distance_request& request) {
  const Distance_hierarchy HA(A), HB(B);
  return signed_distance(A, HA, X_WA, B, HB, X_WB, request);
}

}  // namespace extremal
