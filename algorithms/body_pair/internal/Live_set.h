// The live set of a body-pair tracker: a tracker (or a closed form) per tracked primitive pair
// in reusable slots, found by pair key, stepped once a step with its reading judged
// (Reading_rules), handed across edges and patch sides when its point leaves its primitive,
// and merged with another that reached the same pair. Not API.
#pragma once

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "algorithms/body_pair/internal/Body_pair_support.h"
#include "algorithms/body_pair/internal/Pair_context.h"

namespace extremal::internal {

// How a tracker came to the side of contact it reads (Reading_rules.cpp, judge): a depth
// counts only on a side reached through the contact band.
enum class Provenance : unsigned char {
  Unreached,        // placed, or moved, or handed across, and not come through contact since
  Seeded_apart,     // placed from a solve that found the bodies apart, not read yet
  Behind_sheet,     // seeded apart, and read behind an open sheet ever since
  Through_contact,  // came to its side through the contact band (or placed on a depth pair)
};

// One slot: a tracked primitive pair and what its readings have shown.
struct Live {
  int pa = -1, pb = -1;  // primitives
  bool closed_form = false;  // a mesh triangle against a triangle or the point: no tracker
  bool alive = false;
  bool valid = false;  // the reading holds a pair of the bodies (Reading_rules)
  Reading_rule rejected_by = Reading_rule::None;  // the rule that rejected it, if not valid
  Regime regime = Regime::Apart;  // of the last reading
  long stepped = -1;   // the step it was last stepped in
  Provenance provenance = Provenance::Unreached;
  // It read a depth shallower than the tracked one at the last step (Depth_monitor).
  bool was_shallower = false;
  Extremal_tracker tracker{Feature::point(Vec3::Zero()), Feature::point(Vec3::Zero()), Vec4::Zero()};
  Track_result result;
};

// Slot L was placed from a solve that found the bodies apart (one through contact stays so: its
// side is known).
inline void mark_seeded_apart(Live& L) {
  if (L.provenance != Provenance::Through_contact) L.provenance = Provenance::Seeded_apart;
}

// Its reading would hold but for not having come through contact (a pair seeded inside), in
// front of any sheet: it may be the depth (Depth_monitor).
inline bool holds_unreached(const Live& L) {
  return L.rejected_by == Reading_rule::Depth_not_reached_through_contact &&
         L.provenance != Provenance::Behind_sheet;
}

// Whether slot L's normalised projection errors are within `limit` along every parameter not
// held on a domain bound (one held there keeps the crease's projection error).
bool is_converged_along_free(const Pair_context& context, const Live& L, double limit);
// Whether reading r of features fa and fb, apart, descends into their domains along a
// parameter held on a patch edge (Track_result::on_edge): the distance's derivative along it,
// as its normalised projection error gives it, points inward past `limit`. Such a reading is a
// minimum of the side or corner it is held on, not of the pair: the pair's minimum lies lower
// (test ProbeScenes.ASheetsEdgeHeldOnAPlanesCornerIsNoCertificate).
bool descends_from_edge(const Feature& fa, const Feature& fb, const Track_result& r, double limit);
// Whether slot L's reading is a local minimum of its pair's distance over the two domains:
// converged along its free parameters, and apart not descending from an edge it is held on.
bool at_constrained_minimum(const Pair_context& context, const Live& L, double limit);

class Live_set {
 public:
  explicit Live_set(Pair_context& context);

  // Transitions, merges, and the trackers' corrections (Pair_statistics).
  const Pair_statistics& statistics() const { return m_stats; }

  std::vector<Live>& slots() { return m_live; }
  const std::vector<Live>& slots() const { return m_live; }
  Live& operator[](int k) { return m_live[static_cast<std::size_t>(k)]; }
  const Live& operator[](int k) const { return m_live[static_cast<std::size_t>(k)]; }
  // Counts adds, kills and resets: a stage that changed it leaves it different.
  long generation() const { return m_generation; }

  // A tracker (or closed form) on primitive pair (pa, pb) from parameters; returns its slot.
  int add(int pa, int pb, const Vec4& params);
  void kill(int k);
  void kill_all();
  // The pair's live tracker moved to `params` (another basin), one whose witnesses left the
  // bodies first; -1 if the pair has none.
  int move(int pa, int pb, const Vec4& params);

  // Steps every live slot not yet stepped at this step, with up to three hand-overs each.
  void step_pending();
  // The least distance over the live slots whose readings hold (infinity: none).
  double best() const;
  bool any_valid() const;
  int count() const;
  // Bytes its slots hold (capacities, as Body_pair_options::memory_limit counts them), and
  // those one more add() may take on top (the slots' growth when no slot is free).
  std::size_t bytes() const {
    return m_live.capacity() * sizeof(Live) + m_free.capacity() * sizeof(int) +
           m_keys.capacity() * sizeof(m_keys[0]);
  }
  std::size_t bytes_to_add() const {
    return m_free.empty() && m_live.size() == m_live.capacity()
               ? std::max<std::size_t>(m_live.capacity(), 1) * sizeof(Live)
               : 0;
  }

  // Whether slot L's normalised projection errors are within `limit` along every parameter
  // not held on a domain bound (is_converged_along_free).
  bool is_converged(const Live& L, double limit) const {
    return is_converged_along_free(m_context, L, limit);
  }
  bool at_minimum(const Live& L, double limit) const {
    return at_constrained_minimum(m_context, L, limit);
  }
  // A live slot on (pa, pb) whose witnesses lie on the bodies, at a minimum of its pair
  // (at_constrained_minimum).
  bool tracks_converged(int pa, int pb) const;

  // The live slots' (key, slot), sorted by key then slot; good until the next add or
  // transition: a slot killed or reused since no longer matches its entry (each_live checks),
  // and new slots are not in it.
  void index();
  // Calls f(slot) for each live slot on primitive pair `key` (see pair_key), by the index.
  template <class F>
  void each_live(std::uint64_t key, F f) const;
  // Trackers of one primitive pair whose witnesses coincide: one goes (the one that holds
  // nothing, else the later).
  void merge_duplicates();

 private:
  void step_live(int k);
  // Hands slot k across an edge or side when its point left its primitive; true if it moved.
  bool transition(int k);

  Pair_context& m_context;
  std::vector<Live> m_live;
  std::vector<int> m_free;  // free slots of m_live
  std::vector<std::pair<std::uint64_t, int>> m_keys;  // see index
  long m_generation = 0;
  Pair_statistics m_stats;
};

template <class F>
void Live_set::each_live(std::uint64_t key, F f) const {
  auto e = std::lower_bound(m_keys.begin(), m_keys.end(), std::make_pair(key, -1));
  for (; e != m_keys.end() && e->first == key; ++e) {
    const Live& L = m_live[static_cast<std::size_t>(e->second)];
    if (L.alive && pair_key(L.pa, L.pb) == key) f(e->second);
  }
}

}  // namespace extremal::internal
