// Support functions of a body's convex hull (Penetration_depth.h, support_bound): certified
// bounds on max over the body of n . x by a best-first search over halved Bezier sub-nets.
#include "algorithms/distance/Penetration_depth.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <queue>
#include <sstream>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "algorithms/pair/Feature.h"
#include "algorithms/pair/Pair_geometry.h"
#include "algorithms/distance/internal/Bezier_net.h"
#include "algorithms/distance/internal/Time_budget.h"
#include "kernel/Error.h"
#include "kernel/Shapes.h"

namespace extremal {

using internal::corner_params;
using internal::corner_pole;

namespace {

using internal::Hom;
using Hom_vector = std::vector<Hom, Eigen::aligned_allocator<Hom>>;

// A tree node (piece < 0 ... node >= 0) or a sub-net in the pool (node < 0).
struct Net_item {
  double key = 0.0;
  int node = -1;
  int piece = -1;
  int net = 0;  // pool offset
  double lo[2] = {0, 0}, hi[2] = {0, 0};
  int depth = 0;
};
struct Key_less {
  bool operator()(const Net_item& a, const Net_item& b) const { return a.key < b.key; }
};

// Maximises n.f over element e from params q by Newton's method (body frame); returns true and
// updates q, value when it found a better point on the body.
bool polish_support(const Distance_hierarchy& H, int e, const Vec3& n, double* q, double& value) {
  const auto& el = H.elements()[e];
  const int dim = el.feature.dimension();
  if (dim == 0) return false;
  const Rigid_pose_3 identity;
  Feature_point fp;
  bool improved = false;
  double cur[2] = {q[0], q[1]};
  for (int it = 0; it < 30; ++it) {
    evaluate_feature(el.feature, identity, cur, fp, 2);
    Eigen::Vector2d g = Eigen::Vector2d::Zero();
    Eigen::Matrix2d Hm = Eigen::Matrix2d::Identity();
    for (int i = 0; i < dim; ++i) {
      g[i] = n.dot(fp.d[i]);
      for (int j = 0; j < dim; ++j) Hm(i, j) = n.dot(fp.dd[i][j]);
    }
    Eigen::Vector2d step = Eigen::Vector2d::Zero();
    if (dim == 1) {
      if (!(Hm(0, 0) < 0.0)) break;
      step[0] = -g[0] / Hm(0, 0);
    } else {
      // A maximum: -H positive definite.
      const Eigen::LLT<Eigen::Matrix2d> llt(-Hm);
      if (llt.info() != Eigen::Success) break;
      step = llt.solve(g);
    }
    double next[2] = {cur[0], cur[1]};
    for (int i = 0; i < dim; ++i) {
      const double lo = el.feature.lower(i), hi = el.feature.upper(i);
      const double w = hi - lo;
      step[i] = std::clamp(step[i], -0.25 * w, 0.25 * w);
      next[i] = std::clamp(cur[i] + step[i], lo, hi);
    }
    if (!H.on_body(e, next)) break;
    Feature_point np;
    evaluate_feature(el.feature, identity, next, np, 0);
    const double v = n.dot(np.p);
    if (!(v > value)) break;
    value = v;
    cur[0] = next[0];
    cur[1] = next[1];
    improved = true;
    if (std::abs(step[0]) + std::abs(step[1]) < 1e-15 * (1.0 + std::abs(cur[0]) + std::abs(cur[1])))
      break;
  }
  if (improved) {
    q[0] = cur[0];
    q[1] = cur[1];
  }
  return improved;
}

// A sub-net of a trimmed face holds no maximiser of n.f when the gradient of n.f along the
// face's parameters is nowhere zero over it (its enclosure excludes zero) and it touches no
// open side of the face: a maximiser inside the trimmed domain would make the gradient vanish,
// and one on the trim boundary lies on a B-rep edge, a curve element whose own sub-nets hold
// it (not across a C0 knot line inside the face: Distance_hierarchy::reaches_kink). Such a
// sub-net is dropped without a bound (as Global_distance does for minima on trim
// boundaries): straddling sub-nets would otherwise bound the patch beyond the trim and close
// only linearly.
bool holds_no_maximum(const Distance_hierarchy& H, int e, const Hom* src, int nu, int nv,
                      const double* lo, const double* hi, const Vec3& n, Hom_vector& scratch) {
  const auto& el = H.elements()[e];
  if (el.kind != Element_kind::Face || !el.trimmed || H.reaches_uncarried(e, lo, hi, el.open_sides))
    return false;
  const int count = nu * nv;
  Vec3 centre = Vec3::Zero();
  for (int k = 0; k < count; ++k) centre += src[k].head<3>() / src[k][3];
  centre /= count;
  scratch.resize(count);
  for (int k = 0; k < count; ++k) {
    scratch[k] = src[k];
    scratch[k].head<3>() -= src[k][3] * centre;  // near the origin: less rounding
  }
  const double width[2] = {hi[0] - lo[0], hi[1] - lo[1]};
  internal::Derivative_enclosure enc;
  if (!internal::enclose_piece(scratch.data(), nu, nv, 2, width, enc, 1)) return false;
  for (int k = 0; k < 2; ++k) {
    internal::Interval g{0.0, 0.0};
    double dmax = 0.0;
    for (int c = 0; c < 3; ++c) {
      g = g + n[c] * enc.d[k][c];
      dmax = std::max({dmax, std::abs(enc.d[k][c].lo), std::abs(enc.d[k][c].hi)});
    }
    const double margin = 1e-12 * dmax;  // far above the rounding of the enclosure
    if (g.lo > margin || g.hi < -margin) return true;
  }
  return false;
}

}  // namespace

Support_bound support_bound(const Distance_hierarchy& H, const Rigid_pose_3& X_W, const Vec3& n_W,
                            const Support_request& request) {
  EXTREMAL_PRECONDITION(request.tolerance > 0.0 && request.max_nets > 0);
  Support_bound out;
  const Vec3 n = X_W.rotation().transpose() * n_W;  // body frame
  const double offset = n_W.dot(X_W.translation());
  const auto& tree = H.tree();
  const auto& pieces = H.pieces();
  const double scale = tree.front().radius + tree.front().centre.norm();
  const double tiny = 1e-13 * std::max(scale, 1e-300);
  const double coarse = std::max(request.tolerance, 1e-4 * tree.front().radius);

  Hom_vector pool, scratch;
  std::vector<Net_item> heap_storage;
  heap_storage.reserve(256);
  std::priority_queue<Net_item, std::vector<Net_item>, Key_less> heap(Key_less(),
                                                                       std::move(heap_storage));
  double best = -HUGE_VAL;
  int best_e = -1;
  double best_q[2] = {0, 0};
  double floor_upper = -HUGE_VAL;  // keys of sub-nets too small to split
  bool polished = false;

  auto consider_corners = [&](const Net_item& it) {
    const auto& pc = pieces[it.piece];
    const Hom* net = pool.data() + it.net;
    const int corners = pc.dimension == 2 ? 4 : pc.dimension == 1 ? 2 : 1;
    for (int k = 0; k < corners; ++k) {
      const Hom& P = net[corner_pole(pc.nu, pc.nv, k)];
      const double v = n.dot(P.head<3>() / P[3]);
      if (!(v > best)) continue;
      double q[2];
      corner_params(it.lo, it.hi, k, q);
      if (pc.dimension < 2) q[1] = 0.0;
      if (!H.on_body(pc.element, q)) continue;
      best = v;
      best_e = pc.element;
      best_q[0] = q[0];
      best_q[1] = q[1];
    }
  };
  auto net_key = [&](const Net_item& it, int count) {
    double key = -HUGE_VAL;
    const Hom* net = pool.data() + it.net;
    for (int k = 0; k < count; ++k) key = std::max(key, n.dot(net[k].head<3>() / net[k][3]));
    return key;
  };
  auto net_diagonal = [&](const Net_item& it, int count) {
    Vec3 lo = Vec3::Constant(HUGE_VAL), hi = Vec3::Constant(-HUGE_VAL);
    const Hom* net = pool.data() + it.net;
    for (int k = 0; k < count; ++k) {
      const Vec3 c = net[k].head<3>() / net[k][3];
      lo = lo.cwiseMin(c);
      hi = hi.cwiseMax(c);
    }
    return (hi - lo).norm();
  };

  Net_item root;
  root.node = 0;
  root.key = box_support(tree.front().box, n);
  heap.push(root);
  while (!heap.empty()) {
    const Net_item top = heap.top();
    if (top.key <= best + request.tolerance) break;
    if (!polished && request.newton_polish && best_e >= 0 && top.key <= best + coarse) {
      polished = true;
      polish_support(H, best_e, n, best_q, best);
      continue;
    }
    if (out.nets >= request.max_nets) break;
    heap.pop();
    if (top.node >= 0) {
      const auto& tn = tree[top.node];
      if (tn.piece < 0) {
        for (int child : {tn.left, tn.right}) {
          if (child < 0) continue;
          Net_item c;
          c.node = child;
          c.key = box_support(tree[child].box, n);
          if (c.key > best) heap.push(c);
        }
        continue;
      }
      const auto& pc = pieces[tn.piece];
      if (!H.may_hold_trimmed(pc.element, pc.lo, pc.hi)) continue;
      Net_item it;
      it.piece = tn.piece;
      it.net = static_cast<int>(pool.size());
      pool.insert(pool.end(), H.poles() + pc.offset, H.poles() + pc.offset + pc.nu * pc.nv);
      it.lo[0] = pc.lo[0];
      it.lo[1] = pc.lo[1];
      it.hi[0] = pc.hi[0];
      it.hi[1] = pc.hi[1];
      it.key = net_key(it, pc.nu * pc.nv);
      ++out.nets;
      consider_corners(it);
      if (it.key > best + request.tolerance && pc.dimension == 2 &&
          holds_no_maximum(H, pc.element, pool.data() + it.net, pc.nu, pc.nv, it.lo, it.hi, n, scratch))
        continue;
      if (it.key > best) heap.push(it);
      continue;
    }
    const auto& pc = pieces[top.piece];
    const int count = pc.nu * pc.nv;
    if (pc.dimension == 0 || net_diagonal(top, count) <= tiny) {
      floor_upper = std::max(floor_upper, top.key);  // cannot split further
      continue;
    }
    // Halve along the first parameter for curves; for surfaces along the direction in which
    // n.P varies most within the net's rows or columns (near a pole one direction barely
    // moves the point, and halving it gains nothing).
    int dir = 0;
    if (pc.dimension == 2) {
      const Hom* net = pool.data() + top.net;
      double var[2] = {0.0, 0.0};
      for (int line = 0; line < 2; ++line) {
        const int outer = line == 0 ? pc.nv : pc.nu, inner = line == 0 ? pc.nu : pc.nv;
        for (int a = 0; a < outer; ++a) {
          double lo = HUGE_VAL, hi = -HUGE_VAL;
          for (int b = 0; b < inner; ++b) {
            const Hom& P = line == 0 ? net[b * pc.nv + a] : net[a * pc.nv + b];
            const double v = n.dot(P.head<3>() / P[3]);
            lo = std::min(lo, v);
            hi = std::max(hi, v);
          }
          var[line] = std::max(var[line], hi - lo);
        }
      }
      dir = var[1] > var[0] ? 1 : 0;
    }
    const int at = static_cast<int>(pool.size());
    pool.resize(pool.size() + 2 * count);
    internal::split_net_half(pool.data() + top.net, pc.nu, pc.nv, dir, pool.data() + at,
                             pool.data() + at + count);
    for (int half = 0; half < 2; ++half) {
      Net_item c;
      c.piece = top.piece;
      c.net = at + half * count;
      c.depth = top.depth + 1;
      c.lo[0] = top.lo[0];
      c.lo[1] = top.lo[1];
      c.hi[0] = top.hi[0];
      c.hi[1] = top.hi[1];
      const double mid = 0.5 * (top.lo[dir] + top.hi[dir]);
      if (half == 0) c.hi[dir] = mid; else c.lo[dir] = mid;
      ++out.nets;
      if (!H.may_hold_trimmed(pc.element, c.lo, c.hi)) continue;
      c.key = net_key(c, count);
      if (c.key > best + request.tolerance && pc.dimension == 2 &&
          holds_no_maximum(H, pc.element, pool.data() + c.net, pc.nu, pc.nv, c.lo, c.hi, n, scratch)) {
        consider_corners(c);  // its corners on the face are still real points
        continue;
      }
      consider_corners(c);
      if (c.key > best) heap.push(c);
    }
  }
  if (!polished && request.newton_polish && best_e >= 0) polish_support(H, best_e, n, best_q, best);
  double upper = std::max(best, floor_upper);
  if (!heap.empty()) upper = std::max(upper, heap.top().key);
  out.upper = upper + offset;
  if (best_e >= 0) {
    const auto& el = H.elements()[best_e];
    Feature_point fp;
    evaluate_feature(el.feature, X_W, best_q, fp, 0);
    out.point = fp.p;
    out.lower = std::min(n_W.dot(fp.p), out.upper);
    out.kind = el.kind;
    out.element = best_e;
    out.params = {best_q[0], best_q[1]};
  }
  out.converged = best_e >= 0 && out.upper - out.lower <= request.tolerance;
  return out;
}


}  // namespace extremal
