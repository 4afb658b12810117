// The distance between two sets of bodies (Set_distance.h): the minimum over all body pairs,
// whatever order the boxes suggest, with the sets' certificate and the whole set's time budget.
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "algorithms/distance/Set_distance.h"
#include "kernel/Error.h"
#include "kernel/Shapes.h"

namespace extremal {
namespace {

// Bodies with their hierarchies, placed.
struct Set {
  std::vector<std::unique_ptr<Body>> bodies;
  std::vector<std::unique_ptr<Distance_hierarchy>> hierarchies;
  std::vector<Placed_body> placed;

  void add(Body body, const Rigid_pose_3& pose) {
    bodies.push_back(std::make_unique<Body>(std::move(body)));
    hierarchies.push_back(std::make_unique<Distance_hierarchy>(*bodies.back()));
    placed.push_back({bodies.back().get(), hierarchies.back().get(), pose});
  }
};

Rigid_pose_3 at(double x, double y, double z) { return Rigid_pose_3(Mat3::Identity(), Vec3(x, y, z)); }

Rigid_pose_3 turned_about_z(double angle, const Vec3& t) {
  return Rigid_pose_3(Eigen::AngleAxisd(angle, Vec3::UnitZ()).toRotationMatrix(), t);
}

Distance_request tight() {
  Distance_request r;
  r.absolute_tolerance = 1e-9;
  r.relative_tolerance = 0.0;
  return r;
}

// A rod-like ellipsoid along the diagonal of its (large) box, and three balls: one inside that
// box but far from the rod, one outside the box by its corner near the rod's tip, one far away.
struct Rod_and_balls {
  Set a, b;
  Rod_and_balls() {
    a.add(make_ellipsoid_body(5.0, 0.2, 0.2, "rod"), turned_about_z(M_PI / 4, Vec3::Zero()));
    b.add(make_sphere_body(0.5, "inside the box"), at(3.0, -3.0, 0.0));
    b.add(make_sphere_body(0.5, "by the tip"), at(4.6, 4.6, 0.0));
    b.add(make_sphere_body(0.5, "far"), at(100.0, 0.0, 0.0));
  }
};

TEST(SetDistance, TheNearestPairWinsWhateverItsBox) {
  Rod_and_balls s;
  Distance_workspace ws;
  // The truth, pair by pair.
  std::vector<double> each;
  for (const Placed_body& b : s.b.placed)
    each.push_back(extremal_distance(*s.a.placed[0].hierarchy, s.a.placed[0].pose, *b.hierarchy,
                                     b.pose, tight(), ws)
                       .distance);
  ASSERT_LT(each[1], each[0]);  // the ball by the tip is nearer, though its box is not
  ASSERT_GT(box_distance(transformed(s.a.placed[0].hierarchy->box(), s.a.placed[0].pose),
                         transformed(s.b.placed[1].hierarchy->box(), s.b.placed[1].pose)),
            0.0);

  const Set_distance_result r = set_distance(s.a.placed, s.b.placed, tight(), ws);
  EXPECT_EQ(r.body_a, 0);
  EXPECT_EQ(r.body_b, 1);
  EXPECT_NEAR(r.result.distance, each[1], 1e-9);
  EXPECT_EQ(r.result.status, Distance_status::Converged);
  EXPECT_LE(r.result.lower_bound, each[1]);
  EXPECT_LE(r.result.upper_bound - r.result.lower_bound, r.result.tolerance_used);
  // The box-overlapping ball first, then the tip's (its box nearer than the first answer);
  // the far ball's box is beyond: bounded, not queried.
  EXPECT_EQ(r.work.body_pairs_queried, 2);
  EXPECT_EQ(r.work.body_pairs_bounded, 1);
}

TEST(SetDistance, EqualsTheSmallestPairOverRandomSets) {
  const unsigned seed = 20261124;
  SCOPED_TRACE(seed);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Distance_workspace ws;
  for (int trial = 0; trial < 6; ++trial) {
    SCOPED_TRACE(trial);
    Set a, b;
    auto random_pose = [&](double spread) {
      const Vec3 axis = Vec3(u(rng), u(rng), u(rng)).normalized();
      return Rigid_pose_3(Eigen::AngleAxisd(3.0 * u(rng), axis).toRotationMatrix(),
                          spread * Vec3(u(rng), u(rng), u(rng)));
    };
    for (int i = 0; i < 3; ++i) {
      a.add(make_ellipsoid_body(1.0 + 0.5 * i, 0.6, 0.3), random_pose(6.0));
      b.add(i == 1 ? make_torus_body(1.0, 0.25) : make_ellipsoid_body(0.8, 0.5 + 0.2 * i, 0.4),
            random_pose(6.0) * at(8.0, 0.0, 0.0));
    }
    double truth = HUGE_VAL;
    for (const Placed_body& x : a.placed)
      for (const Placed_body& y : b.placed)
        truth = std::min(truth, extremal_distance(*x.hierarchy, x.pose, *y.hierarchy, y.pose,
                                                  tight(), ws)
                                    .distance);
    const Set_distance_result r = set_distance(a.placed, b.placed, tight(), ws);
    ASSERT_TRUE(r.result.status == Distance_status::Converged ||
                r.result.status == Distance_status::Intersecting ||
                r.result.status == Distance_status::Touching);
    EXPECT_NEAR(r.result.distance, truth, 2e-9);
    EXPECT_LE(r.result.lower_bound, truth + 1e-12);
    // The reported pair holds the witness.
    const Placed_body& x = a.placed[static_cast<std::size_t>(r.body_a)];
    const Placed_body& y = b.placed[static_cast<std::size_t>(r.body_b)];
    EXPECT_NEAR(extremal_distance(*x.hierarchy, x.pose, *y.hierarchy, y.pose, tight(), ws).distance,
                r.result.distance, 2e-9);
  }
}

TEST(SetDistance, BodiesThatMeetEndTheSearch) {
  Set a, b;
  a.add(make_sphere_body(1.0), at(0.0, 0.0, 0.0));
  b.add(make_sphere_body(1.0, "apart"), at(0.0, 2.5, 0.0));
  b.add(make_sphere_body(1.0, "crossing"), at(1.5, 0.0, 0.0));
  b.add(make_sphere_body(1.0, "crossing too"), at(-1.5, 0.0, 0.0));
  Distance_workspace ws;
  const Set_distance_result r = set_distance(a.placed, b.placed, tight(), ws);
  EXPECT_EQ(r.result.status, Distance_status::Intersecting);
  EXPECT_EQ(r.result.distance, 0.0);
  EXPECT_EQ(r.result.lower_bound, 0.0);
  EXPECT_EQ(r.body_b, 1);  // the first of the meeting pairs in the sets' order
  EXPECT_EQ(r.work.body_pairs_queried, 1);
}

TEST(SetDistance, ASpentTimeBudgetLeavesTheBoxBounds) {
  Rod_and_balls s;
  Distance_workspace ws;
  const double truth = set_distance(s.a.placed, s.b.placed, tight(), ws).result.distance;
  // A budget spent before the first query (or within it, whichever the clock gives: both
  // leave the ball by the tip unqueried): pairs left unqueried count with their boxes, and the
  // sets are not certified.
  const double tip_boxes = box_distance(transformed(s.a.placed[0].hierarchy->box(), s.a.placed[0].pose),
                                        transformed(s.b.placed[1].hierarchy->box(), s.b.placed[1].pose));
  const Set_distance_result r = set_distance(s.a.placed, s.b.placed, tight(), ws, 1e-300);
  EXPECT_LE(r.work.body_pairs_queried, 1);
  if (r.work.body_pairs_queried == 0) {
    EXPECT_EQ(r.body_a, -1);
    EXPECT_EQ(r.result.element_a, -1);
  }
  EXPECT_EQ(r.result.status, Distance_status::Budget_exhausted);
  EXPECT_LE(r.result.lower_bound, tip_boxes);  // the tip's pair counted by its boxes
  EXPECT_LE(r.result.lower_bound, truth);
}

TEST(SetDistance, TheRequestsCutoffHoldsForTheSets) {
  Rod_and_balls s;
  Distance_workspace ws;
  const double truth = set_distance(s.a.placed, s.b.placed, tight(), ws).result.distance;
  Distance_request below = tight();
  below.cutoff = 0.5 * truth;  // nothing that close: no witness, a lower bound at the cutoff
  const Set_distance_result r = set_distance(s.a.placed, s.b.placed, below, ws);
  EXPECT_EQ(r.body_a, -1);
  EXPECT_EQ(r.result.status, Distance_status::Converged);
  EXPECT_EQ(r.result.upper_bound, below.cutoff);
  EXPECT_GE(r.result.lower_bound, below.cutoff - 1e-9);
  Distance_request above = tight();
  above.cutoff = 2.0 * truth;
  EXPECT_NEAR(set_distance(s.a.placed, s.b.placed, above, ws).result.distance, truth, 1e-9);
}

TEST(SetDistance, RejectsAnEmptySet) {
  Rod_and_balls s;
  Distance_workspace ws;
  EXPECT_THROW((void)set_distance({}, s.b.placed, tight(), ws), Precondition_violation);
  std::vector<Placed_body> missing = s.b.placed;
  missing[1].hierarchy = nullptr;
  EXPECT_THROW((void)set_distance(s.a.placed, missing, tight(), ws), Precondition_violation);
  std::vector<Placed_body> no_body = s.b.placed;
  no_body[0].body = nullptr;
  EXPECT_THROW((void)signed_set_distance(s.a.placed, no_body, Signed_distance_request()),
               Precondition_violation);
}

Signed_distance_request tight_signed() {
  Signed_distance_request r;
  r.absolute_tolerance = 1e-9;
  r.relative_tolerance = 0.0;
  return r;
}

TEST(SignedSetDistance, TheDeepestOverlapWins) {
  Set a, b;
  a.add(make_sphere_body(1.0), at(0.0, 0.0, 0.0));
  a.add(make_sphere_body(1.0), at(10.0, 0.0, 0.0));
  b.add(make_sphere_body(0.5, "apart"), at(10.0, 1.7, 0.0));       // 0.2 from the second
  b.add(make_sphere_body(0.5, "shallow"), at(0.0, -1.4, 0.0));    // 0.1 deep in the first
  b.add(make_sphere_body(0.5, "deep"), at(1.2, 0.0, 0.0));        // 0.3 deep in the first
  const Signed_set_distance_result r = signed_set_distance(a.placed, b.placed, tight_signed());
  EXPECT_EQ(r.body_a, 0);
  EXPECT_EQ(r.body_b, 2);
  EXPECT_NEAR(r.result.distance, -0.3, 1e-9);
  EXPECT_TRUE(r.result.is_certified());
  EXPECT_LE(r.result.lower_bound, -0.3 + 1e-12);
  EXPECT_NE(r.result.overlap, Overlap_kind::None);
}

TEST(SignedSetDistance, ApartItIsTheSetDistance) {
  Rod_and_balls s;
  Distance_workspace ws;
  const Set_distance_result d = set_distance(s.a.placed, s.b.placed, tight(), ws);
  const Signed_set_distance_result r = signed_set_distance(s.a.placed, s.b.placed, tight_signed());
  EXPECT_EQ(r.body_b, d.body_b);
  EXPECT_NEAR(r.result.distance, d.result.distance, 1e-9);
  EXPECT_TRUE(r.result.is_certified());
  EXPECT_EQ(r.result.overlap, Overlap_kind::None);
  // The ball in the rod's box is queried first (its boxes overlap), the tip's with the apart
  // query cut off at that answer; the far ball's box is beyond.
  EXPECT_EQ(r.work.body_pairs_queried, 2);
  EXPECT_EQ(r.work.body_pairs_bounded, 1);
}

TEST(SignedSetDistance, ABodyInsideAnotherWinsOverPairsApart) {
  Set a, b;
  a.add(make_sphere_body(5.0, "shell"), at(0.0, 0.0, 0.0));
  a.add(make_sphere_body(0.5), at(20.0, 0.0, 0.0));
  b.add(make_sphere_body(0.3, "near the small one"), at(21.0, 0.0, 0.0));  // 0.2 apart
  b.add(make_sphere_body(0.3, "inside the shell"), at(3.0, 0.0, 0.0));
  const Signed_set_distance_result r = signed_set_distance(a.placed, b.placed, tight_signed());
  EXPECT_EQ(r.body_a, 0);
  EXPECT_EQ(r.body_b, 1);
  EXPECT_EQ(r.result.overlap, Overlap_kind::B_inside_A);
  // Minus the hulls' depth: B's ball pushed out along +x, 5 - (3 - 0.3).
  EXPECT_NEAR(r.result.distance, -2.3, 1e-9);
  EXPECT_TRUE(r.result.is_certified());
}

TEST(SignedSetDistance, ANestedPairBehindACutoffIsStillFound) {
  // A ball in a torus's hole: apart by 0.5, but its box overlaps the torus's more deeply than a
  // ball near a shell's wall, inside it, overlaps the shell's; so the torus pair is queried
  // first and the nested ball's apart query is cut off at 0.5, below its surfaces' gap 0.7:
  // only the containment test finds it.
  Set a, b;
  a.add(make_sphere_body(5.0, "shell"), at(0.0, 0.0, 0.0));
  a.add(make_torus_body(3.0, 0.5), at(20.0, 0.0, 0.0));
  b.add(make_sphere_body(0.3, "inside the shell"), at(4.0, 0.0, 0.0));
  b.add(make_sphere_body(2.0, "in the hole"), at(20.0, 0.0, 0.0));
  auto bound = [&](int i, int j) {
    return signed_box_bound(transformed(a.placed[i].hierarchy->box(), a.placed[i].pose),
                            transformed(b.placed[j].hierarchy->box(), b.placed[j].pose));
  };
  ASSERT_LT(bound(1, 1), bound(0, 0));
  const Signed_set_distance_result r = signed_set_distance(a.placed, b.placed, tight_signed());
  EXPECT_EQ(r.body_a, 0);
  EXPECT_EQ(r.body_b, 0);
  EXPECT_EQ(r.result.overlap, Overlap_kind::B_inside_A);
  EXPECT_NEAR(r.result.distance, -1.3, 1e-9);  // 5 - (4 - 0.3)
  EXPECT_TRUE(r.result.is_certified());
  EXPECT_EQ(r.work.body_pairs_queried, 2);
  EXPECT_GT(r.work.winding_cells, 0);
}

TEST(SignedSetDistance, ABestWithinTheToleranceCutsNothingOff) {
  // The first pair (boxes overlapping more) is 5e-4 apart, within the tolerance 1e-3; the
  // second overlaps by 0.3. A cutoff at 5e-4 would settle every pair of the second at
  // 5e-4 - 1e-3 < 0 at once and never see its surfaces meet.
  Set a, b;
  a.add(make_sphere_body(1.0), at(0.0, 0.0, 0.0));
  a.add(make_sphere_body(1.0), at(10.0, 0.0, 0.0));
  const double c = 2.0005 / std::sqrt(2.0);
  b.add(make_sphere_body(1.0, "just apart"), at(c, c, 0.0));
  b.add(make_sphere_body(1.0, "overlapping"), at(11.7, 0.0, 0.0));
  Signed_distance_request loose = tight_signed();
  loose.absolute_tolerance = 1e-3;
  const Signed_set_distance_result r = signed_set_distance(a.placed, b.placed, loose);
  EXPECT_EQ(r.body_a, 1);
  EXPECT_EQ(r.body_b, 1);
  EXPECT_NEAR(r.result.distance, -0.3, 1e-3);
  EXPECT_LE(r.result.lower_bound, -0.3 + 1e-12);
  EXPECT_TRUE(r.result.is_certified());
}

TEST(SignedSetDistance, BoxBoundsAreLowerBounds) {
  // Apart, overlapping, one inside the other: the boxes' signed bound is below the truth.
  const Bbox_3 unit(0, 0, 0, 1, 1, 1);
  EXPECT_DOUBLE_EQ(signed_box_bound(unit, Bbox_3(3, 0, 0, 4, 1, 1)), 2.0);
  EXPECT_DOUBLE_EQ(signed_box_bound(unit, Bbox_3(0.75, 0, 0, 2, 1, 1)), -0.25);
  EXPECT_DOUBLE_EQ(signed_box_bound(Bbox_3(-5, -5, -5, 5, 5, 5), Bbox_3(2.7, -0.3, -0.3, 3.3, 0.3, 0.3)),
                   -2.3);
  Set a, b;
  a.add(make_sphere_body(1.0), at(0.0, 0.0, 0.0));
  b.add(make_sphere_body(0.5), at(1.2, 0.3, 0.0));
  const Signed_distance_result s = signed_distance(*a.placed[0].body, a.placed[0].pose,
                                                   *b.placed[0].body, b.placed[0].pose,
                                                   tight_signed());
  EXPECT_LE(signed_box_bound(transformed(a.placed[0].hierarchy->box(), a.placed[0].pose),
                             transformed(b.placed[0].hierarchy->box(), b.placed[0].pose)),
            s.lower_bound);
  // An apart query stopped before it showed the surfaces apart: they may meet, so the signed
  // lower bound falls back on the boxes (0, the apart query's own bound, would be above s).
  Signed_distance_request starved = tight_signed();
  starved.apart.max_nodes = 1;
  starved.apart.newton_polish = false;
  const Signed_distance_result t = signed_distance(*a.placed[0].body, a.placed[0].pose,
                                                   *b.placed[0].body, b.placed[0].pose, starved);
  ASSERT_EQ(t.overlap, Overlap_kind::None);  // the starved query did not see them meet
  EXPECT_FALSE(t.is_certified());
  EXPECT_LE(t.lower_bound, s.upper_bound);
}

}  // namespace
}  // namespace extremal
