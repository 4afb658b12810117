// A cylinder's rim pressed into a flat face: a peg tilted over a plate or a sheet, tumbling on a
// box. The deepest point is on an edge of the cylinder (a cap's rim), where neither surface's
// normal gives the pair's direction: the plate's does, and its witness is the foot of the rim
// point. Every case has a closed form (the rim's lowest point below the face), checked at every
// row.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "algorithms/Body_pair_tracker.h"
#include "algorithms/Penetration_depth.h"
#include "io/Model_reader.h"
#include "kernel/Shapes.h"

namespace extremal {
namespace {

std::string shared_data(const std::string& rel) { return std::string(EXTREMAL_SHARED_DATA) + "/" + rel; }

constexpr double k_radius = 10.0, k_height = 40.0;  // the peg, mm; its origin is its base centre

// The peg turned by `tilt` about x with its base centre at `base`.
Rigid_pose_3 peg_pose(const Vec3& base, double tilt) {
  return Rigid_pose_3(Eigen::AngleAxisd(tilt, Vec3::UnitX()).toRotationMatrix(), base);
}

// Height of the peg's lowest point above the plane z = top, its base at `base`, turned by `tilt`
// (either rim's lowest point: the far one once the axis points below the horizontal).
double lowest_above(const Vec3& base, double tilt, double top) {
  const double rim = k_radius * std::abs(std::sin(tilt));
  return base.z() - top + std::min(-rim, k_height * std::cos(tilt) - rim);
}

// The one-shot solver's common-point search started on the rim: its minimum-norm step pushed
// the cap's radius past the rim, and clamped there it stalled. The bodies read 7e-11 apart,
// 'converged' and certified, with the rim 5.1 deep.
TEST(RimContact, TheOneShotSolverSeesARimCrossingAFace) {
  const io::Model m = io::read_model(shared_data("step/pr2ct.stp"));
  ASSERT_EQ(m.bodies.size(), 1u);
  const Body& box = m.bodies[0];
  const Body peg = make_cylinder_body(k_radius, k_height);
  for (const double z : {197.85, 197.9, 199.0}) {
    const Vec3 base(100.0, 100.0, z);
    const Signed_distance_result r = signed_distance(peg, peg_pose(base, 0.3), box, box.placement);
    EXPECT_TRUE(r.is_certified()) << "z = " << z;
    EXPECT_EQ(r.overlap, Overlap_kind::Surfaces_meet) << "z = " << z;
    EXPECT_NEAR(r.distance, lowest_above(base, 0.3, 200.0), 1e-8) << "z = " << z;
  }
}

}  // namespace
}  // namespace extremal
