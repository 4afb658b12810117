// Tracks the extremal pair between two bodies made of many primitives (faces, B-rep edges,
// curves, a point, mesh triangles) - ../shared/DESIGN.md section 3:
//   - broad phase: world boxes of the primitives (body-frame hull boxes transformed, never
//     rebuilt), inflated by the current distance plus a margin, paired by
//     CGAL::box_intersection_d after a body-frame tree cut, so the cost follows the near
//     primitives, not the body size; it reaches a little farther than it must and runs again
//     only once the relative motion has used that up;
//   - an Extremal_tracker on each candidate pair that holds the minimum, seeded by the
//     certified global solver restricted to that pair (extremal_distance_between). Apart, the
//     other candidate pairs carry a certified lower bound instead (check_vacated), kept up to
//     date from the proofs of their restricted solves (where those fail, only the failing
//     sub-patch pairs are solved again), and get a tracker when a solve finds them closer than
//     the tracked minimum (../shared/DESIGN.md section 3 has a tracker per
//     candidate pair: measured on bench/compare (c), all but one of those trackers followed
//     pairs that never held the minimum). In contact every candidate pair is tracked;
//   - patch switching: a tracked point that leaves its face across an edge continues on the
//     other side with mapped parameters (face -> edge -> face across B-rep edges, face -> face
//     across geometrically matched patch sides, triangle -> mesh edge -> triangle in meshes),
//     a transition, not a restart; trackers that reach the same pair merge;
//   - triangle-triangle and triangle-point pairs of mesh bodies: exact closed forms;
//   - the body pair's answer: the minimum over trackers whose witnesses lie on the bodies
//     (inside trims and triangles), with face ids and parameters.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "algorithms/pair/Extremal_tracker.h"
#include "algorithms/distance/Global_distance.h"
#include "algorithms/distance/Penetration_depth.h"
#include "algorithms/body_pair/Tracking_model.h"
#include "kernel/Body.h"

namespace extremal {

namespace internal {
struct Sub_patch_pair;
}

enum class Pair_status {
  Tracking,     // apart, tracked
  Contact,      // touching: |distance| within the contact tolerance
  Penetrating,  // distance below minus the contact tolerance
  Boundary,     // apart, the pair on a patch edge or corner
  Farther,      // beyond the threshold: not tracked
  Fallback,     // degenerate geometry: damped step (Pair_report::degeneracy says why)
};
const char* to_string(Pair_status s);

struct Pair_report {
  double time = 0.0;
  double distance = 0.0;  // signed where the geometry has an outward side
  Vec3 point_a = Vec3::Zero(), point_b = Vec3::Zero(), normal = Vec3::Zero();
  // Face index (curves follow the faces, mesh triangles follow them as in the global solver);
  // a witness on a B-rep or mesh edge names a face along it, params mapped onto that face.
  int feature_a = -1, feature_b = -1;
  Vec4 params = Vec4::Zero();
  int edge_a = -1, edge_b = -1;  // B-rep edge (Body::edges) the witness lies on, else -1
  Pair_status status = Pair_status::Tracking;
  Degeneracy degeneracy = Degeneracy::None;
  // No tracker held a pair on the bodies at this step (all seeded this step, or wandering in a
  // deep overlap): the answer is the certified solver's of this step (0 at a common point
  // where the surfaces meet, the hulls' depth where a body lies inside the other).
  bool solved = false;
  int trackers = 0;  // live feature-pair trackers
  // Certified global solves so far (start, audits, re-seeds and check_deep's checks), and the
  // trackers audits and re-seeds seeded.
  int audits = 0, reseeds = 0;
  // Totals since the start: patch transitions (a tracker handed across an edge or side),
  // merges (trackers that reached the same pair), trackers seeded on candidate pairs (entering
  // in contact, found closer than the tracked minimum, or in contact when it began).
  long transitions = 0, merges = 0, seeds = 0;
  int candidates = 0;  // live candidate primitive pairs of the broad phase
  long broad_phases = 0;  // broad phases run since the start
  // Totals since the start: candidate pairs without a tracker checked for a basin closer than
  // the tracked minimum (one per pair and step); the checks whose carried lower bound
  // (decayed by the relative motion since it was certified) could not clear them, which ran
  // the restricted certified solver; and the trackers those solves seeded on a closer basin.
  long vacated_checks = 0, vacated_solves = 0, vacated_seeds = 0;
  // Of those solves, the ones on a face sharing a patch side with a tracked face (a crease:
  // the side declared carried, see Body_pair_tracker::check_vacated).
  long vacated_crease_solves = 0;
  // Of those solves, the ones whose carried bound still cleared the tracked minimum: the
  // neighbours across its carried sides were no longer tracked, or the reach of its set-aside
  // proofs had run out and checking them again at the current pose failed.
  long vacated_reach_solves = 0;
  // Sub-patch nodes those solves made in all (a repeatable measure of their work).
  long vacated_nodes = 0;
  // Of those solves, the ones that solved again only the sub-patch pairs whose kept proofs no
  // longer cleared it (the rest of the pair's domain kept its proofs).
  long vacated_partial_solves = 0;
  // Checks past the reach whose set-aside proofs all still held at the current pose: no solve.
  long vacated_proof_checks = 0;
  // Checks whose carried bound ran out but whose last solve's bounded pairs, re-bounded at the
  // current pose, still cleared the tracked minimum: no solve.
  long vacated_bound_checks = 0;
  // Totals since the start over the trackers' steps: corrections run (Tracker_options), and
  // the steps that ran all of them without converging first.
  long corrections = 0, capped_corrections = 0;
};

struct Body_pair_options {
  // Scenes correct the pair when one step's linearisation falls short (see
  // Tracker_options::corrections).
  Tracker_options tracker = [] {
    Tracker_options o;
    o.corrections = 10;
    return o;
  }();
  double threshold = 0.0;  // > 0: pairs whose boxes are farther apart are not tracked
  // Broad-phase margin added to the current distance (scene units); 0: 2% of the smaller
  // body's box diagonal.
  double broad_margin = 0.0;
  double contact_tolerance = 1e-9;  // |distance| at or below this is contact
  int seed_samples = 16;   // samples per surface direction when seeding (32 per curve)
  // Steps between audits by the certified global solver (0 = never): when the global minimum
  // has moved to another feature pair, a tracker is seeded there.
  int audit_every = 0;
  // A tracked primitive pair is watched for another basin of its own (a rod moved across a
  // ring leaves the ring's near side for its far side, both on one face pair): a basin that
  // comes closer than the tracked one by more than this fraction of its distance (at least the
  // seeding tolerance) gets the pair's tracker. Smaller costs deeper restricted solves near the
  // tracked minimum, which the watch must clear without settling it; 0: not watched.
  double own_basin_gap = 1e-3;
  // The certified solver's request on one candidate primitive pair (seeding a new pair, and
  // checking a pair whose tracker moved on for a closer basin): a start for the tracker, whose
  // corrections converge it, so a looser tolerance and a small node budget bound the cost of
  // pairs with a continuum of equal minima (parallel planar faces).
  Distance_request seeding = [] {
    Distance_request r;
    r.absolute_tolerance = 1e-9;
    r.relative_tolerance = 1e-9;
    r.max_nodes = 3000;
    return r;
  }();
  // Bodies that overlap when a tracker starts or re-seeds (surfaces meet, or one inside the
  // other): the penetration pair of their convex hulls (hull_signed_distance) seeds a tracker
  // that reports the depth. The cells bound the cost where the depth has a continuum of
  // directions (coaxial bodies); the tracker's corrections converge the seed.
  Signed_distance_request overlap = [] {
    Signed_distance_request r;
    r.absolute_tolerance = 1e-9;
    r.relative_tolerance = 1e-9;
    r.max_cells = 4000;
    return r;
  }();
  // The certified solver's request for the start and the audits. Without the bounds about
  // centres and axes of symmetry: with them the start at a ball's pole above a cylinder's cap
  // centre (bench/stress_suite c0_cylinder) lands the tracker's first step 1.1e-6 off, a pole
  // start-up transient not yet mended.
  Distance_request global = [] {
    Distance_request r;
    r.absolute_tolerance = 1e-7;
    r.relative_tolerance = 1e-7;
    r.max_nodes = 50000;
    r.symmetry_bounds = false;
    return r;
  }();
};

class Body_pair_tracker {
 public:
  // The bodies must outlive the tracker.
  Body_pair_tracker(const Body& a, const Body& b, const Body_pair_options& options = {});
  // With prepared models (shared between the pairs of a scene); they must outlive the tracker.
  Body_pair_tracker(std::shared_ptr<const Tracking_model> a, std::shared_ptr<const Tracking_model> b,
                    const Body_pair_options& options = {});
  ~Body_pair_tracker();
  Body_pair_tracker(Body_pair_tracker&&) noexcept;

  // Converged solve at rest at poses X_WA, X_WB: a tracker on the certified global pair, and
  // the broad phase's candidate pairs (in contact, the first step seeds them). Called by the
  // first step if not before.
  void start(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB);

  const Pair_report& step(double t, const Rigid_pose_3& X_WA, const Twist_3& V_A,
                          const Rigid_pose_3& X_WB, const Twist_3& V_B, double dt);

  const std::vector<Feature>& features_a() const { return m_features_a; }
  const std::vector<Feature>& features_b() const { return m_features_b; }
  const Tracking_model& model_a() const { return *m_model_a; }
  const Tracking_model& model_b() const { return *m_model_b; }

 private:
  struct Live {
    int pa = -1, pb = -1;  // primitives
    bool closed_form = false;  // a mesh triangle against a triangle or the point: no tracker
    bool alive = false;
    bool valid = false;  // the witnesses lie on the bodies
    long stepped = -1;   // the step it was last stepped in
    bool through_contact = false;  // it reached its side of contact through the contact band
    // Its reading would hold but for not having come through contact (a pair seeded inside);
    // and it read a depth shallower than the tracked one at the last step (see step()).
    bool holds_unreached = false;
    bool was_shallower = false;
    // Seeded from a solve that found the bodies apart; and it has read the pair behind an open
    // sheet since its first step, never in front (see step_live).
    bool seeded_apart = false;
    bool behind_sheet = false;
    Extremal_tracker tracker{Feature::point(Vec3::Zero()), Feature::point(Vec3::Zero()), Vec4::Zero()};
    Track_result result;
  };
  bool is_farther(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) const;
  // The global solver on the whole pair (Body_pair_options::global), counted as an audit.
  Distance_result global_solve(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB);
  // Seeds a tracker on the pair of global result g when it beats `tracked` by more than its
  // tolerance. Returns true if it seeded.
  bool seed_from(const Distance_result& g, const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB,
                 double tracked);
  // seed_from on a new global solve.
  bool seed_from_global(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB, double tracked);
  // When one body lies inside the other (g apart), or both are convex and g says their
  // surfaces meet: a tracker, through contact, on the penetration pair of their hulls (of a
  // point inside a body: g's pair, its distance from the surface). Keeps
  // the answer of g (or of the depth) for a report that no tracker holds (m_solved). True if
  // it seeded. Non-convex bodies whose surfaces meet: only once the trackers seeded at the
  // common points found no penetration pair (`local_seeds_failed`), and only when each of the
  // hulls' witnesses lies inside the other body (against a tracked depth, one of them).
  // Only when the depth is above `deeper` by more than its tolerance (a tracked pair as deep
  // holds it already).
  // `known`: overlap_of(g) when the caller has it.
  bool seed_overlap(const Distance_result& g, const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB,
                    bool local_seeds_failed, double deeper = -HUGE_VAL,
                    const Overlap_test* known = nullptr);
  // The pair of hull depth h (the closest pair of A and of B moved apart by the depth), as
  // primitives and tracker parameters. False when h's own witnesses face each other across the
  // depth (they are the pair) or that solve fails.
  bool depth_pair(const Signed_distance_result& h, const Rigid_pose_3& X_WA,
                  const Rigid_pose_3& X_WB, int& pa, int& pb, Vec4& params);
  // Moves a penetration seed on pair (pa, pb) (unit `n` from A to B, `depth` < 0) to the most
  // central pair of the same depth when it lies on a continuum of them, on its faces or on
  // faces beside its witnesses.
  void centre_depth_seed(int& pa, int& pb, const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB,
                         const Vec3& n, double depth, Vec4& params) const;
  // Deep inside (the tracked minimum `best` < 0 past the normal form's band): the certified
  // solver says whether the bodies still overlap. Apart, the penetrating trackers go and the
  // certified pair is tracked; inside, where the hulls' depth is the bodies' (convex, or one
  // inside the other), its pair replaces the trackers deeper than it. True if it changed them.
  // `force`: another penetration pair has just read shallower than `best` by more than
  // depth_tolerance(best): checked whatever the depth and the motion (but not two sheets, nor a
  // closed-form pair).
  bool check_deep(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB, double best, bool force);
  // The least overlap of the two bodies' boxes along the axes of either frame, at m_relative,
  // plus its tolerance (depth_tolerance): an upper bound on the depth of two solids (a
  // translation that parts the boxes parts them). Made once a step.
  double boxes_bound();
  // Whether body A (side 0) or B is closed (body_closedness, made on first use).
  bool closed(int side);
  // A tracker on pair (pa, pb) from `params`: the pair's live one moved there (another basin),
  // or a new one with a candidate entry. Returns its slot.
  int place(int pa, int pb, const Vec4& params, const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB);
  // A tracker on a penetration pair found by a solver (counted as a seed).
  void add_inside(int pa, int pb, const Vec4& params, const Rigid_pose_3& X_WA,
                  const Rigid_pose_3& X_WB);
  // Whether both bodies are certified convex (made on first use).
  bool convex();
  // The depth search's tolerance at `depth` (Body_pair_options::overlap).
  double depth_tolerance(double depth) const;
  // m_solved from a solver's witness pair.
  void keep_solved(double distance, const Vec3& point_a, const Vec3& point_b, const Vec3& normal,
                   Element_kind kind_a, int element_a, const std::array<double, 2>& params_a,
                   Element_kind kind_b, int element_b, const std::array<double, 2>& params_b);
  void broad_phase(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB, double reach);
  // Whether check_vacated can certify primitive pair (pa, pb) without a tracker: both have
  // global elements and the pair is not a closed form (those always get a tracker).
  bool certifiable(int pa, int pb) const;
  // Seeds candidate pairs without a tracker that hold a pair closer than `best`.
  // True if it certified a pair whose surfaces meet (the bodies are not apart after all).
  bool check_vacated(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB, double best);
  // In contact (check_vacated does not run): seeds the candidate pairs without a tracker once
  // (entering pairs get none from the broad phase), and a pair seeded apart again once the
  // motion may have closed the gap its seed's solve certified. True if it seeded.
  bool seed_in_contact(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB);
  // Sets Candidate::tracked for the candidates a live slot tracks.
  void mark_tracked();
  // A tracker (or closed form) on primitive pair (pa, pb) from parameters at time t; returns
  // its slot.
  int add_live(int pa, int pb, const Vec4& params);
  // Seeds pair (pa, pb) from the global solver restricted to it (or its closed form). Returns
  // that solve's certified lower bound on the pair's distance (-infinity without one).
  double seed_pair(int pa, int pb, const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB);
  // Steps slot k at time t (evaluates the closed form), setting its validity.
  void step_live(int k);
  // Whether live tracker k's reading holds a pair of the bodies (Live::valid), and the flags it
  // keeps (through_contact, behind_sheet); `first`: its first step (Body_pair_validity.cpp).
  void judge(int k, bool first);
  // Steps every live slot not yet stepped at this step, with up to three hand-overs each.
  void step_pending();
  // m_live_keys: the live slots' (key, slot), sorted; rebuilt by each user (broad_phase,
  // merge_duplicates), good until the next add_live or transition: a slot killed or reused since
  // no longer matches its entry (the lookups below check), and new slots are not in it.
  void index_live();
  // Calls f(slot) for each live slot on primitive pair `key` (see pair_key), by m_live_keys.
  template <class F>
  void each_live(std::uint64_t key, F f) const;
  // Replaces a seed on a patch side by an interior pair at the same distance, if there is one.
  void prefer_central(int pa, int pb, const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB,
                      Vec4& params) const;
  // Hands slot k across an edge or side when its point left its primitive; true if it moved.
  bool transition(int k);
  void merge_duplicates();
  void kill(int k);
  void fill_report();
  double reach_margin() const;

  std::shared_ptr<const Tracking_model> m_model_a, m_model_b;
  Body_pair_options m_options;
  std::vector<Feature> m_features_a, m_features_b;
  std::vector<Live> m_live;
  std::vector<int> m_free;  // free slots of m_live
  // The poses of a restricted solve whose proofs a candidate keeps: A placed at `a`, and
  // X_AB = `relative`.
  struct Solve_pose {
    Rigid_pose_3 a, relative;
  };
  // A candidate keeps the proofs of at most this many solves (a partial solve adds one); past
  // it, the pair is solved anew.
  static constexpr int k_kept_solves = 8;
  // Broad phase: candidate pairs, sorted by key (pa << 32 | pb), each with a certified lower
  // bound on its distance at the relative pose X_AB it was established at (its box distance
  // when it entered, then the restricted solver's lower bound); the bound is carried between
  // steps and decreased by how far the relative motion since can have brought the pair closer.
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
    // (m_proofs[proof_begin, + proof_count)) and those they bounded (m_bounds[bound_begin, +
    // bound_count)), each in the world frame of the solve that made it (solves[its index]).
    // When the carried bound or the reach runs out, check_vacated checks them again at the
    // current pose instead of solving again, and solves again only the pairs that fail.
    int proof_begin = 0, proof_count = 0, bound_begin = 0, bound_count = 0;
    // Its kept solves' poses: m_solve_poses[solve_block, + solve_count) (a block of
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
    // stationary point no proving cutoff above the tracked minimum settles (check_vacated).
    bool holds_own_minimum = false;
  };
  std::vector<Candidate> m_candidates, m_next_candidates;
  // Index of `key` in m_candidates, or -1.
  int find_candidate(std::uint64_t key) const;
  // Whether slot L's normalised projection errors are within `limit` along every parameter
  // not held on a domain bound.
  bool is_converged(const Live& L, double limit) const;
  // A live slot on (pa, pb) whose witnesses lie on the bodies, converged.
  bool tracks_converged(int pa, int pb) const;
  // Sides of primitive p of body `side` (0 A, 1 B) shared (within tol / 4) with a neighbour
  // whose pair with `other` is tracked: the crease sides a restricted solve may declare carried.
  unsigned carried_sides(int side, int p, int other, double tol) const;
  // Whether the neighbours across a candidate's carried sides are still tracked.
  bool carriers_tracked(const Candidate& C) const;
  // Whether every set-aside pair of C's last solve still holds its gradient proof at the
  // current relative pose; if so, `reach` gets how far each side may move from here on.
  bool proofs_hold(const Candidate& C, std::array<double, 2>& reach) const;
  // The smallest bound of the pairs C's last solve bounded, re-bounded at the current relative
  // pose; stops early once one falls below `need`. -infinity if the solve kept none.
  double bounds_now(const Candidate& C, double need) const;
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
  // Where C's kept proofs no longer clear `cutoff` at the current pose (a bound re-bounded
  // below it, a set-aside pair whose gradient proof fails or lasts less than `min_reach`):
  // their sub-patch pairs into m_restarts, the others marked kept (m_keep_bound, m_keep_proof)
  // with the lowest bound (`lower`) and reaches (`reach`) they give. False when C is better
  // solved anew: no proofs, as many kept solves as it may hold, or more failing pairs than
  // twice the solve's node budget `max_nodes` (their sub-patches would exhaust it).
  bool plan_partial_solve(const Candidate& C, int element_a, int element_b, double cutoff,
                          double min_reach, int max_nodes, double& lower,
                          std::array<double, 2>& reach);
  // Appends the workspace's proofs of the solve just made at pose `at` to m_proofs and
  // m_bounds as C's, after those of C's earlier proofs a partial solve kept (`partial`;
  // otherwise they are dropped), and drops the ranges of candidates no longer listed when too
  // many are stale.
  void keep_proofs(Candidate& C, const Solve_pose& at, bool partial);
  struct Kept_proof {
    Gradient_proof proof;
    int solve = 0;  // index into its candidate's solves
  };
  struct Kept_bound {
    Bound_proof proof;
    int solve = 0;
  };
  std::vector<Kept_proof> m_proofs;
  std::vector<Kept_bound> m_bounds;
  // Blocks of k_kept_solves poses (Candidate::solve_block), and the free ones.
  std::vector<Solve_pose> m_solve_poses;
  std::vector<int> m_free_solve_blocks;
  // C's block, made on first use (which may move the others: no pointer outlives a call).
  Solve_pose* solves_of(Candidate& C);
  const Solve_pose* solves_of(const Candidate& C) const {
    return C.solve_block < 0 ? nullptr : m_solve_poses.data() + C.solve_block;
  }
  // Gives C's block back (a candidate dropped, or replaced without its proofs).
  void release_solves(Candidate& C);
  // The candidates' proof_count and bound_count summed: the entries of m_proofs and m_bounds
  // still read (the rest are stale ranges, compacted away by keep_proofs).
  long m_kept_proof_total = 0, m_kept_bound_total = 0;
  std::vector<int> m_order;  // scratch of keep_proofs
  std::vector<std::pair<std::uint64_t, int>> m_live_keys;  // see index_live
  // Scratch of plan_partial_solve.
  std::vector<internal::Sub_patch_pair> m_restarts;
  std::vector<unsigned char> m_keep_proof, m_keep_bound;
  std::vector<int> m_prims_a, m_prims_b;
  std::vector<Bbox_3> m_world_a, m_world_b;
  struct Broad_scratch;
  std::unique_ptr<Broad_scratch> m_scratch;
  Distance_workspace m_workspace;
  bool m_started = false;
  bool m_have_pose = false;
  Rigid_pose_3 m_last_A, m_last_B;  // poses of the last step
  Rigid_pose_3 m_last_relative;     // X_AB at the last broad phase
  double m_broad_reach = -HUGE_VAL;  // the reach it was run with
  Rigid_pose_3 m_relative, m_previous_relative;  // X_AB at this step and the one before
  // The current step's inputs, for step_live and transition.
  double m_t = 0.0, m_dt = 1e-3;
  const Rigid_pose_3* m_XA = nullptr;
  const Rigid_pose_3* m_XB = nullptr;
  const Twist_3* m_VA = nullptr;
  const Twist_3* m_VB = nullptr;
  long m_steps = 0;
  Pair_report m_report;
  // The last answer of the solver (start or re-seed), reported at its step when no tracker
  // holds: the report's fields.
  struct Solved {
    double distance = 0.0;
    Vec3 point_a = Vec3::Zero(), point_b = Vec3::Zero(), normal = Vec3::Zero();
    int pa = -1, pb = -1;
    Vec4 params = Vec4::Zero();
    long step = -1;  // m_steps when it was made
  } m_solved;
  // closed() of each, and whether both are certified convex, made on first use.
  signed char m_closed_a = -1, m_closed_b = -1, m_convex = -1;
  double m_deep_checked = HUGE_VAL;  // the tracked minimum at check_deep's last check
  Rigid_pose_3 m_deep_at;             // and X_AB there
  double m_boxes_bound = HUGE_VAL;    // boxes_bound's value
  long m_boxes_bound_at = -1;         // and the step it was made in
  // This step's solve found the surfaces meeting (check_vacated, or a lost step's solve) and
  // still no tracker holds a depth or contact: the report is the solver's (m_solved).
  bool m_apart_unheld = false;
  bool m_meets_at_start = false;  // the start's solve found the surfaces crossing: this one,
  Distance_result m_start_solve;  // at this relative pose
  Rigid_pose_3 m_start_relative;
};

// The features of a body: its faces, then its curves; a point body is its origin.
std::vector<Feature> features_of(const Body& body);

}  // namespace extremal
