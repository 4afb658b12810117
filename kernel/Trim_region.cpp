#include "kernel/Trim_region.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace extremal {

namespace {

struct Uv {
  double u, v;
};

Uv eval_uv(const Nurbs_curve_3& c, double t) {
  Curve_point cp;
  c.evaluate(t, cp, 0);
  return {cp.p.x(), cp.p.y()};
}

double point_segment_distance2(double pu, double pv, const Uv& a, const Uv& b) {
  const double du = b.u - a.u, dv = b.v - a.v;
  const double len2 = du * du + dv * dv;
  double s = 0.0;
  if (len2 > 0.0) s = std::clamp(((pu - a.u) * du + (pv - a.v) * dv) / len2, 0.0, 1.0);
  const double eu = a.u + s * du - pu, ev = a.v + s * dv - pv;
  return eu * eu + ev * ev;
}

// Appends points of c on (t0, t1] so that the polyline stays within `dev` of the curve: the chord
// is split while a quarter, half or three-quarter point strays farther than dev from it.
void flatten(const Nurbs_curve_3& c, double t0, const Uv& p0, double t1, const Uv& p1,
             double dev, int depth, std::vector<Uv>& out) {
  bool fine = depth >= 22;
  if (!fine) {
    const double dev2 = dev * dev;
    fine = true;
    for (double f : {0.25, 0.5, 0.75}) {
      const Uv q = eval_uv(c, std::min(t0 + f * (t1 - t0), t1));
      if (point_segment_distance2(q.u, q.v, p0, p1) > dev2) {
        fine = false;
        break;
      }
    }
  }
  if (fine) {
    out.push_back(p1);
    return;
  }
  const double tm = 0.5 * (t0 + t1);
  const Uv pm = eval_uv(c, tm);
  flatten(c, t0, p0, tm, pm, dev, depth + 1, out);
  flatten(c, tm, pm, t1, p1, dev, depth + 1, out);
}

std::vector<Uv> flatten_curve(const Nurbs_curve_3& c, double dev) {
  std::vector<Uv> pts;
  const auto& k = c.knots();
  const double lo = c.domain_min(), hi = c.domain_max();
  std::vector<double> breaks;
  breaks.push_back(lo);
  for (double t : k)
    if (t > breaks.back() && t < hi) breaks.push_back(t);
  breaks.push_back(hi);
  const int sub = std::min(c.degree() + 1, 8);
  pts.push_back(eval_uv(c, lo));
  for (std::size_t s = 0; s + 1 < breaks.size(); ++s) {
    const double a = breaks[s], b = breaks[s + 1];
    for (int i = 0; i < sub; ++i) {
      const double t0 = std::min(a + (b - a) * i / sub, b);
      const double t1 = (i + 1 == sub) ? b : std::min(a + (b - a) * (i + 1) / sub, b);
      const Uv p0 = pts.back();
      flatten(c, t0, p0, t1, eval_uv(c, t1), dev, 0, pts);
    }
  }
  return pts;
}

}  // namespace

Trim_region::Trim_region(const std::vector<Trim_loop>& loops, double tolerance) {
  // Parameter extent from the control points, which bound the curves.
  double umin = std::numeric_limits<double>::infinity(), umax = -umin, vmin = umin, vmax = -umin;
  for (const auto& loop : loops)
    for (const auto& tc : loop.curves)
      for (const auto& p : tc.uv.poles()) {
        umin = std::min(umin, p.x());
        umax = std::max(umax, p.x());
        vmin = std::min(vmin, p.y());
        vmax = std::max(vmax, p.y());
      }
  if (!(umin <= umax)) return;  // no curves: untrimmed
  const double extent = std::max({umax - umin, vmax - vmin, 1e-300});
  m_tol = (tolerance > 0.0 && std::isfinite(tolerance)) ? tolerance : 1e-5 * extent;
  const double dev = 0.5 * m_tol;

  std::vector<Uv> loop_pts;
  for (const auto& loop : loops) {
    if (loop.curves.empty()) continue;
    loop_pts.clear();
    for (const auto& tc : loop.curves) {
      std::vector<Uv> pts = flatten_curve(tc.uv, dev);
      if (tc.reversed) std::reverse(pts.begin(), pts.end());
      if (!loop_pts.empty()) {
        const Uv& last = loop_pts.back();
        if (std::hypot(last.u - pts.front().u, last.v - pts.front().v) > m_tol) m_closed = false;
      }
      loop_pts.insert(loop_pts.end(), pts.begin(), pts.end());
    }
    const Uv& first = loop_pts.front();
    const Uv& last = loop_pts.back();
    if (std::hypot(last.u - first.u, last.v - first.v) > m_tol) m_closed = false;
    loop_pts.push_back(first);  // close the loop (a zero-length segment when it already is)
    for (std::size_t i = 0; i + 1 < loop_pts.size(); ++i) {
      const Uv& a = loop_pts[i];
      const Uv& b = loop_pts[i + 1];
      if (a.u == b.u && a.v == b.v) continue;
      m_seg.push_back({a.u, a.v, b.u, b.v});
    }
  }
  if (m_seg.empty()) return;

  m_umin = m_vmin = std::numeric_limits<double>::infinity();
  m_umax = m_vmax = -m_umin;
  for (const auto& s : m_seg) {
    m_umin = std::min({m_umin, s.u0, s.u1});
    m_umax = std::max({m_umax, s.u0, s.u1});
    m_vmin = std::min({m_vmin, s.v0, s.v1});
    m_vmax = std::max({m_vmax, s.v0, s.v1});
  }
  // Slabs over [vmin - tol, vmax + tol]; each segment goes into every slab its v range, widened
  // by the tolerance, touches, so one slab holds every segment a query in it can cross or touch.
  m_slabs = static_cast<int>(std::clamp<std::size_t>(m_seg.size() / 2, 1, 2048));
  const double lo = m_vmin - m_tol, hi = m_vmax + m_tol;
  m_slab_h = (hi - lo) / m_slabs;
  if (!(m_slab_h > 0.0)) m_slab_h = 1.0;
  m_slab_start.assign(m_slabs + 1, 0);
  for (const auto& s : m_seg) {
    const int a = slab_of(std::min(s.v0, s.v1) - m_tol), b = slab_of(std::max(s.v0, s.v1) + m_tol);
    for (int k = a; k <= b; ++k) ++m_slab_start[k + 1];
  }
  for (int k = 0; k < m_slabs; ++k) m_slab_start[k + 1] += m_slab_start[k];
  m_slab_seg.resize(m_slab_start[m_slabs]);
  std::vector<int> fill(m_slab_start.begin(), m_slab_start.end() - 1);
  for (std::size_t i = 0; i < m_seg.size(); ++i) {
    const auto& s = m_seg[i];
    const int a = slab_of(std::min(s.v0, s.v1) - m_tol), b = slab_of(std::max(s.v0, s.v1) + m_tol);
    for (int k = a; k <= b; ++k) m_slab_seg[fill[k]++] = static_cast<int>(i);
  }
}

int Trim_region::slab_of(double v) const {
  const double f = std::floor((v - (m_vmin - m_tol)) / m_slab_h);
  return static_cast<int>(std::clamp(f, 0.0, static_cast<double>(m_slabs - 1)));
}

Trim_location Trim_region::locate(double u, double v) const {
  if (m_seg.empty()) return Trim_location::Inside;
  if (!(std::isfinite(u) && std::isfinite(v))) return Trim_location::Outside;
  if (v < m_vmin - m_tol || v > m_vmax + m_tol || u < m_umin - m_tol || u > m_umax + m_tol)
    return Trim_location::Outside;
  const int k = slab_of(v);
  const double tol2 = m_tol * m_tol;
  bool inside = false;
  for (int i = m_slab_start[k]; i < m_slab_start[k + 1]; ++i) {
    const Segment& s = m_seg[m_slab_seg[i]];
    // Near the segment: on the boundary band.
    if (u >= std::min(s.u0, s.u1) - m_tol && u <= std::max(s.u0, s.u1) + m_tol &&
        point_segment_distance2(u, v, {s.u0, s.v0}, {s.u1, s.v1}) <= tol2)
      return Trim_location::On_boundary;
    // Crossing of the ray towards +u, half-open in v so shared vertices count once.
    if ((s.v0 > v) != (s.v1 > v)) {
      const double uc = s.u0 + (v - s.v0) * (s.u1 - s.u0) / (s.v1 - s.v0);
      if (uc > u) inside = !inside;
    }
  }
  return inside ? Trim_location::Inside : Trim_location::Outside;
}

bool Trim_region::boundary_directions(double u, double v, double along[2], double out[2]) const {
  if (m_seg.empty() || !(std::isfinite(u) && std::isfinite(v))) return false;
  if (v < m_vmin - m_tol || v > m_vmax + m_tol || u < m_umin - m_tol || u > m_umax + m_tol)
    return false;
  const int k = slab_of(v);
  const Segment* nearest = nullptr;
  double best = m_tol * m_tol;
  for (int i = m_slab_start[k]; i < m_slab_start[k + 1]; ++i) {
    const Segment& s = m_seg[m_slab_seg[i]];
    const double d2 = point_segment_distance2(u, v, {s.u0, s.v0}, {s.u1, s.v1});
    if (d2 <= best) best = d2, nearest = &s;
  }
  if (nearest == nullptr) return false;
  const double du = nearest->u1 - nearest->u0, dv = nearest->v1 - nearest->v0;
  const double len = std::hypot(du, dv);
  along[0] = du / len;
  along[1] = dv / len;
  // Four bands across: past the band on either side, unless near the segment's end.
  const double step = 4.0 * m_tol;
  for (const double sign : {1.0, -1.0}) {
    out[0] = -sign * along[1];
    out[1] = sign * along[0];
    if (locate(u + step * out[0], v + step * out[1]) == Trim_location::Outside &&
        locate(u - step * out[0], v - step * out[1]) != Trim_location::Outside)
      return true;
  }
  return false;
}

bool Trim_region::box_outside(double u0, double v0, double u1, double v1) const {
  if (m_seg.empty()) return false;
  if (!(std::isfinite(u0) && std::isfinite(v0) && std::isfinite(u1) && std::isfinite(v1)))
    return false;
  // The box grown by the band (and a little more for rounding): a segment that misses it is
  // farther than the tolerance from every point of the box.
  const double g = 1.01 * m_tol + 1e-15 * (std::abs(m_umax) + std::abs(m_vmax) + 1.0);
  const double bu0 = u0 - g, bu1 = u1 + g, bv0 = v0 - g, bv1 = v1 + g;
  if (bu1 < m_umin || bu0 > m_umax || bv1 < m_vmin || bv0 > m_vmax) return true;
  // A centre on the face answers at once (one slab's scan); boxes inside the face are the
  // common case and would otherwise scan every slab they span.
  if (locate(0.5 * (u0 + u1), 0.5 * (v0 + v1)) != Trim_location::Outside) return false;
  const int ka = slab_of(bv0), kb = slab_of(bv1);
  for (int k = ka; k <= kb; ++k)
    for (int i = m_slab_start[k]; i < m_slab_start[k + 1]; ++i) {
      const Segment& s = m_seg[m_slab_seg[i]];
      // Liang-Barsky clip of the segment against the grown box.
      double t0 = 0.0, t1 = 1.0;
      const double du = s.u1 - s.u0, dv = s.v1 - s.v0;
      const double p[4] = {-du, du, -dv, dv};
      const double q[4] = {s.u0 - bu0, bu1 - s.u0, s.v0 - bv0, bv1 - s.v0};
      bool hit = true;
      for (int e = 0; e < 4 && hit; ++e) {
        if (p[e] == 0.0) {
          if (q[e] < 0.0) hit = false;
        } else {
          const double r = q[e] / p[e];
          if (p[e] < 0.0) {
            if (r > t1) hit = false;
            else t0 = std::max(t0, r);
          } else {
            if (r < t0) hit = false;
            else t1 = std::min(t1, r);
          }
        }
      }
      if (hit) return false;
    }
  return true;
}

}  // namespace extremal
