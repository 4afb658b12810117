// The candidate stage in use (Candidate_stage.h): a broad phase over the two bodies' boxes, and
// for each candidate pair without a tracker a certified lower bound carried across steps,
// decayed by the relative motion since it was certified and kept up to date from the proofs of
// the pair's restricted solves (re-checked at the current pose; where they fail, only the
// failing sub-patch pairs are solved again). In contact every candidate pair is tracked. Not
// API.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "algorithms/body_pair/internal/Candidate_stage.h"
#include "algorithms/body_pair/internal/Pair_seeding.h"
#include "algorithms/body_pair/internal/Tuning.h"
#include "algorithms/distance/internal/Restricted_solve.h"

namespace extremal::internal {

class Kept_proof_stage final : public Candidate_stage {
 public:
  Kept_proof_stage(Pair_context& context, Pair_solver& solver, Live_set& live,
                   Pair_seeding& seeding);
  ~Kept_proof_stage() override;

  void clear() override;
  void refresh(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB, double reach) override;
  void update(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB, double best) override;
  Apart_certificate certify_apart(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB,
                                  double best) override;
  bool seed_in_contact(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) override;
  void track(int pa, int pb, const Rigid_pose_3& relative) override;
  int size() const override { return static_cast<int>(m_candidates.size()); }
  const Pair_statistics& statistics() const override { return m_stats; }
  bool over_limit() const override { return m_over; }
  // The bytes it holds, as Body_pair_options::memory_limit counts them: the capacities of its
  // vectors and of the live set's slots.
  std::size_t bytes() const;

 private:
  // The poses of a restricted solve whose proofs a candidate keeps: A placed at `a`, and
  // X_AB = `relative`.
  struct Solve_pose {
    Rigid_pose_3 a, relative;
  };
  // A candidate pair, sorted by key (pa << 32 | pb), with a certified lower bound on its
  // distance at the relative pose X_AB it was established at (its box distance when it
  // entered, then the restricted solver's lower bound); the bound is carried between steps and
  // decreased by how far the relative motion since can have brought the pair closer.
  struct Candidate {
    std::uint64_t key = 0;
    double lower = 0.0;
    Rigid_pose_3 at;  // X_AB when `lower` held
    // How far above the tracked minimum its last restricted solve was cut off, when that
    // solve found nothing below the cutoff (0 otherwise): the next one reaches higher.
    double slack = 0.0;
    // When that solve set sub-patch pairs aside (Distance_result::carried_reach): how far B's
    // points may move in A's frame ([0]) and A's in B's ([1]) before `lower` stops holding, and
    // the sides of A's and B's primitive (carried_sides bits) whose neighbours' pairs must stay
    // tracked.
    std::array<double, 2> reach{{HUGE_VAL, HUGE_VAL}};
    Rigid_pose_3 reach_at;  // X_AB the reach counts from (`at`, or where the proofs last held)
    std::array<unsigned, 2> carried{{0u, 0u}};
    // The proofs behind the carried bound: the pairs its restricted solves set aside
    // (m_kept.proofs[proof_begin, + proof_count)) and those they bounded
    // (m_kept.bounds[bound_begin, +
    // bound_count)), each in the world frame of the solve that made it (solves[its index]).
    // When the carried bound or the reach runs out, certify_apart checks them again at the
    // current pose instead of solving again, and solves again only the pairs that fail.
    int proof_begin = 0, proof_count = 0, bound_begin = 0, bound_count = 0;
    // Its kept solves' poses: m_kept.solve_poses[solve_block, + solve_count) (a block of
    // k_kept_solves made on its first kept solve; -1: none). Kept apart from the candidate,
    // which the broad phase sorts, copies and mostly drops untouched.
    int solve_block = -1;
    int solve_count = 0;
    bool tracked = false;  // scratch of mark_tracked: a live slot tracks the pair
    // Scratch of mark_tracked: the least distance of the pair's live trackers whose witnesses
    // lie on the bodies (infinity: none).
    double tracked_distance = HUGE_VAL;
    int tracked_slot = -1;  // the live slot at that distance
    bool contact_seeded = false;  // seed_in_contact gave it a tracker
    // The lower bound of the pair's distance that seed's solve certified, at X_AB = seeded_at
    // (infinity: seeded in contact, or no certificate): while the motion since cannot have
    // closed it, the pair is not seeded again.
    double seeded_lower = HUGE_VAL;
    Rigid_pose_3 seeded_at;
    // Its last restricted solve found the pair's own minimum, at or above the tracked one: a
    // stationary point no proving cutoff above the tracked minimum settles (certify_apart).
    bool holds_own_minimum = false;
    // A tracked pair's watch: the region about its tracked point that its last solve certified
    // convex (has_region). Kept bounds inside it are bounded after motion by that region's
    // convexity, certified again at the current pose about the tracker's point, rather than by
    // their hulls (bounds_now): the watch need not solve again at every step of the motion.
    Parameter_box region;
    bool has_region = false;
    // A pair with one basin (Pair_context::single_basin_locatable): the parameters its last
    // Newton solve ended at, where the next starts.
    Vec4 located = Vec4::Zero();
    bool has_located = false;
    // Its queue entries' generation (older entries are stale), the step it was last checked
    // at, and its entries' keys (carried when the queues are made again over new indices; a
    // candidate never checked is due at once).
    unsigned generation = 0;
    long checked_step = -1;
    bool checked_tracked = false;  // tracked at its last check (certify_apart)
    double bound_key = -HUGE_VAL, reach_key = HUGE_VAL;
  };
  // An entry of a queue of candidates (certify_apart): due once `key` falls below the level its
  // queue is read at.
  struct Queue_entry {
    double key;
    int index;  // into m_candidates
    unsigned generation;
  };
  struct Queue_order {
    bool operator()(const Queue_entry& x, const Queue_entry& y) const { return x.key > y.key; }
  };
  // The relative motion since each of a candidate's kept solves, as motions of B's points with
  // A held (b) or A's with B held (a), in those solves' world frames, and the lengths their
  // rounding scales with; each made on first use.
  class Motions {
   public:
    Motions(const Solve_pose* solves, const Rigid_pose_3& relative)
        : m_solves(solves), m_relative(relative) {}
    const Rigid_pose_3& b(int k);
    const Rigid_pose_3& a(int k);
    double length(int k) {
      b(k);
      return m_length[k];
    }

   private:
    // Made in place on first use (these run for every check: no identities written ahead).
    union Slot {
      Slot() {}
      Rigid_pose_3 pose;
    };
    const Solve_pose* m_solves;  // the candidate's kept solves
    const Rigid_pose_3& m_relative;
    Slot m_b[k_kept_solves], m_a[k_kept_solves];
    double m_length[k_kept_solves];
    unsigned m_made_b = 0, m_made_a = 0;
  };
  struct Kept_proof {
    Gradient_proof proof;
    int solve = 0;  // index into its candidate's solves
  };
  struct Kept_bound {
    Bound_proof proof;
    int solve = 0;
  };

  void broad_phase(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB, double reach);
  // The most bytes one candidate pair may take: its entries in m_candidates and
  // m_next_candidates, in the broad phase's list (twice, for its growth) and in the three
  // queues (queue_capacity()).
  static constexpr std::size_t k_candidate_bytes =
      2 * sizeof(Candidate) + 2 * sizeof(std::pair<std::uint64_t, double>) +
      3 * k_queue_slack * sizeof(Queue_entry);
  // Whether `more` bytes on top of bytes() stay within the memory limit (or there is none).
  bool fits(std::size_t more) const;
  // The candidates of this step do not fit the memory limit: every candidate and kept proof
  // goes, their memory given back, and the trackers but the closest one that holds.
  void go_over_limit();
  // Records bytes() in the statistics' peak.
  void note_bytes();
  // Index of `key` in m_candidates, or -1.
  int find_candidate(std::uint64_t key) const;
  // Whether certify_apart can certify primitive pair (pa, pb) without a tracker: both have
  // global elements and the pair is not a closed form (those always get a tracker).
  bool certifiable(int pa, int pb) const;
  // C's bound becomes `lower` at the current pose, with no kept proofs, reach or carried sides.
  void forget_proofs(Candidate& C, double lower);
  // Queues candidate C, just checked, with `lower` its bound at this step: in m_queues.bound at
  // lower + m_moved (due once the motion since may have brought it below `need`), and while its
  // set-aside proofs hold, in m_queues.reach at m_moved plus their remaining reach.
  void queue(Candidate& C, double lower);
  // The most entries either queue holds: queue() drops the stale ones before it passes this.
  std::size_t queue_capacity() const { return k_queue_slack * m_candidates.size() + 64; }
  // Makes the queues again over the candidates' current indices: each at its carried keys, or
  // every one due at once when `all_due` (their keys no longer hold: seeded in contact, or
  // m_moved started again).
  void requeue_all(bool all_due);
  // Sets Candidate::tracked for the candidates a live slot tracks.
  void mark_tracked();
  // Sides of primitive p of body `side` (0 A, 1 B) shared (within a fraction of tol, Tuning.h)
  // with a neighbour whose pair with `other` is tracked: the crease sides a restricted solve
  // may declare carried.
  unsigned carried_sides(int side, int p, int other, double tol) const;
  // Whether the neighbours across a candidate's carried sides are still tracked.
  bool carriers_tracked(const Candidate& C) const;
  // Whether every set-aside pair of C's last solve still holds its gradient proof at the
  // current relative pose; if so, `reach` gets how far each side may move from here on.
  bool proofs_hold(const Candidate& C, std::array<double, 2>& reach) const;
  // The smallest bound of the pairs C's last solve bounded, re-bounded at the current relative
  // pose (those inside C's carried region by its convexity about C's tracked point, when the
  // hulls do not clear them); stops early once one falls below `need`. -infinity if the solve
  // kept none.
  double bounds_now(const Candidate& C, double need) const;
  // For an untracked pair with one basin (Pair_context::single_basin_locatable): Newton's
  // method from C's last located parameters (or the domains' middles) to the pair's one
  // stationary point over its patches. Its certified bound at this pose: that point's distance
  // (the least over the patches), or infinity where the point lies off the primitives (outside
  // a trim, or held on a patch side) whose borders are all carried by edges, whose pairs are
  // candidates or beyond the broad phase's reach. None when Newton did not converge (the pair
  // is solved). `params` gets the point.
  std::optional<double> locate_single_basin(Candidate& C, int pa, int pb, Vec4& params);
  // C's carried region, doubled about its tracked point while it stays certified convex.
  void grow_region(Candidate& C, const Primitive& A, const Primitive& B);
  // Where C's kept proofs no longer clear `cutoff` at the current pose (a bound re-bounded
  // below it, a set-aside pair whose gradient proof fails or lasts less than `min_reach`):
  // their sub-patch pairs into m_scratch.restarts, the others marked kept
  // (m_scratch.keep_bound, m_scratch.keep_proof)
  // with the lowest bound (`lower`) and reaches (`reach`) they give. False when C is better
  // solved anew: no proofs, as many kept solves as it may hold, or more failing pairs than
  // twice the solve's node budget `max_nodes` (their sub-patches would exhaust it).
  bool plan_partial_solve(const Candidate& C, int element_a, int element_b, double cutoff,
                          double min_reach, int max_nodes, double& lower,
                          std::array<double, 2>& reach);
  // Appends the workspace's proofs of the solve just made at pose `at` to m_kept.proofs and
  // m_kept.bounds as C's, after those of C's earlier proofs a partial solve kept (`partial`;
  // otherwise they are dropped), and drops the ranges of candidates no longer listed when too
  // many are stale.
  void keep_proofs(Candidate& C, const Solve_pose& at, bool partial);
  // C's block, made on first use (which may move the others: no pointer outlives a call).
  Solve_pose* solves_of(Candidate& C);
  const Solve_pose* solves_of(const Candidate& C) const {
    return C.solve_block < 0 ? nullptr : m_kept.solve_poses.data() + C.solve_block;
  }
  // Gives C's block back (a candidate dropped, or replaced without its proofs).
  void release_solves(Candidate& C);

  Pair_context& m_context;
  Pair_solver& m_solver;
  Live_set& m_live;
  Pair_seeding& m_seeding;
  Pair_statistics m_stats;  // its checks, solves and seeds
  bool m_over = false;      // see over_limit()
  std::vector<Candidate> m_candidates, m_next_candidates;
  // The candidates' kept proofs: the pairs their restricted solves set aside and bounded, and
  // the poses of those solves.
  struct {
    std::vector<Kept_proof> proofs;
    std::vector<Kept_bound> bounds;
    // Blocks of k_kept_solves poses (Candidate::solve_block), and the free ones.
    std::vector<Solve_pose> solve_poses;
    std::vector<int> free_solve_blocks;
    // The candidates' proof_count and bound_count summed: the entries of proofs and bounds
    // still read (the rest are stale ranges, compacted away by keep_proofs).
    long proof_total = 0, bound_total = 0;
    std::vector<int> order;  // (keep_proofs' scratch)
  } m_kept;
  // The candidates without a tracker, queued by when the motion may have used up their bound
  // (bound: due once a key less `moved` falls below `need`) or their set-aside proofs' reach
  // (reach: once it falls below 0): a step checks only the due ones. `moved` sums the relative
  // motion's displacement bound (Approach::most) over the steps, up to X_AB = moved_at.
  struct {
    std::vector<Queue_entry> bound, reach;
    bool dirty = true;    // the candidates' indices changed
    bool all_due = true;  // and their keys no longer hold
    double moved = 0.0;
    Rigid_pose_3 moved_at;
  } m_queues;
  // The last broad phase: X_AB there and the reach it was run with.
  struct {
    Rigid_pose_3 relative;
    double reach = -HUGE_VAL;
  } m_broad;
  struct Broad_scratch;
  // Scratch, kept for its capacity: of plan_partial_solve (restarts, keep_proof, keep_bound),
  // of the broad phase (prims, world boxes; its boxes in m_boxes), of certify_apart (queue_kept).
  struct {
    std::vector<Sub_patch_pair> restarts;
    std::vector<unsigned char> keep_proof, keep_bound;
    std::vector<int> prims_a, prims_b;
    std::vector<Bbox_3> world_a, world_b;
    std::vector<Queue_entry> queue_kept;
  } m_scratch;
  std::unique_ptr<Broad_scratch> m_boxes;  // (the broad phase's, Kept_proof_stage.cpp)
};

}  // namespace extremal::internal
