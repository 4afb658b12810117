// The branch and bound's walk: the queue of node pairs, best first, splitting and pruning, and
// the result (Global_distance.h).
#include "algorithms/distance/internal/Distance_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "kernel/Error.h"

namespace extremal::internal {

void Distance_solver::fill(Distance_result& r) const {
  r.upper_bound = m_best.distance;
  r.distance = m_best.distance;
  r.point_a = m_best.pa;
  r.point_b = m_best.pb;
  const auto& ea = m_side[0].h->elements();
  const auto& eb = m_side[1].h->elements();
  if (m_best.ea >= 0) {
    r.kind_a = ea[m_best.ea].kind;
    r.element_a = ea[m_best.ea].index;
    r.face_a = r.kind_a == Element_kind::Face ? r.element_a : -1;
  }
  if (m_best.eb >= 0) {
    r.kind_b = eb[m_best.eb].kind;
    r.element_b = eb[m_best.eb].index;
    r.face_b = r.kind_b == Element_kind::Face ? r.element_b : -1;
  }
  r.params_a = {m_best.qa[0], m_best.qa[1]};
  r.params_b = {m_best.qb[0], m_best.qb[1]};
  if (m_best.distance > 0.0) r.normal = (m_best.pb - m_best.pa) / m_best.distance;
  // At rounding distance the witnesses' direction is noise (a ball resting on a plane at its
  // pole, 6e-13 apart, read (-0.77, 0.60, -0.20)): the surfaces' normal, as at contact. Closer
  // than a millionth of the smaller body, the surface normal where it agrees with d within 5
  // degrees (a face's interior point: exact there; a cap at its rim is not, and d stays),
  // turned along d.
  const double small = m_size[0] > 0.0 && m_size[1] > 0.0 ? std::min(m_size[0], m_size[1])
                                                          : std::max(m_size[0], m_size[1]);
  if (m_best.distance <= 1e-6 * small) {
    const Vec3 n[2] = {surface_normal(0), surface_normal(1)};
    if (m_best.distance <= 1e-12 * small) {
      const Vec3& m = n[0] != Vec3::Zero() ? n[0] : n[1];
      if (m != Vec3::Zero()) r.normal = m.dot(r.normal) < 0.0 ? Vec3(-m) : m;
    } else {
      const double c[2] = {n[0].dot(r.normal), n[1].dot(r.normal)};
      const int k = std::abs(c[0]) >= std::abs(c[1]) ? 0 : 1;
      if (std::abs(c[k]) >= 0.996) r.normal = c[k] < 0.0 ? Vec3(-n[k]) : n[k];
    }
  }
  r.newton_runs = m_newton_runs;
  r.intersection_attempts = m_intersection_attempts;
  r.nodes_created = static_cast<long>(m_side[0].pools->nodes.size() + m_side[1].pools->nodes.size());
}

void Distance_solver::set_resolution() {
  // Floating-point resolution of the scene: coordinates are good to a few ulps of their size,
  // in the world and in the body frames they were placed from (a part modelled in assembly
  // coordinates, 1.7e3 from its frame's origin, placed near the world's: its world points
  // carry the rounding of 1.7e3, and a ball through it read 2e-13 'apart').
  double coord = 0.0;
  for (int side = 0; side < 2; ++side) {
    const Bbox_3& body = m_side[side].h->box();
    const Bbox_3 world = transformed(body, *m_side[side].X);
    for (int k = 0; k < 3; ++k)
      coord = std::max({coord, std::abs(world.min(k)), std::abs(world.max(k)),
                        std::abs(body.min(k)), std::abs(body.max(k)),
                        std::abs(m_side[side].X->translation()[k])});
  }
  m_resolution = 16.0 * std::numeric_limits<double>::epsilon() * std::max(coord, 1e-300);
}

Distance_result Distance_solver::run() {
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  for (auto& s : m_scratch.side) s.clear();
  m_scratch.heap.clear();
  m_scratch.solutions.clear();
  m_scratch.regions.clear();
  m_scratch.proofs.clear();
  m_scratch.bounds.clear();
  for (int side = 0; side < 2; ++side) {
    const Bbox_3& box = m_side[side].h->box();
    m_size[side] =
        Vec3(box.xmax() - box.xmin(), box.ymax() - box.ymin(), box.zmax() - box.zmin()).norm();
    const std::vector<Symmetry>& own = m_side[side].h->symmetries();
    m_scratch.placed[side].resize(own.size());
    m_scratch.along_motion[side].resize(own.size());
    for (std::size_t k = 0; k < own.size(); ++k) {
      m_scratch.placed[side][k] = own[k].placed(*m_side[side].X);
      m_scratch.along_motion[side][k] =
          m_proof.motion_axis.any() && near_symmetry(m_proof.motion_axis, m_scratch.placed[side][k],
                                                   k_near_symmetry * m_size[side]);
    }
  }

  set_resolution();

  Distance_result result;
  if (m_req.cutoff < HUGE_VAL && m_req.cutoff > m_resolution) m_best.distance = m_req.cutoff;  // no witness yet (ea = -1)
  if (m_proof.stationary && m_only[0] >= 0 && m_only[1] >= 0) {
    internal::Known_solution s{m_only[0], m_only[1], Vec4::Zero()};
    for (int k = 0; k < 4; ++k) s.params[k] = (*m_proof.stationary)[k];
    s.given = true;
    m_scratch.solutions.push_back(s);
  }
  auto& heap = m_scratch.heap;
  double dropped = HUGE_VAL;  // smallest bound among pruned and settled pairs
  if (m_starts != nullptr) {
    // Sub-patch pairs of an earlier query whose proofs failed: each boxed anew at these poses,
    // each sub-patch made once.
    std::size_t size = 16;
    while (size < 2 * m_starts->size()) size *= 2;
    for (auto& table : m_scratch.sub_patches) table.assign(size, -1);
    for (const Sub_patch_pair& s : *m_starts) {
      const int na = m_side[0].sub_patch(m_only[0], s.a_lo.data(), s.a_hi.data(), m_scratch.sub_patches[0]);
      const int nb = m_side[1].sub_patch(m_only[1], s.b_lo.data(), s.b_hi.data(), m_scratch.sub_patches[1]);
      const double cutoff = prune_level() - k_prune * tolerance();
      const double L =
          lower_bound(m_side[0].pools->nodes[na], m_side[1].pools->nodes[nb], cutoff);
      if (L >= cutoff) {
        dropped = std::min(dropped, L);
        keep_bound(m_side[0].pools->nodes[na], m_side[1].pools->nodes[nb], L);
        continue;
      }
      if (holds_no_minimum(na, nb, 0) || holds_no_minimum(na, nb, 1)) continue;
      heap.push_back({L, na, nb});
      std::push_heap(heap.begin(), heap.end(), Heap_order());
    }
  } else if (m_only[0] < 0) {
    const int ra = m_side[0].make_from_tree(0, 0);
    const int rb = m_side[1].make_from_tree(0, 0);
    heap.push_back({lower_bound(m_side[0].pools->nodes[ra], m_side[1].pools->nodes[rb], HUGE_VAL),
                    ra, rb});
  } else {
    // The pieces of the two elements, pair by pair.
    const auto& ea = m_side[0].h->elements()[m_only[0]];
    const auto& eb = m_side[1].h->elements()[m_only[1]];
    const int first_b = static_cast<int>(m_side[1].pools->nodes.size());
    for (int q = 0; q < eb.piece_count; ++q)
      m_side[1].make_from_tree(m_side[1].h->leaf_of_piece(eb.first_piece + q), 1);
    for (int p = 0; p < ea.piece_count; ++p) {
      const int na = m_side[0].make_from_tree(m_side[0].h->leaf_of_piece(ea.first_piece + p), 1);
      if (!m_side[0].h->may_hold_trimmed(m_only[0], m_side[0].pools->nodes[na].lo,
                                         m_side[0].pools->nodes[na].hi))
        continue;
      for (int q = 0; q < eb.piece_count; ++q) {
        const int nb = first_b + q;
        if (!m_side[1].h->may_hold_trimmed(m_only[1], m_side[1].pools->nodes[nb].lo,
                                           m_side[1].pools->nodes[nb].hi))
          continue;
        heap.push_back({lower_bound(m_side[0].pools->nodes[na], m_side[1].pools->nodes[nb],
                                    HUGE_VAL),
                        na, nb});
        std::push_heap(heap.begin(), heap.end(), Heap_order());
      }
    }
  }
  bool out_of_budget = false;
  long pops = 0;

  while (!heap.empty()) {
    const Pair_entry top = heap.front();
    // Prune against 0.999 of the tolerance so that rounding in upper - lower cannot push the
    // final gap past it.
    if (top.lower >= prune_level() - k_prune * tolerance()) break;
    if (static_cast<long>(m_side[0].pools->nodes.size() + m_side[1].pools->nodes.size()) >
        m_req.max_nodes) {
      out_of_budget = true;
      break;
    }
    if (m_req.max_seconds > 0.0 && (pops & 63) == 0 &&
        std::chrono::duration<double>(clock::now() - t0).count() > m_req.max_seconds) {
      out_of_budget = true;
      break;
    }
    std::pop_heap(heap.begin(), heap.end(), Heap_order());
    heap.pop_back();
    ++pops;
    const Live_node a = m_side[0].pools->nodes[top.a];
    const Live_node b = m_side[1].pools->nodes[top.b];
    if (a.is_net() && b.is_net()) {
      const double before = m_best.distance;
      corner_candidates(a, b);
      if (m_best.distance < before) polish(a, b);
      // (While proving a cutoff, convexity bounds around a witness above the floor would
      // settle nothing: the pairs there are set aside or split until they clear the cutoff.)
      if (m_req.newton_polish && !m_scratch.solutions.empty() && (!proving() || m_proof.stationary))
        try_certify(a, b);
      // (A pair left here for a meeting keeps its bound: the kept proofs cover the domains.)
      if (top.lower <= m_resolution && m_best.distance > m_resolution &&
          m_intersection_attempts < 64 && (a.depth + b.depth) % 3 == 0) {
        if (try_intersection(a, b)) {
          keep_bound(m_side[0].pools->nodes[top.a], m_side[1].pools->nodes[top.b], top.lower);
          break;
        }
      }
      if (m_best.distance <= m_resolution) {
        keep_bound(m_side[0].pools->nodes[top.a], m_side[1].pools->nodes[top.b], top.lower);
        break;
      }
    }
    const bool sa = m_side[0].splittable(a, m_resolution);
    const bool sb = m_side[1].splittable(b, m_resolution);
    if (!sa && !sb) {
      dropped = std::min(dropped, top.lower);
      keep_bound(m_side[0].pools->nodes[top.a], m_side[1].pools->nodes[top.b], top.lower);
      continue;
    }
    // The larger node is split; but while nothing can be pruned (no witness and no cutoff), a
    // net k_witness_split_ratio times larger than the group of the other tree splits the group,
    // since only two nets give a witness (corner_candidates). Test
    // DistanceFiles.ASheetFarLargerThanAPartFindsAWitnessWithinItsBudget.
    int which = (sa && (!sb || a.size >= b.size)) ? 0 : 1;
    if (!(prune_level() < HUGE_VAL) && a.is_net() != b.is_net()) {
      const int group = a.is_net() ? 1 : 0;
      const double net_size = group == 1 ? a.size : b.size;
      const double group_size = group == 1 ? b.size : a.size;
      if ((group == 0 ? sa : sb) && net_size > k_witness_split_ratio * group_size) which = group;
    }
    int c[2];
    m_side[which].children(which == 0 ? top.a : top.b, c[0], c[1]);
    for (int k = 0; k < 2; ++k) {
      const int ia = which == 0 ? c[k] : top.a;
      const int ib = which == 1 ? c[k] : top.b;
      {  // a piece of a trimmed face whose parameter box misses the trim holds nothing
        const Live_node& child = m_side[which].pools->nodes[c[k]];
        if (child.is_net() &&
            !m_side[which].h->may_hold_trimmed(child.element, child.lo, child.hi))
          continue;
      }
      const double cutoff = prune_level() - k_prune * tolerance();
      Normal_gap normal;
      const double L =
          std::max(top.lower, lower_bound(m_side[0].pools->nodes[ia], m_side[1].pools->nodes[ib],
                                          cutoff, top.lower, &normal));
      if (L < cutoff) {
        if (holds_no_minimum(ia, ib, 0) || holds_no_minimum(ia, ib, 1)) continue;
        heap.push_back({L, ia, ib});
        std::push_heap(heap.begin(), heap.end(), Heap_order());
      } else {
        dropped = std::min(dropped, L);
        keep_bound(m_side[0].pools->nodes[ia], m_side[1].pools->nodes[ib], L, &normal);
      }
    }
  }
  if (m_proof.keep_proofs)
    for (const Pair_entry& e : heap)
      keep_bound(m_side[0].pools->nodes[e.a], m_side[1].pools->nodes[e.b], e.lower);
  // Smallest bound of the pairs pruned, settled or left open (set-aside pairs are in none).
  const double open_lower = heap.empty() ? dropped : std::min(dropped, heap.front().lower);
  // Bounds that reach zero with a witness that does not: look for a common point from the
  // witness, so that bodies that meet are never reported a rounding error apart.
  if (!m_met && m_best.ea >= 0 && m_best.distance > m_resolution) {
    if (std::min(open_lower, m_best.distance) <= m_resolution) {
      const int na = feature(0, m_best.ea).dimension();
      Vec4 x = Vec4::Zero();
      for (int k = 0; k < na; ++k) x[k] = m_best.qa[k];
      for (int k = 0; k < feature(1, m_best.eb).dimension(); ++k) x[na + k] = m_best.qb[k];
      try_intersection(m_best.ea, m_best.eb, x);
    }
  }
  result.pairs_processed = pops;
  fill(result);
  result.uncarried_lower_bound = std::max(0.0, open_lower);
  result.carried_reach = {m_reach[0], m_reach[1]};
  if (m_met || m_best.distance <= m_resolution) {
    // The bodies meet: report exactly zero, never a rounding-level positive number.
    classify_meeting();
    result.distance = result.upper_bound = result.lower_bound = 0.0;
    result.uncarried_lower_bound = 0.0;
    const Vec3 mid = 0.5 * (m_best.pa + m_best.pb);
    result.point_a = result.point_b = mid;
    result.normal = m_meet_normal;
    result.status = m_transversal ? Distance_status::Intersecting
                                             : Distance_status::Touching;
    result.tolerance_used = tolerance();
    return result;
  }
  result.lower_bound = std::max(0.0, std::min(open_lower, m_best.distance));
  result.tolerance_used = tolerance();
  const double gap = result.upper_bound - result.lower_bound;
  if (out_of_budget)
    result.status = Distance_status::Budget_exhausted;
  else if (gap <= result.tolerance_used)
    result.status = Distance_status::Converged;
  else
    result.status = Distance_status::Resolution_limit;
  return result;
}

}  // namespace extremal::internal
