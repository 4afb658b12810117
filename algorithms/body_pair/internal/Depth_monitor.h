// The depth monitor of a body-pair tracker: where the bodies overlap, it seeds the depth of
// bodies that start or are found overlapping (one inside the other, convex, or where the
// trackers at the common points find nothing), and checks deep inside whether the tracked pair
// is still the depth (a saddle of the distance goes on existing after it stops being one). Not
// API.
#pragma once

#include "algorithms/body_pair/internal/Pair_answer.h"
#include "algorithms/body_pair/internal/Pair_seeding.h"
#include "algorithms/body_pair/internal/Pair_solver.h"
#include "algorithms/distance/Penetration_depth.h"

namespace extremal::internal {

// The certified solver's last answer the monitor kept (a global solve's, or a hulls' depth):
// reported at its step when no tracker holds a pair.
struct Solved {
  double distance = 0.0;
  double lower_bound = -HUGE_VAL;  // certified (the solver's): at most the true distance
  Vec3 point_a = Vec3::Zero(), point_b = Vec3::Zero(), normal = Vec3::Zero();
  int pa = -1, pb = -1;  // primitives
  Vec4 params = Vec4::Zero();
  long step = -1;  // Pair_context::steps when it was made
};

class Depth_monitor {
 public:
  Depth_monitor(Pair_context& context, Pair_solver& solver, Live_set& live, Pair_seeding& seeding)
      : m_context(context), m_solver(solver), m_live(live), m_seeding(seeding) {}

  // The last answer of the certified solver it kept (seed_overlap, check).
  const Solved& solved() const { return m_solved; }
  // Trackers it seeded (Pair_statistics::seeds).
  long seeds() const { return m_seeds; }

  // Forgets the last check and the side entered by (the tracker starts again).
  void reset() {
    m_checked.value = HUGE_VAL;
    m_sheet_side = Vec3::Zero();
    m_meet.pa = -1;
    m_meet.at_valid = false;
  }
  // After each step's answer: a solid against an open body keeps the side it is on while they
  // are apart or in contact (the answer's normal, in A's frame), the side it enters by.
  void note_answer(const Pair_answer& r, const Rigid_pose_3& X_WA);
  // After the trackers stepped, with the tracked minimum `best`: whether a penetration pair
  // has just become shallower than `best` by more than the depth tolerance (held, or held but
  // for not having come through contact: it may be the depth now); once per crossing.
  bool shallower_pair(double best);
  // Deep inside (`best` < 0 past the normal form's band, or `force`): the certified solver
  // says whether the bodies still overlap. Apart, the penetrating trackers go and the certified
  // pair is tracked; inside, where the hulls' depth is the bodies' (convex, or one inside the
  // other), its pair replaces the trackers deeper than it. True if it changed them. Not
  // inside (`best` at or above minus the contact tolerance): forgets the last check.
  bool check(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB, double best, bool force);
  // When one body lies inside the other (g apart), or both are convex and g says their
  // surfaces meet: a tracker, through contact, on the penetration pair of their hulls (of a
  // point inside a body: g's pair, its distance from the surface). Keeps the answer of g (or
  // of the depth) for a report that no tracker holds. True if it seeded. Non-convex bodies
  // whose surfaces meet: only once the trackers seeded at the common points found no
  // penetration pair (`local_seeds_failed`), and only when each of the hulls' witnesses lies
  // inside the other body (against a tracked depth, one of them). Only when the depth is above
  // `deeper` by more than its tolerance (a tracked pair as deep holds it already). `known`:
  // overlap_of(g) when the caller has it.
  bool seed_overlap(const Distance_result& g, const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB,
                    bool local_seeds_failed, double deeper = -HUGE_VAL,
                    const Overlap_test* known = nullptr);

 private:
  // The pair of hull depth h (the closest pair of A and of B moved apart by the depth), as
  // primitives and tracker parameters. False when h's own witnesses face each other across the
  // depth (they are the pair) or that solve fails.
  bool depth_pair(const Signed_distance_result& h, const Rigid_pose_3& X_WA,
                  const Rigid_pose_3& X_WB, int& pa, int& pb, Vec4& params);
  // Bodies not both closed (or points) overlap only while their surfaces meet, or a closed one
  // holds part of the other: whether they still do at this step (a common point found again
  // from the last one, else the certified solve). Apart, the penetrating trackers go and the
  // certified pair is tracked (`seeded`). Once per relative pose.
  bool open_pair_overlaps(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB, bool& seeded);
  // The penetrating trackers deeper than `above` (valid or not: they may come back), but not
  // the ones just placed (not stepped yet), go.
  void drop_inside(double above);
  // Moves a penetration seed on pair (pa, pb) (unit `n` from A to B, `depth` < 0) to the most
  // central pair of the same depth when it lies on a continuum of them, on its faces or on
  // faces beside its witnesses.
  void centre_depth_seed(int& pa, int& pb, const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB,
                         const Vec3& n, double depth, Vec4& params) const;

  // m_solved from a solver's witness pair.
  template <class Result>
  void keep_solved(const Result& r, double sign = 1.0);

  Pair_context& m_context;
  Pair_solver& m_solver;
  Live_set& m_live;
  Pair_seeding& m_seeding;
  Solved m_solved;
  long m_seeds = 0;
  // The tracked minimum at the last check, and X_AB there.
  struct {
    double value = HUGE_VAL;
    Rigid_pose_3 at;
  } m_checked;
  // A solid against an open body: the normal of the last report that read them apart or in
  // contact, in A's frame (zero: none since the start).
  Vec3 m_sheet_side = Vec3::Zero();
  // The last common point of the surfaces found (primitives and parameters; pa < 0: none), and
  // the relative pose open_pair_overlaps last decided at (at_valid) and what it decided (meets).
  struct {
    int pa = -1, pb = -1;
    Vec4 params = Vec4::Zero();
    Rigid_pose_3 at;
    bool at_valid = false, meets = false;
  } m_meet;
};

}  // namespace extremal::internal
