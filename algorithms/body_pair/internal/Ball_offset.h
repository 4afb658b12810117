// A ball tracked as its centre (Body_pair_tracker): a ball's distance to anything, penetration
// included, is its centre's less its radius (Minkowski), so a pair with a ball runs its stages on
// a point body at the ball's centre, two or three parameters fewer for every primitive pair,
// and the report is moved out by the radius. Only against bodies whose inside a point's sign
// tells (closed bodies, points, balls): across an open sheet a ball keeps the side it entered
// by (docs/behaviour.md), which its centre's unsigned distance does not. And only while the
// centre is outside the other body: deeper, the ball's own surface is tracked (the depth
// monitor's rules are the solids'). Test BodyScenes.ABallIsTrackedAsItsCentre. Not API.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "algorithms/body_pair/Body_pair_options.h"
#include "algorithms/body_pair/Pair_report.h"
#include "algorithms/body_pair/Tracking_model.h"
#include "algorithms/pair/Extremal_tracker.h"

namespace extremal::internal {

class Ball_offset {
 public:
  // `centres`: balls may be tracked as their centres (false: never, the bodies as given).
  Ball_offset(std::shared_ptr<const Tracking_model> a, std::shared_ptr<const Tracking_model> b,
              bool centres);
  Ball_offset(const Ball_offset&) = delete;
  Ball_offset& operator=(const Ball_offset&) = delete;

  // Whether either body is tracked as its centre.
  bool any() const { return m_side[0].radius > 0.0 || m_side[1].radius > 0.0; }
  // The bodies as given, and the models the stages run on (a ball's: its centre's point body).
  const std::shared_ptr<const Tracking_model>& given(int side) const { return m_given[side]; }
  const std::vector<Feature>& given_features(int side) const { return m_features[side]; }
  std::shared_ptr<const Tracking_model> inner(int side) const;
  // The sum of the radii tracked as centres.
  double radii() const { return m_side[0].radius + m_side[1].radius; }

  // The inner bodies' pose and twist from a given body's (its centre's point body: the ball's
  // frame moved to its centre).
  void place(int side, const Rigid_pose_3& X_W, const Twist_3& V, Rigid_pose_3& inner_X,
             Twist_3& inner_V) const;
  // The error budget the inner pair is certified at: the given one at a lower bound on this
  // step's distance (the last step's lower bound less how much closer the relative motion since
  // can have brought the bodies), so that an inner certificate is one of the given pair too.
  Error_budget inner_budget(const Error_budget& given, const Rigid_pose_3& X_WA,
                            const Rigid_pose_3& X_WB);
  // The given pair's report from the inner one: the distance less the radii, a ball's witness
  // moved out to its surface along the normal (its parameters on the ball's face by Newton's
  // method from the last step's), the status and lower bound at that distance.
  void report(const Pair_report& inner, const Body_pair_options& given, const Rigid_pose_3& X_WA,
              const Rigid_pose_3& X_WB, Pair_report& out);

 private:
  struct Side {
    double radius = 0.0;  // 0: not a ball
    Vec3 centre = Vec3::Zero();  // body frame
    std::unique_ptr<Body> point;  // at the ball's centre
    std::shared_ptr<const Tracking_model> model;  // of `point`
    // The witness on the ball's face: a point (placed at the witness) against the face.
    Feature at_witness = Feature::point(Vec3::Zero());
    std::unique_ptr<Extremal_tracker> witness;
    bool witness_started = false;
  };
  std::array<Side, 2> m_side;
  std::shared_ptr<const Tracking_model> m_given[2];
  std::vector<Feature> m_features[2];
  // The last report's lower bound on the given pair's distance and the relative pose it held
  // at (-infinity: none).
  double m_last_lower = -HUGE_VAL;
  Rigid_pose_3 m_last_relative;
};

}  // namespace extremal::internal
