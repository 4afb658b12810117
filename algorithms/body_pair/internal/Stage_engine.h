// The engine of a body pair of NURBS faces, curves, points and mesh triangles: named stages, run
// in order by one loop (docs/design.md, "Architecture"):
//   - the live set: an Extremal_tracker (or a closed form, between mesh triangles) on each
//     tracked primitive pair, stepped, its reading judged by the reading rules, handed across
//     edges and patch sides when its point leaves its primitive, merged with another that
//     reached the same pair;
//   - the depth monitor: where the bodies overlap, whether the tracked pair is still the depth;
//   - the candidate stage: the primitive pairs that may hold the minimum (a broad phase over
//     body-frame boxes), and the certificate that those without a tracker hold nothing closer
//     (kept proofs of restricted solves), seeding a tracker where one does;
//   - the certified global solver when no tracker holds a pair, and audits.
// After every stage the loop steps the trackers the stage placed and reads the tracked minimum
// again. The answer is the least reading that holds, with face ids and parameters, or the
// solver's. Not API.
#pragma once

#include <memory>

#include "algorithms/body_pair/internal/Candidate_stage.h"
#include "algorithms/body_pair/internal/Depth_monitor.h"
#include "algorithms/body_pair/internal/Live_set.h"
#include "algorithms/body_pair/internal/Pair_engine.h"
#include "algorithms/body_pair/internal/Pair_seeding.h"
#include "algorithms/body_pair/internal/Pair_solver.h"

namespace extremal::internal {

class Stage_engine final : public Pair_engine {
 public:
  Stage_engine(std::shared_ptr<const Tracking_model> a, std::shared_ptr<const Tracking_model> b,
               const Body_pair_options& options);
  Stage_engine(const Stage_engine&) = delete;
  Stage_engine& operator=(const Stage_engine&) = delete;

  void start(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) override;
  const Pair_answer& step(const Pair_step& step) override;
  double box_bound(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) const override {
    return boxes_apart(*m_context.model_a, X_WA, *m_context.model_b, X_WB);
  }
  void farther(double, const Rigid_pose_3&) override { m_started = false; }
  // The next step starts again (a ball's centre back out of the other body).
  void restart() { m_started = false; }
  void add_statistics(Pair_statistics& s) const override;
  double audit_time_us() const override { return m_notes.audit_us; }

 private:
  // A stage of a step, in the order of k_stages (Stage_engine.cpp).
  using Stage = void (Stage_engine::*)();
  // Steps the trackers the last stage placed (all of them at a step's start) and reads the
  // tracked minimum.
  void step_trackers();
  void monitor_depth();
  void update_candidates();
  void certify_apart();
  // Apart by the trackers while a closed body holds the other: solved as lost, no certificate.
  void check_nested();
  // Over the memory limit (Candidate_stage::over_limit): the global solver's bound is the
  // step's certificate, and its witness seeds a tracker where closer than the tracked one.
  void certify_by_global();
  void solve_where_met();
  // After a solve that found the surfaces meeting: a tracker reading apart is no answer.
  void check_held();
  void seed_in_contact();
  void check_contact_depth();
  void resolve_start_overlap();
  void solve_if_lost();
  void merge_duplicates();
  void audit();
  void solve_if_unheld();
  // A depth first read by a later stage, between bodies not both closed: checked as at the start.
  void check_late_depth();
  // The certified solver seeds again when no tracker holds a pair.
  void solve_lost();
  void make_answer();
  // A pair without an inside (Pair_kind::has_inside): a negative answer is 0 where they meet.
  void unsigned_answer();

  Pair_context m_context;
  Pair_solver m_solver;
  Live_set m_live;
  Pair_seeding m_seeding;
  std::unique_ptr<Candidate_stage> m_candidates;
  Depth_monitor m_depth;
  Pair_answer m_answer;
  // The tracked minimum (infinity: none holds) and the live set's generation it was read at.
  struct {
    double best = HUGE_VAL;
    long seen = -1;
  } m_tracked;
  bool m_started = false;
  // The start's solve found the surfaces crossing: that solve, at this relative pose.
  struct {
    bool pending = false;
    Distance_result solve;
    Rigid_pose_3 relative;
  } m_start;
  // What this step's stages found for the later ones (cleared at each step).
  struct {
    bool candidates = false;         // the candidate stages run (a minimum is tracked)
    bool apart = false;              // and read the bodies apart
    Apart_certificate certificate;   // certify_apart's, this step
    bool seeded_in_contact = false;  // seed_in_contact placed trackers
    double depth_before = 0.0;       // the tracked minimum before them
    // A solve found the surfaces meeting while no tracker holds a depth or contact: the
    // answer is the solver's.
    bool unheld = false;
    bool meets = false;  // a solve since the last check_held found the surfaces meeting
    double audit_us = 0.0;  // time spent in audits
  } m_notes;
  long m_reseeds = 0;  // trackers the global solves re-seeded
  long m_memory_limited = 0;  // steps over the memory limit
};

}  // namespace extremal::internal
