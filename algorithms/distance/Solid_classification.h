// Whether a body is closed (so that it can contain something), cheaply certified convex, and
// the winding number of its faces about a point: the containment tests of the signed distance
// (Penetration_depth.h, whose header comment gives the method).
#pragma once

#include <cmath>
#include <optional>
#include <string>

#include "algorithms/distance/Distance_hierarchy.h"
#include "kernel/Body.h"
#include "kernel/Rigid_pose_3.h"
#include "kernel/Types.h"

namespace extremal {

struct Closedness {
  bool closed = false;
  std::string reason;  // why not (or how it was decided)
};
Closedness body_closedness(const Body& body);

// Cheaply certified convex: a point body, or one untrimmed sphere or ellipsoid face.
bool is_certified_convex(const Body& body);

// A ball: its centre (body frame) and radius.
struct Ball {
  Vec3 centre = Vec3::Zero();
  double radius = 0.0;
};
// The ball a body bounds, when it is one closed untrimmed face of kind "sphere" whose points
// (sampled on a grid, and its control net's box) agree with that ball to k_ball_agreement of its
// radius: distances to it are those to its centre less its radius.
std::optional<Ball> certified_ball(const Body& body);

struct Winding_number {
  double value = 0.0;      // the quadrature's value
  bool determined = false;  // within 0.25 of an integer, and the refinement finished
  long cells = 0;           // quadrature cells
  bool inside() const { return determined && std::abs(value) > 0.5; }
};

// Winding number of the faces of H (placed by X_W) about the world point x_W, which must lie at
// least `clearance` > 0 from them (a certified distance lower bound).
[[nodiscard]] Winding_number winding_number(const Distance_hierarchy& H, const Rigid_pose_3& X_W,
                                            const Vec3& x_W, double clearance);

}  // namespace extremal
