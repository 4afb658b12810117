// What every stage of a body-pair tracker reads (Stage_engine.h): the two prepared bodies, the
// options (fixed at construction), the pair's kind, and this step's inputs (set once a step by
// the engine, read by the stages). No stage writes its results here: each owns them. Not API.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "algorithms/body_pair/Body_pair_options.h"
#include "algorithms/body_pair/Pair_report.h"
#include "algorithms/body_pair/Tracking_model.h"
#include "algorithms/body_pair/internal/Pair_kind.h"

namespace extremal::internal {

class Pair_context {
 public:
  Pair_context(std::shared_ptr<const Tracking_model> a, std::shared_ptr<const Tracking_model> b,
               const Body_pair_options& options);

  const Tracking_model& model(int side) const { return side == 0 ? *model_a : *model_b; }
  const Primitive& primitive(int side, int p) const { return model(side).primitives()[p]; }
  // The larger body's box diagonal (the length rounding and merges scale with).
  double length() const;
  // The broad phase's margin: Body_pair_options::broad_margin, or a fraction of the smaller
  // body (against a point, of the other; Tuning.h).
  double reach_margin() const;
  // The depth search's tolerance at `depth` (Body_pair_options::overlap).
  double depth_tolerance(double depth) const;
  // The least overlap of the two bodies' boxes along the axes of either frame, at `relative`,
  // plus its tolerance: an upper bound on the depth of two solids (a translation that parts the
  // boxes parts them). Made once a step.
  double boxes_bound();
  // Whether both bodies are certified convex (made on first use).
  bool convex();
  // Whether body `side` (0 A, 1 B) is certified convex (made on first use).
  bool convex_body(int side);
  // Whether the distance between primitives pa and pb apart has at most one basin inside
  // their domains, within this step's error budget at distance d: both flat, or one flat and the other
  // on a convex body (a convex function restricted to a plane or a line), each flat within a
  // fraction of the budget (k_flat_budget). A converged tracker on such a pair reads its
  // minimum over the domains' insides (their borders are their edges' pairs).
  bool flat_single_basin(int pa, int pb, double d);
  // flat_single_basin with its stationary point unique and regular (one side a point, or one
  // a convex body's face): Newton's method finds it (Kept_proof_stage::locate_single_basin).
  bool single_basin_locatable(int pa, int pb, double d);

  const std::shared_ptr<const Tracking_model> model_a, model_b;
  const Body_pair_options options;
  const Pair_kind kind;

  // This step's inputs, set by Stage_engine::step and read by the stages.
  struct Step_inputs {
    double t = 0.0, dt = 1e-3;
    const Rigid_pose_3* X_WA = nullptr;
    const Rigid_pose_3* X_WB = nullptr;
    const Twist_3* V_A = nullptr;
    const Twist_3* V_B = nullptr;
    Rigid_pose_3 relative, previous_relative;  // X_AB at this step and the one before
    long steps = 0;                            // steps begun since construction
    Error_budget budget;                       // this step is certified at (Pair_step::budget)
  } now;

 private:
  // Made on first use: the boxes' bound of step m_boxes_bound_at, and whether the bodies are
  // certified convex (-1: not known yet).
  struct {
    double boxes_bound = HUGE_VAL;
    long boxes_bound_at = -1;
    signed char convex = -1;
    signed char convex_body[2] = {-1, -1};
  } m_made;
};

}  // namespace extremal::internal
