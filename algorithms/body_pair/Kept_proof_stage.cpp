#include "algorithms/body_pair/internal/Kept_proof_stage.h"

#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "algorithms/body_pair/internal/Body_pair_support.h"

namespace extremal::internal {

namespace {

using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, int,
                                                      CGAL::Box_intersection_d::ID_FROM_BOX_ADDRESS>;

}  // namespace

struct Kept_proof_stage::Broad_scratch {
  std::vector<Box> boxes_a, boxes_b;
  std::vector<std::pair<std::uint64_t, double>> found;  // (key, box distance), sorted by key
};

namespace {

// Thrown by the broad phase's box callback once the pairs found pass what the memory limit
// leaves room for (CGAL's box intersection has no other way out).
struct Over_limit {};

template <class T>
std::size_t capacity_bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

template <class T>
void release(std::vector<T>& v) {
  std::vector<T>().swap(v);
}

}  // namespace

std::size_t Kept_proof_stage::bytes() const {
  return capacity_bytes(m_candidates) + capacity_bytes(m_next_candidates) +
         capacity_bytes(m_kept.proofs) + capacity_bytes(m_kept.bounds) + capacity_bytes(m_kept.solve_poses) +
         capacity_bytes(m_kept.free_solve_blocks) + capacity_bytes(m_kept.order) +
         capacity_bytes(m_scratch.restarts) + capacity_bytes(m_scratch.keep_proof) +
         capacity_bytes(m_scratch.keep_bound) + capacity_bytes(m_scratch.prims_a) + capacity_bytes(m_scratch.prims_b) +
         capacity_bytes(m_scratch.world_a) + capacity_bytes(m_scratch.world_b) +
         capacity_bytes(m_boxes->boxes_a) + capacity_bytes(m_boxes->boxes_b) +
         capacity_bytes(m_boxes->found) + capacity_bytes(m_queues.bound) +
         capacity_bytes(m_queues.reach) + capacity_bytes(m_scratch.queue_kept) + m_live.bytes();
}

bool Kept_proof_stage::fits(std::size_t more) const {
  const std::size_t limit = m_context.options.memory_limit;
  return limit == 0 || bytes() + more <= limit;
}

void Kept_proof_stage::note_bytes() { m_stats.memory_bytes = std::max(m_stats.memory_bytes, bytes()); }

void Kept_proof_stage::go_over_limit() {
  m_over = true;
  release(m_candidates);
  release(m_next_candidates);
  release(m_kept.proofs);
  release(m_kept.bounds);
  release(m_kept.solve_poses);
  release(m_kept.free_solve_blocks);
  release(m_kept.order);
  release(m_scratch.restarts);
  release(m_scratch.keep_proof);
  release(m_scratch.keep_bound);
  release(m_queues.bound);
  release(m_queues.reach);
  release(m_scratch.queue_kept);
  release(m_boxes->found);
  m_kept.proof_total = m_kept.bound_total = 0;
  m_queues.dirty = m_queues.all_due = true;
  m_broad.reach = -HUGE_VAL;
  // (The global solver certifies the pair while over: Stage_engine::certify_by_global.)
  int keep = -1;
  for (std::size_t k = 0; k < m_live.slots().size(); ++k) {
    const Live& L = m_live[static_cast<int>(k)];
    if (L.alive && L.valid && (keep < 0 || L.result.distance < m_live[keep].result.distance))
      keep = static_cast<int>(k);
  }
  for (std::size_t k = 0; k < m_live.slots().size(); ++k)
    if (m_live[static_cast<int>(k)].alive && static_cast<int>(k) != keep) m_live.kill(static_cast<int>(k));
}

int Kept_proof_stage::find_candidate(std::uint64_t key) const {
  const auto it = std::lower_bound(m_candidates.begin(), m_candidates.end(), key,
                                   [](const Candidate& c, std::uint64_t k) { return c.key < k; });
  return it != m_candidates.end() && it->key == key ? static_cast<int>(it - m_candidates.begin())
                                                    : -1;
}

void Kept_proof_stage::broad_phase(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB,
                                    double reach) {
  const Tracking_model& A = *m_context.model_a;
  const Tracking_model& B = *m_context.model_b;
  // Cut each body's tree by the other body's world box (inflated by the reach) taken into its
  // frame: what remains is near the other body.
  const Bbox_3 wa = transformed(A.box(), X_WA);
  const Bbox_3 wb = transformed(B.box(), X_WB);
  m_scratch.prims_a.clear();
  m_scratch.prims_b.clear();
  const bool edges_a = !(B.has_mesh() || B.body().is_point);
  const bool edges_b = !(A.has_mesh() || A.body().is_point);
  A.collect(transformed(inflate(wb, reach), X_WA.inverse()), edges_a, m_scratch.prims_a);
  B.collect(transformed(inflate(wa, reach), X_WB.inverse()), edges_b, m_scratch.prims_b);
  // World boxes of the survivors, inflated by half the reach each: boxes that intersect are
  // within the reach along every axis; the exact box distance decides.
  auto& ba = m_boxes->boxes_a;
  auto& bb = m_boxes->boxes_b;
  ba.clear();
  bb.clear();
  m_scratch.world_a.clear();
  m_scratch.world_b.clear();
  for (int p : m_scratch.prims_a) {
    m_scratch.world_a.push_back(transformed(A.primitives()[p].box, X_WA));
    ba.emplace_back(inflate(m_scratch.world_a.back(), 0.5 * reach), static_cast<int>(m_scratch.world_a.size()) - 1);
  }
  for (int p : m_scratch.prims_b) {
    m_scratch.world_b.push_back(transformed(B.primitives()[p].box, X_WB));
    bb.emplace_back(inflate(m_scratch.world_b.back(), 0.5 * reach), static_cast<int>(m_scratch.world_b.size()) - 1);
  }
  const Rigid_pose_3 relative = X_WA.inverse() * X_WB;
  // Sorted as (key, distance) pairs, then made candidates: a candidate is large (its kept
  // solves' poses), and sorting them moved 4% of a step's time in a contact of many pairs.
  auto& found = m_boxes->found;
  found.clear();
  // The most pairs the memory limit leaves room for, beside the proofs and trackers the stage
  // holds (the candidates' vectors are counted per pair, at their most).
  std::size_t most = std::numeric_limits<std::size_t>::max();
  if (const std::size_t limit = m_context.options.memory_limit) {
    const std::size_t held = bytes() - capacity_bytes(m_candidates) -
                             capacity_bytes(m_next_candidates) - capacity_bytes(found) -
                             capacity_bytes(m_queues.bound) - capacity_bytes(m_queues.reach) -
                             capacity_bytes(m_scratch.queue_kept);
    most = held >= limit ? 0 : (limit - held) / k_candidate_bytes;
  }
  try {
    CGAL::box_intersection_d(ba.begin(), ba.end(), bb.begin(), bb.end(),
                             [&](const Box& x, const Box& y) {
                               const int i = x.info(), j = y.info();
                               const double d = box_distance(m_scratch.world_a[i], m_scratch.world_b[j]);
                               if (d > reach) return;
                               if (found.size() >= most) throw Over_limit();
                               found.emplace_back(pair_key(m_scratch.prims_a[i], m_scratch.prims_b[j]), d);
                             });
  } catch (const Over_limit&) {
    ++m_stats.broad_phases;
    go_over_limit();
    return;
  }
  m_over = false;
  std::sort(found.begin(), found.end());  // (keys are distinct)
  m_next_candidates.clear();
  for (const auto& [key, d] : found) {
    Candidate c;
    c.key = key;
    c.lower = d;  // the boxes hold the primitives
    c.at = relative;
    m_next_candidates.push_back(c);
  }
  // Pairs that left: their trackers go. Pairs that entered: their box distance is their bound
  // (check_vacated certifies them apart, seed_in_contact seeds them in contact), but pairs
  // those cannot certify are seeded now. Pairs that stayed keep their carried bound unless the
  // box distance now is at least as high.
  // (By key: in contact every candidate pair has a tracker, and thousands of mesh triangles'
  // pairs made a scan of the trackers per candidate most of a step.)
  m_live.index();
  std::size_t i = 0, j = 0;
  auto drop = [&](std::uint64_t key) { m_live.each_live(key, [&](int k) { m_live.kill(k); }); };
  while (i < m_candidates.size() || j < m_next_candidates.size()) {
    if (j == m_next_candidates.size() ||
        (i < m_candidates.size() && m_candidates[i].key < m_next_candidates[j].key)) {
      release_solves(m_candidates[i]);
      drop(m_candidates[i++].key);
    } else if (i == m_candidates.size() || m_next_candidates[j].key < m_candidates[i].key) {
      const std::uint64_t key = m_next_candidates[j++].key;
      // (A tracker may have arrived by a transition.)
      const int pa = key_a(key), pb = key_b(key);
      if (!certifiable(pa, pb)) {
        bool tracked = false;
        m_live.each_live(key, [&](int) { tracked = true; });
        if (!tracked && fits(m_live.bytes_to_add())) m_seeding.seed_pair(pa, pb, X_WA, X_WB);
      }
    } else {
      // The carried bound (with its pose, reach and carried sides) when it is the higher one;
      // the slack in any case, and so, for a pair seeded in contact whose solve certified it
      // apart, that bound and pose (see seed_in_contact).
      Candidate& next = m_next_candidates[j];
      Candidate& was = m_candidates[i];
      if (was.lower > next.lower) {
        next = was;
      } else {
        release_solves(was);  // (its proofs go with it)
        next.slack = was.slack;
        if (was.seeded_lower < HUGE_VAL) {
          next.contact_seeded = was.contact_seeded;
          next.seeded_lower = was.seeded_lower;
          next.seeded_at = was.seeded_at;
        }
      }
      ++i;
      ++j;
    }
  }
  // Trackers that moved by transitions onto pairs outside the set go too.
  auto by_key = [](const Candidate& c, std::uint64_t k) { return c.key < k; };
  for (std::size_t k = 0; k < m_live.slots().size(); ++k) {
    if (!m_live[k].alive) continue;
    const std::uint64_t key = pair_key(m_live[k].pa, m_live[k].pb);
    const auto it = std::lower_bound(m_next_candidates.begin(), m_next_candidates.end(), key, by_key);
    if (it == m_next_candidates.end() || it->key != key) m_live.kill(static_cast<int>(k));
  }
  m_candidates.swap(m_next_candidates);
  m_kept.proof_total = m_kept.bound_total = 0;
  for (const Candidate& c : m_candidates) {
    m_kept.proof_total += c.proof_count;
    m_kept.bound_total += c.bound_count;
  }
  m_broad.relative = relative;
  m_broad.reach = reach;
  m_queues.dirty = true;
  ++m_stats.broad_phases;
  note_bytes();
  // (The trackers seeded on pairs that cannot be certified count too.)
  if (!fits(0)) go_over_limit();
}

Kept_proof_stage::Kept_proof_stage(Pair_context& context, Pair_solver& solver, Live_set& live,
                                   Pair_seeding& seeding)
    : m_context(context), m_solver(solver), m_live(live), m_seeding(seeding),
      m_boxes(std::make_unique<Broad_scratch>()) {}

Kept_proof_stage::~Kept_proof_stage() = default;

void Kept_proof_stage::clear() {
  m_over = false;
  m_candidates.clear();
  m_queues.dirty = m_queues.all_due = true;
  m_kept.proofs.clear();
  m_kept.bounds.clear();
  m_kept.solve_poses.clear();
  m_kept.free_solve_blocks.clear();
  m_kept.proof_total = m_kept.bound_total = 0;
}

void Kept_proof_stage::refresh(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB, double reach) {
  broad_phase(X_WA, X_WB, reach);
}

void Kept_proof_stage::update(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB, double best) {
  // A set built with reach R holds every pair that was within R then, so every pair within R
  // less the relative motion since: made anew once that falls below |best| plus the margin,
  // reaching farther by a fraction of the margin (k_broad_extra) so as to last.
  const Pair_context& c = m_context;
  const double margin = c.reach_margin();
  const double reach = std::abs(best) + margin;
  // (Over the memory limit, every step tries again: the set may fit now.)
  if (m_over) {
    broad_phase(X_WA, X_WB, reach + k_broad_extra * margin);
    return;
  }
  if (near_pose(c.now.relative, m_broad.relative, c.length())) return;
  const double moved =
      approach_bound(c.model_a->box(), c.model_b->box(), m_broad.relative, c.now.relative).closer;
  if (reach + moved > m_broad.reach) broad_phase(X_WA, X_WB, reach + k_broad_extra * margin);
}

void Kept_proof_stage::track(int pa, int pb, const Rigid_pose_3& relative) {
  const std::uint64_t key = pair_key(pa, pb);
  if (m_over || find_candidate(key) >= 0) return;
  Candidate c;
  c.key = key;
  c.lower = -std::numeric_limits<double>::infinity();  // no bound yet
  c.at = relative;
  m_candidates.insert(std::lower_bound(m_candidates.begin(), m_candidates.end(), key,
                                       [](const Candidate& x, std::uint64_t k) { return x.key < k; }),
                      c);
  m_queues.dirty = true;  // (the indices moved)
}

}  // namespace extremal::internal
