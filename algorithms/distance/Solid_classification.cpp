#include "algorithms/distance/Solid_classification.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "algorithms/distance/internal/Bezier_net.h"
#include "kernel/Error.h"

namespace extremal {

// certified_ball: sampled points and the net's box agree with the ball to this fraction of its
// radius (a rational quadratic sphere: to rounding).
constexpr double k_ball_agreement = 1e-12;

namespace {
using internal::Hom;
using Hom_vector = std::vector<Hom, Eigen::aligned_allocator<Hom>>;
}  // namespace

// ---- Closedness ----------------------------------------------------------------------------

namespace {

// Point on side `side` (0 u_min, 1 u_max, 2 v_min, 3 v_max) of s at fraction t along it.
Vec3 side_point(const Nurbs_surface_3& s, int side, double t) {
  Surface_point sp;
  const double u = side == 0 ? s.u_min() : side == 1 ? s.u_max() : s.u_min() + t * (s.u_max() - s.u_min());
  const double v = side == 2 ? s.v_min() : side == 3 ? s.v_max() : s.v_min() + t * (s.v_max() - s.v_min());
  s.evaluate(u, v, sp, 0);
  return sp.p;
}

// Distance from x to side `side` of s: sampled, then Newton on the squared distance.
double distance_to_side(const Nurbs_surface_3& s, int side, const Vec3& x) {
  const int samples = 64;
  double best_t = 0.0, best = HUGE_VAL;
  for (int k = 0; k <= samples; ++k) {
    const double t = static_cast<double>(k) / samples;
    const double d = (side_point(s, side, t) - x).squaredNorm();
    if (d < best) {
      best = d;
      best_t = t;
    }
  }
  const bool along_v = side < 2;
  const double w = along_v ? s.v_max() - s.v_min() : s.u_max() - s.u_min();
  double t = best_t;
  for (int it = 0; it < 30; ++it) {
    Surface_point sp;
    const double u = side == 0 ? s.u_min() : side == 1 ? s.u_max() : s.u_min() + t * (s.u_max() - s.u_min());
    const double v = side == 2 ? s.v_min() : side == 3 ? s.v_max() : s.v_min() + t * (s.v_max() - s.v_min());
    s.evaluate(u, v, sp, 2);
    const Vec3 d = sp.p - x;
    const Vec3 dt = (along_v ? sp.dv : sp.du) * w;
    const Vec3 dtt = (along_v ? sp.dvv : sp.duu) * w * w;
    const double g = d.dot(dt), h = dt.squaredNorm() + d.dot(dtt);
    if (!(h > 0.0)) break;
    const double nt = std::clamp(t - g / h, 0.0, 1.0);
    const double nd = (side_point(s, side, nt) - x).squaredNorm();
    if (!(nd < best)) break;
    best = nd;
    t = nt;
  }
  return std::sqrt(best);
}

}  // namespace

Closedness body_closedness(const Body& body) {
  Closedness out;
  if (body.is_point) {
    out.reason = "a point body encloses nothing";
    return out;
  }
  if (!body.mesh.empty()) {
    std::map<std::pair<int, int>, int> uses;
    for (const auto& t : body.mesh.triangles)
      for (int k = 0; k < 3; ++k) {
        const int a = t[k], b = t[(k + 1) % 3];
        ++uses[{std::min(a, b), std::max(a, b)}];
      }
    for (const auto& [edge, count] : uses)
      if (count != 2) {
        std::ostringstream os;
        os << "mesh edge (" << edge.first << ", " << edge.second << ") has " << count
           << " triangle(s), not 2: the mesh is not closed";
        out.reason = os.str();
        return out;
      }
    out.closed = true;
    out.reason = "every mesh edge has two triangles";
    return out;
  }
  if (body.faces.empty()) {
    out.reason = "the body has no faces (curves only)";
    return out;
  }
  const bool brep = !body.edges.empty();
  for (std::size_t k = 0; k < body.edges.size(); ++k)
    if (body.edges[k].curve && body.edges[k].uses.size() != 2) {  // a pole edge has no curve
      std::ostringstream os;
      os << "B-rep edge " << k << " bounds " << body.edges[k].uses.size()
         << " face(s), not 2: the shell is not closed";
      out.reason = os.str();
      return out;
    }
  // Patch sides: each wraps, collapses, or lies on a side of another face (untrimmed faces).
  const Bbox_3 box = body.hull_bbox();
  const double size = Vec3(box.xmax() - box.xmin(), box.ymax() - box.ymin(), box.zmax() - box.zmin()).norm();
  const double tol = 1e-8 * size;
  struct Free_side {
    int face, side;
  };
  std::vector<Free_side> free_sides;
  for (std::size_t i = 0; i < body.faces.size(); ++i) {
    const Face& f = body.faces[i];
    if (!f.trims.empty()) {
      if (!brep) {
        std::ostringstream os;
        os << "face " << i << " is trimmed but the body has no B-rep edges to close it";
        out.reason = os.str();
        return out;
      }
      continue;  // its boundary is B-rep edges, each shared by two faces (checked above)
    }
    const Feature feature = Feature::surface(f.surface);
    const unsigned collapsed = feature.collapsed_edges();
    for (int side = 0; side < 4; ++side) {
      const bool wraps = side < 2 ? f.surface.is_closed_u() : f.surface.is_closed_v();
      if (wraps || (collapsed & (1u << side))) continue;
      free_sides.push_back({static_cast<int>(i), side});
    }
  }
  for (const Free_side& fs : free_sides) {
    const Nurbs_surface_3& s = body.faces[fs.face].surface;
    for (int k = 1; k <= 5; ++k) {
      const Vec3 x = side_point(s, fs.side, k / 6.0);
      bool matched = false;
      for (const Free_side& other : free_sides) {
        if (other.face == fs.face && other.side == fs.side) continue;
        if (distance_to_side(body.faces[other.face].surface, other.side, x) <= tol) {
          matched = true;
          break;
        }
      }
      if (!matched) {
        static const char* names[] = {"u_min", "u_max", "v_min", "v_max"};
        std::ostringstream os;
        os << "face " << fs.face << ": its " << names[fs.side]
           << " side is a free boundary (no other face meets it): the body is not closed";
        out.reason = os.str();
        return out;
      }
    }
  }
  out.closed = true;
  out.reason = brep ? "every B-rep edge bounds two faces" : "every patch side wraps, collapses or meets another patch";
  return out;
}

bool is_certified_convex(const Body& body) {
  if (body.is_point) return true;
  if (body.faces.size() != 1 || !body.curves.empty() || !body.mesh.empty()) return false;
  const Face& f = body.faces.front();
  if (!f.trims.empty() || (f.kind != "sphere" && f.kind != "ellipsoid")) return false;
  return body_closedness(body).closed;
}

std::optional<Ball> certified_ball(const Body& body) {
  if (!is_certified_convex(body) || body.is_point || body.faces.front().kind != "sphere")
    return std::nullopt;
  const Nurbs_surface_3& s = body.faces.front().surface;
  // The control net of a whole sphere is symmetric about its centre, and so is its box.
  const Bbox_3 box = s.hull_bbox();
  Ball b;
  b.centre = Vec3(0.5 * (box.xmin() + box.xmax()), 0.5 * (box.ymin() + box.ymax()),
                  0.5 * (box.zmin() + box.zmax()));
  constexpr int k_samples = 9;
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (int i = 0; i < k_samples; ++i)
    for (int j = 0; j < k_samples; ++j) {
      const double u = s.u_min() + (s.u_max() - s.u_min()) * i / (k_samples - 1);
      const double v = s.v_min() + (s.v_max() - s.v_min()) * j / (k_samples - 1);
      Surface_point p;
      s.evaluate(u, v, p, 0);
      const double r = (p.p - b.centre).norm();
      lo = std::min(lo, r);
      hi = std::max(hi, r);
    }
  b.radius = 0.5 * (lo + hi);
  if (!(hi - lo <= k_ball_agreement * b.radius) || !(b.radius > 0.0)) return std::nullopt;
  return b;
}

// ---- Winding number ------------------------------------------------------------------------

Winding_number winding_number(const Distance_hierarchy& H, const Rigid_pose_3& X_W, const Vec3& x_W,
                              double clearance) {
  EXTREMAL_PRECONDITION(clearance > 0.0);
  static const double gx[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                               0.9061798459386640};
  static const double gw[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                               0.4786286704993665, 0.2369268850561891};
  Winding_number out;
  const Vec3 x = X_W.inverse().apply_point(x_W);
  const long max_cells = 2000000;
  const int max_depth = 80;
  double sum = 0.0;
  bool failed = false;
  struct Cell {
    int net, depth;
    double lo[2], hi[2];
  };
  Hom_vector pool;
  std::vector<Cell> stack;
  for (const auto& pc : H.pieces()) {
    if (pc.dimension != 2 || failed) continue;
    const auto& el = H.elements()[pc.element];
    const Nurbs_surface_3& s = *el.feature.surface();
    const double sign = s.outward_sign();
    const int count = pc.nu * pc.nv;
    pool.clear();
    stack.clear();
    pool.insert(pool.end(), H.poles() + pc.offset, H.poles() + pc.offset + count);
    stack.push_back({0, 0, {pc.lo[0], pc.lo[1]}, {pc.hi[0], pc.hi[1]}});
    while (!stack.empty()) {
      const Cell c = stack.back();
      stack.pop_back();
      if (el.trimmed && !H.may_hold_trimmed(pc.element, c.lo, c.hi)) continue;
      Vec3 bmin = Vec3::Constant(HUGE_VAL), bmax = Vec3::Constant(-HUGE_VAL);
      for (int k = 0; k < count; ++k) {
        const Vec3 p = pool[c.net + k].head<3>() / pool[c.net + k][3];
        bmin = bmin.cwiseMin(p);
        bmax = bmax.cwiseMax(p);
      }
      const double diag = (bmax - bmin).norm();
      const double dist = std::max(internal::box_distance(bmin, bmax, x, x), clearance);
      bool split = diag > 0.5 * dist;
      double cell_sum = 0.0;
      if (!split) {
        int in = 0, total = 0;
        const double ju = 0.5 * (c.hi[0] - c.lo[0]), jv = 0.5 * (c.hi[1] - c.lo[1]);
        for (int i = 0; i < 5; ++i)
          for (int j = 0; j < 5; ++j) {
            const double q[2] = {c.lo[0] + ju * (1.0 + gx[i]), c.lo[1] + jv * (1.0 + gx[j])};
            ++total;
            if (el.trimmed && !H.on_body(pc.element, q)) continue;
            ++in;
            Surface_point sp;
            s.evaluate(q[0], q[1], sp, 1);
            const Vec3 r = sp.p - x;
            const double r2 = r.squaredNorm();
            cell_sum += gw[i] * gw[j] * r.dot(sp.du.cross(sp.dv)) / (r2 * std::sqrt(r2));
          }
        cell_sum *= sign * ju * jv;
        // A trim boundary through the cell: refine until the cell is small against its
        // distance, so the misclassified sliver weighs little.
        if (in > 0 && in < total && diag > 0.05 * dist) split = true;
      }
      if (!split) {
        sum += cell_sum;
        ++out.cells;
        continue;
      }
      if (c.depth >= max_depth || out.cells + static_cast<long>(stack.size()) > max_cells) {
        failed = true;
        break;
      }
      const int dir = c.depth % 2;
      const int at = static_cast<int>(pool.size());
      pool.resize(pool.size() + 2 * count);
      internal::split_net_half(pool.data() + c.net, pc.nu, pc.nv, dir, pool.data() + at,
                               pool.data() + at + count);
      const double mid = 0.5 * (c.lo[dir] + c.hi[dir]);
      Cell left = c, right = c;
      left.net = at;
      right.net = at + count;
      left.depth = right.depth = c.depth + 1;
      left.hi[dir] = mid;
      right.lo[dir] = mid;
      stack.push_back(left);
      stack.push_back(right);
    }
  }
  out.value = sum / (4.0 * M_PI);
  out.determined = !failed && std::abs(out.value - std::round(out.value)) <= 0.25;
  return out;
}

}  // namespace extremal
