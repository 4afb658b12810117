#include "kernel/Body.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace extremal {

namespace {

void add(Bbox_3& box, const Vec3& p) { box += Bbox_3(p.x(), p.y(), p.z(), p.x(), p.y(), p.z()); }

// Box of a curve: samples on every knot span, then Newton steps on (C'.e) = 0 from the best
// sample of each of the six directions.
void add_curve(Bbox_3& box, const Nurbs_curve_3& c) {
  const auto& k = c.knots();
  const double lo = c.domain_min(), hi = c.domain_max();
  std::vector<double> ts;
  double prev = lo;
  for (std::size_t i = 0; i < k.size(); ++i) {
    if (k[i] <= prev || k[i] > hi) continue;
    for (int s = 0; s < 12; ++s) ts.push_back(std::min(prev + (k[i] - prev) * s / 12.0, hi));
    prev = k[i];
  }
  ts.push_back(hi);
  Curve_point cp;
  double best_t[6], best_val[6];
  std::fill(best_val, best_val + 6, -std::numeric_limits<double>::infinity());
  for (double t : ts) {
    c.evaluate(t, cp, 0);
    add(box, cp.p);
    for (int d = 0; d < 6; ++d) {
      const double val = (d < 3 ? 1.0 : -1.0) * cp.p[d % 3];
      if (val > best_val[d]) best_val[d] = val, best_t[d] = t;
    }
  }
  for (int d = 0; d < 6; ++d) {
    const double sgn = d < 3 ? 1.0 : -1.0;
    double t = best_t[d];
    for (int it = 0; it < 12; ++it) {
      c.evaluate(t, cp, 2);
      const double g = sgn * cp.d1[d % 3], h = sgn * cp.d2[d % 3];
      if (!(h < 0.0)) break;
      const double tn = std::clamp(t - g / h, lo, hi);
      if (tn == t) break;
      Curve_point q;
      c.evaluate(tn, q, 0);
      if (sgn * q.p[d % 3] < best_val[d]) break;
      best_val[d] = sgn * q.p[d % 3];
      add(box, q.p);
      t = tn;
    }
  }
}

void add_face(Bbox_3& box, const Face& f, const std::vector<Edge>& edges) {
  const Nurbs_surface_3& s = f.surface;
  // Boundary: the trim curves mapped on the patch (the face's own geometry; a file's 3D edge
  // curves may stray from it by the edge tolerance).
  (void)edges;
  for (const auto& loop : f.trims)
    for (const auto& tc : loop.curves) {
      const Nurbs_curve_3& c = tc.uv;
      Surface_point sp;
      for (int i = 0; i <= 64; ++i) {
        const double t =
            std::min(c.domain_min() + (c.domain_max() - c.domain_min()) * i / 64.0, c.domain_max());
        const Point_3 uv = c.point(t);
        s.evaluate(std::clamp(uv.x(), s.u_min(), s.u_max()),
                   std::clamp(uv.y(), s.v_min(), s.v_max()), sp, 0);
        add(box, sp.p);
      }
    }
  // Interior: a grid inside the trim, then Newton on the gradient of each coordinate.
  const int nu = std::clamp(4 * (s.number_of_poles_u() - s.degree_u() + 1), 16, 64);
  const int nv = std::clamp(4 * (s.number_of_poles_v() - s.degree_v() + 1), 16, 64);
  double best_val[6], best_u[6], best_v[6];
  std::fill(best_val, best_val + 6, -std::numeric_limits<double>::infinity());
  Surface_point sp;
  for (int i = 0; i <= nu; ++i) {
    const double u = std::min(s.u_min() + (s.u_max() - s.u_min()) * i / nu, s.u_max());
    for (int j = 0; j <= nv; ++j) {
      const double v = std::min(s.v_min() + (s.v_max() - s.v_min()) * j / nv, s.v_max());
      if (!f.contains(u, v)) continue;
      s.evaluate(u, v, sp, 0);
      add(box, sp.p);
      for (int d = 0; d < 6; ++d) {
        const double val = (d < 3 ? 1.0 : -1.0) * sp.p[d % 3];
        if (val > best_val[d]) best_val[d] = val, best_u[d] = u, best_v[d] = v;
      }
    }
  }
  for (int d = 0; d < 6; ++d) {
    if (!std::isfinite(best_val[d])) continue;
    const double sgn = d < 3 ? 1.0 : -1.0;
    const int a = d % 3;
    double u = best_u[d], v = best_v[d];
    for (int it = 0; it < 12; ++it) {
      s.evaluate(u, v, sp, 2);
      const double gu = sgn * sp.du[a], gv = sgn * sp.dv[a];
      const double huu = sgn * sp.duu[a], huv = sgn * sp.duv[a], hvv = sgn * sp.dvv[a];
      const double det = huu * hvv - huv * huv;
      double su, sv;
      if (huu < 0.0 && det > 0.0) {  // negative definite: Newton step to the maximum
        su = -(hvv * gu - huv * gv) / det;
        sv = -(huu * gv - huv * gu) / det;
      } else {
        break;
      }
      const double un = std::clamp(u + su, s.u_min(), s.u_max());
      const double vn = std::clamp(v + sv, s.v_min(), s.v_max());
      if ((un == u && vn == v) || !f.contains(un, vn)) break;
      Surface_point q;
      s.evaluate(un, vn, q, 0);
      if (sgn * q.p[a] < best_val[d]) break;
      best_val[d] = sgn * q.p[a];
      add(box, q.p);
      u = un;
      v = vn;
    }
  }
}

}  // namespace

Bbox_3 Body::hull_bbox() const {
  Bbox_3 box;
  if (is_point) box += Point_3(0, 0, 0).bbox();
  for (const auto& f : faces) box += f.surface.hull_bbox();
  for (const auto& c : curves) box += c.hull_bbox();
  for (const auto& p : mesh.vertices) box += p.bbox();
  return box;
}

Bbox_3 Body::trimmed_bbox() const {
  Bbox_3 box;
  if (is_point) box += Point_3(0, 0, 0).bbox();
  for (const auto& f : faces) add_face(box, f, edges);
  for (const auto& c : curves) add_curve(box, c);
  for (const auto& t : mesh.triangles)
    for (int k : t)
      if (k >= 0 && k < static_cast<int>(mesh.vertices.size())) box += mesh.vertices[k].bbox();
  return box;
}

Bbox_3 Body::trimmed_bbox(const Rigid_pose_3& X) const {
  Body placed;
  placed.faces.reserve(faces.size());
  for (const auto& f : faces) {
    Face g(transformed(f.surface, X), f.kind);
    g.surface.set_outward_sign(f.surface.outward_sign());
    g.trims = f.trims;
    g.trim_region = f.trim_region;
    placed.faces.push_back(std::move(g));
  }
  for (const auto& c : curves) placed.curves.push_back(transformed(c, X));
  placed.edges = edges;
  for (auto& e : placed.edges)
    if (e.curve) e.curve = transformed(*e.curve, X);
  for (const auto& p : mesh.vertices) placed.mesh.vertices.push_back(X(p));
  placed.mesh.triangles.insert(placed.mesh.triangles.end(), mesh.triangles.begin(),
                               mesh.triangles.end());
  Bbox_3 box = placed.trimmed_bbox();
  if (is_point) box += to_point(X.translation()).bbox();
  return box;
}

}  // namespace extremal
