// A ball tracked as its centre (an engine of Body_pair_tracker): a ball's distance to anything, penetration
// included, is its centre's less its radius (Minkowski), so a pair with a ball runs its stages on
// a point body at the ball's centre, two or three parameters fewer for every primitive pair,
// and the answer is moved out by the radius. Only against bodies whose inside a point's sign
// tells (closed bodies, points, balls): across an open sheet a ball keeps the side it entered
// by (docs/behaviour.md), which its centre's unsigned distance does not. Inside a closed body
// too: the row is the centre's signed distance less the radius (docs/behaviour.md, "Overlap").
// Tests BodyScenes.ABallIsTrackedAsItsCentre,
// Overlap.ABallInAClosedMeshReadsItsCentresSignedDistanceLessItsRadius. Not API.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "algorithms/body_pair/Body_pair_options.h"
#include "algorithms/body_pair/Tracking_model.h"
#include "algorithms/body_pair/internal/Stage_engine.h"
#include "algorithms/pair/Extremal_tracker.h"

namespace extremal::internal {

class Ball_pair final : public Pair_engine {
 public:
  // Whether either body is a ball this engine tracks as its centre: a certified ball against
  // a body whose inside a point's sign tells (a closed body, a point, a ball).
  static bool takes(const Tracking_model& a, const Tracking_model& b);

  // The models must outlive it.
  Ball_pair(std::shared_ptr<const Tracking_model> a, std::shared_ptr<const Tracking_model> b,
            const Body_pair_options& options);
  Ball_pair(const Ball_pair&) = delete;
  Ball_pair& operator=(const Ball_pair&) = delete;

  void start(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) override;
  // The centre's answer, certified at the given budget, moved out by the radii.
  const Pair_answer& step(const Pair_step& step) override;
  void farther(double box_bound, const Rigid_pose_3& relative) override;
  void add_statistics(Pair_statistics& s) const override;
  double audit_time_us() const override;
  // The boxes of the centres, less the radii: a lower bound on the balls' distance.
  double box_bound(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) const override;

 private:
  struct Side {
    double radius = 0.0;  // 0: not a ball
    Vec3 centre = Vec3::Zero();  // body frame
    std::unique_ptr<Body> point;  // at the ball's centre
    std::shared_ptr<const Tracking_model> model;  // of `point`, or the body as given
    // The witness on the ball's face: a point (placed at the witness) against the face.
    Feature at_witness = Feature::point(Vec3::Zero());
    std::unique_ptr<Extremal_tracker> witness;
    bool witness_started = false;
  };
  static std::array<Side, 2> sides_of(const std::shared_ptr<const Tracking_model> (&given)[2]);
  // The centre's pose and twist from a given body's (the ball's frame moved to its centre).
  void place(int side, const Rigid_pose_3& X_W, const Twist_3& V, Rigid_pose_3& inner_X,
             Twist_3& inner_V) const;
  // The error budget the centre's pair is certified at: the given one at a lower bound on this
  // step's distance (the last step's lower bound less how much closer the relative motion
  // since can have brought the bodies), so that the centre's certificate is the balls' too.
  Error_budget centre_budget(const Error_budget& given, const Rigid_pose_3& X_WA,
                             const Rigid_pose_3& X_WB) const;
  // The given pair's answer from the centre's: the distance less the radii, a ball's witness
  // moved out to its surface along the normal (its parameters on the ball's face by Newton's
  // method from the last step's), the lower bound less the radii.
  void move_out(const Pair_answer& inner, const Pair_step& step);

  std::array<Side, 2> m_side;
  std::shared_ptr<const Tracking_model> m_given[2];
  double m_radii = 0.0;  // the sum of the radii tracked as centres
  Body_pair_options m_options;
  Stage_engine m_centres;  // the pair with each ball as its centre's point
  Pair_answer m_answer;
  // The last answer's lower bound on the given pair's distance and the relative pose it held
  // at (-infinity: none).
  double m_last_lower = -HUGE_VAL;
  Rigid_pose_3 m_last_relative;
};

}  // namespace extremal::internal
