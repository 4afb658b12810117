#include "algorithms/mesh/Mesh_front.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "algorithms/distance/Triangle_distance.h"
#include "algorithms/mesh/internal/Mesh_tuning.h"

namespace extremal {

using internal::k_box_rounding;
using internal::k_front_growth;
using internal::k_front_floor;
using internal::k_carried_cost_ratio;
using internal::k_key_rounding;

namespace {

// How far the corners of o all lie beyond the plane of triangle t, on either side (0 where
// they straddle it, or t is degenerate): a lower bound on the triangles' distance.
double plane_gap(const Vec3* t, const Vec3* o) {
  const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]);
  const double len = n.norm();
  if (!(len > 0.0)) return 0.0;
  const double d0 = n.dot(o[0] - t[0]), d1 = n.dot(o[1] - t[0]), d2 = n.dot(o[2] - t[0]);
  const double lo = std::min({d0, d1, d2}), hi = std::max({d0, d1, d2});
  return std::max({0.0, lo / len, -hi / len});
}

// The point body as a box: its origin.
const Obb& point_box() {
  static const Obb box;
  return box;
}

}  // namespace

Mesh_front::Mesh_front(const Mesh_bvh& a, const Mesh_bvh* b) : m_a(a), m_b(b) {
  m_length = box_diagonal(a.box()) + (b ? box_diagonal(b->box()) : 0.0);
  m_heap.reserve(1024);
}

double Mesh_front::box_bound(int a, int b, double enough) const {
  ++const_cast<Mesh_front_statistics&>(m_stats).box_bounds;
  const bool leaf_a = Mesh_bvh::is_leaf(a), leaf_b = m_b && Mesh_bvh::is_leaf(b);
  if (leaf_a && m_b && !leaf_b) {  // A's triangle against B's box, in A's frame
    const Obb& box = m_b->node(b).box;
    return triangle_box_lower_bound(m_a.corners(Mesh_bvh::leaf_slot(a)), m_R * box.centre + m_t,
                                    m_R * box.axes, box.half, enough);
  }
  if (leaf_b && !leaf_a) {  // B's triangle, placed in A's frame, against A's box
    const Vec3* c = m_b->corners(Mesh_bvh::leaf_slot(b));
    const Vec3 t[3] = {m_R * c[0] + m_t, m_R * c[1] + m_t, m_R * c[2] + m_t};
    const Obb& box = m_a.node(a).box;
    return triangle_box_lower_bound(t, box.centre, box.axes, box.half, enough);
  }
  Obb leaf_box;  // (a leaf's box against the point is made here)
  const Obb& ba = leaf_a ? (leaf_box = m_a.box(a)) : m_a.node(a).box;
  const Obb& bb = !m_b ? point_box() : m_b->node(b).box;
  return obb_lower_bound(ba, bb, m_R, m_t, enough);
}

double Mesh_front::measure_triangles(int slot_a, int slot_b) {
  ++m_stats.triangle_pairs;
  const Vec3* ca = m_a.corners(slot_a);
  if (slot_b < 0) {
    const Mesh_point q = closest_on_triangle_feature(m_t, ca[0], ca[1], ca[2]);
    if (q.distance < m_best.distance) {
      m_best.distance = q.distance;
      m_best.triangle_a = m_a.triangle_of_slot(slot_a);
      m_best.triangle_b = -1;
      m_best.point_a = q.point;
      m_best.point_b = m_t;
      m_best.uv_a[0] = q.uv[0];
      m_best.uv_a[1] = q.uv[1];
      m_best.uv_b[0] = m_best.uv_b[1] = 0.0;
    }
    return q.distance;
  }
  const Vec3* cb = m_b->corners(slot_b);
  for (int k = 0; k < 3; ++k) m_corners_b[k] = m_R * cb[k] + m_t;
  const Triangle_closest c = triangle_distance(ca, m_corners_b);
  if (c.distance < m_best.distance) {
    m_best.distance = c.distance;
    m_best.triangle_a = m_a.triangle_of_slot(slot_a);
    m_best.triangle_b = m_b->triangle_of_slot(slot_b);
    m_best.point_a = c.point_a;
    m_best.point_b = c.point_b;
    for (int k = 0; k < 2; ++k) {
      m_best.uv_a[k] = c.uv_a[k];
      m_best.uv_b[k] = c.uv_b[k];
    }
  }
  return c.distance;
}

double Mesh_front::bound(int a, int b, double enough) {
  // Two leaves (or a leaf and the point): cheap bounds first (the planes, then a triangle
  // against the other's box), the exact distance where they do not reach `enough`.
  if (Mesh_bvh::is_leaf(a) && (!m_b || Mesh_bvh::is_leaf(b))) {
    if (m_b && enough < HUGE_VAL) {
      // The triangles' planes first: the other's corners all beyond one by at least `enough`
      // bound the pair without measuring it.
      const Vec3* ca = m_a.corners(Mesh_bvh::leaf_slot(a));
      const Vec3* cb = m_b->corners(Mesh_bvh::leaf_slot(b));
      Vec3 pb[3];
      for (int k = 0; k < 3; ++k) pb[k] = m_R * cb[k] + m_t;
      const double gap = std::max(plane_gap(ca, pb), plane_gap(pb, ca));
      const double rounding = k_box_rounding * (ca[0].norm() + pb[0].norm() + gap);
      if (gap - rounding >= enough) return gap - rounding;
      // Then A's triangle against the box of B's.
      const Obb box = m_b->box(b);
      const double boxed =
          triangle_box_lower_bound(ca, m_R * box.centre + m_t, m_R * box.axes, box.half, enough);
      if (boxed >= enough) return boxed;
    }
    return measure(a, b);
  }
  return box_bound(a, b, enough);
}

double Mesh_front::measure(int a, int b) {
  return measure_triangles(Mesh_bvh::leaf_slot(a), m_b ? Mesh_bvh::leaf_slot(b) : -1);
}

void Mesh_front::push(double lower, int a, int b) {
  m_heap.push_back({lower + m_sum, a, b});
  std::push_heap(m_heap.begin(), m_heap.end(), Later());
}

void Mesh_front::sift_down() {
  // The top's key grew: moved down to its place (one path of the heap).
  const std::size_t n = m_heap.size();
  std::size_t i = 0;
  const Entry e = m_heap[0];
  for (;;) {
    std::size_t c = 2 * i + 1;
    if (c >= n) break;
    if (c + 1 < n && m_heap[c + 1].key < m_heap[c].key) ++c;
    if (!(m_heap[c].key < e.key)) break;
    m_heap[i] = m_heap[c];
    i = c;
  }
  m_heap[i] = e;
}

void Mesh_front::restart() {
  m_heap.clear();
  m_sum = 0.0;
  m_restart_pending = true;
}

template <class Slack>
void Mesh_front::descend(double lower, int a, int b, const Slack& slack) {
  // Depth first from (a, b), bounded at this pose, nearer child first: pairs that clear the
  // minimum go to the front, leaf pairs are measured (and kept with their distance). The
  // minimum only falls during a step, so what cleared stays cleared until the next.
  m_stack.clear();
  m_stack.push_back({lower, a, b});
  while (!m_stack.empty()) {
    const Item it = m_stack.back();
    m_stack.pop_back();
    const double need = m_best.distance - slack();
    // (Compared as the key it would be stored as, so that what is pushed as cleared is
    // settled when read back: test MeshPairs.TheCarriedFrontEqualsBruteForceAtEveryStepOfRandomMotions.)
    if ((it.lower + m_sum) - m_sum >= need) {
      push(it.lower, it.a, it.b);
      continue;
    }
    ++m_stats.opened;
    const bool leaf_a = Mesh_bvh::is_leaf(it.a);
    const bool leaf_b = !m_b || Mesh_bvh::is_leaf(it.b);
    if (leaf_a && leaf_b) {
      push(measure(it.a, it.b), it.a, it.b);
      continue;
    }
    // Split the larger node (a leaf cannot be split).
    const bool split_a = !leaf_a && (leaf_b || m_a.node(it.a).box.half.squaredNorm() >=
                                                   m_b->node(it.b).box.half.squaredNorm());
    Item c0, c1;
    if (split_a) {
      const int* child = m_a.node(it.a).child;
      c0 = {bound(child[0], it.b, need), child[0], it.b};
      c1 = {bound(child[1], it.b, need), child[1], it.b};
    } else {
      const int* child = m_b->node(it.b).child;
      c0 = {bound(it.a, child[0], need), it.a, child[0]};
      c1 = {bound(it.a, child[1], need), it.a, child[1]};
    }
    if (c0.lower < c1.lower) std::swap(c0, c1);
    m_stack.push_back(c0);  // the farther, then the nearer on top
    m_stack.push_back(c1);
  }
}

const Mesh_closest& Mesh_front::update(const Rigid_pose_3& X_AB, double closer, double tolerance) {
  ++m_stats.steps;
  m_R = X_AB.rotation();
  m_t = X_AB.translation();
  bool rebuilt = false;
  const long opened_before = m_stats.opened;
  if (!m_started) {
    m_started = true;
    m_best = Mesh_closest();
    restart();
    rebuilt = true;
  } else if (m_restart) {
    m_restart = false;
    restart();
    rebuilt = true;
  } else {
    m_sum += closer;
  }
  // The best pair of the last step, measured at this pose, is the minimum to beat.
  if (m_best.triangle_a >= 0) {
    const int ta = m_best.triangle_a, tb = m_best.triangle_b;
    m_best.distance = HUGE_VAL;
    measure_triangles(m_a.slot_of_triangle(ta), tb < 0 ? -1 : m_b->slot_of_triangle(tb));
  }
  // A key's bound holds less the motion since (key - m_sum, to the rounding of the sum). The
  // tolerance is at least that rounding, so that an entry pushed back as clear stays settled.
  auto slack = [&] {
    return std::max(tolerance, k_key_rounding * (std::abs(m_best.distance) + m_sum + m_length));
  };
  auto clears = [&](double lower) { return lower >= m_best.distance - slack(); };
  auto settled = [&](const Entry& e) { return clears(e.key - m_sum); };
  for (int pass = 0; pass < 2; ++pass) {
    if (m_restart_pending) {  // from the roots
      m_restart_pending = false;
      const int root_a = m_a.root(), root_b = m_b ? m_b->root() : 0;
      descend(bound(root_a, root_b), root_a, root_b, slack);
    }
    while (!m_heap.empty() && !settled(m_heap.front())) {
      const Entry e = m_heap.front();
      ++m_stats.opened;
      const double lower = bound(e.a, e.b, m_best.distance - slack());
      if (clears((lower + m_sum) - m_sum)) {  // bounded again at this pose, in place (as a key)
        m_heap.front().key = lower + m_sum;
        sift_down();
        continue;
      }
      std::pop_heap(m_heap.begin(), m_heap.end(), Later());
      m_heap.pop_back();
      descend(lower, e.a, e.b, slack);
    }
    // Grown past a multiple of its size after the last rebuild: made anew from the roots.
    if (pass == 0 && m_heap.size() > k_front_growth * m_rebuilt_size + k_front_floor) {
      ++m_stats.rebuilds;
      restart();
      rebuilt = true;
      continue;
    }
    break;
  }
  // Every pair off the front's heap is measured or pruned against the best; the heap's least
  // key, decayed and less its rounding, bounds the rest.
  m_best.lower_bound = m_best.distance;
  if (!m_heap.empty())
    m_best.lower_bound = std::min(m_best.lower_bound,
                                  m_heap.front().key - m_sum -
                                      k_key_rounding * (std::abs(m_best.distance) + m_sum + m_length));
  // A carried step that cost more than a traversal from the roots did (the motion decayed most
  // of the front): the next step traverses from the roots again, so that no step costs much
  // more than a cold query (test MeshFront.TheCarriedFrontEqualsAColdSolveAndBruteForceAtEveryStep).
  const long opened = m_stats.opened - opened_before;
  if (rebuilt) {
    ++m_stats.traversals;
    m_rebuilt_size = m_heap.size();
    m_cold_cost = opened;
  } else if (static_cast<double>(opened) > k_carried_cost_ratio * static_cast<double>(m_cold_cost)) {
    m_restart = true;
    ++m_stats.cost_restarts;
  }
  return m_best;
}

}  // namespace extremal
