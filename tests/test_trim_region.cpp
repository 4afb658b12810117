// Point-in-trimmed-face test (kernel/Trim_region.h): exact answers on loops with known geometry,
// the On_boundary band, orientation independence, holes, open loops.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <random>

#include "kernel/Body.h"
#include "kernel/Shapes.h"
#include "kernel/Trim_region.h"

namespace extremal {
namespace {

std::uint64_t seed() {
  const char* env = std::getenv("EXTREMAL_SEED");
  return env && *env ? std::strtoull(env, nullptr, 0) : 20260917ULL;
}

Nurbs_curve_3 segment(double u0, double v0, double u1, double v1) {
  return Nurbs_curve_3(1, {Point_3(u0, v0, 0), Point_3(u1, v1, 0)}, {0, 0, 1, 1});
}

// Rational quadratic full circle in the (u, v) plane, 9 poles (exact).
Nurbs_curve_3 circle(double cu, double cv, double r) {
  const Nurbs_curve_3 c = make_circle(r);
  std::vector<Point_3> poles;
  for (const auto& p : c.poles()) poles.emplace_back(p.x() + cu, p.y() + cv, 0.0);
  return Nurbs_curve_3(c.degree(), poles, c.knots(), c.weights());
}

Trim_loop square_loop(double lo, double hi, bool ccw) {
  Trim_loop l;
  if (ccw) {
    l.curves.push_back({segment(lo, lo, hi, lo)});
    l.curves.push_back({segment(hi, lo, hi, hi)});
    l.curves.push_back({segment(hi, hi, lo, hi)});
    l.curves.push_back({segment(lo, hi, lo, lo)});
  } else {
    l.curves.push_back({segment(lo, lo, lo, hi)});
    l.curves.push_back({segment(lo, hi, hi, hi)});
    l.curves.push_back({segment(hi, hi, hi, lo)});
    l.curves.push_back({segment(hi, lo, lo, lo)});
  }
  return l;
}

TEST(TrimRegion, UntrimmedIsInsideEverywhere) {
  Trim_region r;
  EXPECT_FALSE(r.is_trimmed());
  EXPECT_EQ(r.locate(0.3, 0.7), Trim_location::Inside);
  EXPECT_EQ(r.locate(1e9, -1e9), Trim_location::Inside);
}

TEST(TrimRegion, SquareWithCircularHoleMatchesGeometry) {
  const std::uint64_t s = seed();
  std::cout << "[   SEED   ] EXTREMAL_SEED=" << s << std::endl;
  SCOPED_TRACE(::testing::Message() << "rerun with EXTREMAL_SEED=" << s);
  std::mt19937_64 rng(s);
  for (bool ccw : {true, false}) {
    std::vector<Trim_loop> loops{square_loop(0.0, 1.0, ccw)};
    Trim_loop hole;
    hole.is_outer = false;
    hole.curves.push_back({circle(0.5, 0.5, 0.25), -1, ccw});
    loops.push_back(hole);
    const Trim_region region(loops, 1e-6);
    ASSERT_TRUE(region.is_trimmed());
    EXPECT_TRUE(region.is_closed());
    std::uniform_real_distribution<double> U(-0.2, 1.2);
    int inside = 0, boundary = 0, outside = 0;
    for (int k = 0; k < 200000; ++k) {
      const double u = U(rng), v = U(rng);
      const double dr = std::hypot(u - 0.5, v - 0.5) - 0.25;
      const double dsq = std::max(std::abs(u - 0.5), std::abs(v - 0.5)) - 0.5;
      const double dist = std::min(std::abs(dr), std::abs(dsq));
      const bool truth = dsq < 0 && dr > 0;
      const Trim_location loc = region.locate(u, v);
      // On_boundary reaches 1.5 tolerances from the exact curve (the band around a polyline
      // within half a tolerance of it).
      if (dist > 1.5 * region.tolerance()) {
        ASSERT_EQ(loc, truth ? Trim_location::Inside : Trim_location::Outside)
            << "(" << u << ", " << v << ")";
      } else if (loc != Trim_location::On_boundary) {
        // Inside the band but not reported On_boundary: still must be right.
        ASSERT_EQ(loc == Trim_location::Inside, truth) << "(" << u << ", " << v << ")";
      }
      if (dist < 0.5 * region.tolerance()) {
        ASSERT_EQ(loc, Trim_location::On_boundary) << "(" << u << ", " << v << ")";
      }
      inside += loc == Trim_location::Inside;
      boundary += loc == Trim_location::On_boundary;
      outside += loc == Trim_location::Outside;
    }
    EXPECT_GT(inside, 0);
    EXPECT_GT(outside, 0);
  }
}

// Sixteen circular holes in a square: slabs that hold many segments, and boxes: box_outside
// must never claim a box that holds a point of the face, and must claim boxes well inside a
// hole or beyond the square.
TEST(TrimRegion, ManyHolesClassifyPointsAndBoxes) {
  const std::uint64_t s = seed();
  SCOPED_TRACE(::testing::Message() << "rerun with EXTREMAL_SEED=" << s);
  std::mt19937_64 rng(s);
  std::vector<Trim_loop> loops{square_loop(0.0, 1.0, true)};
  const double r = 0.08;
  auto centre = [](int i) { return 0.125 + 0.25 * i; };
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      Trim_loop hole;
      hole.is_outer = false;
      hole.curves.push_back({circle(centre(i), centre(j), r), -1, (i + j) % 2 == 0});
      loops.push_back(hole);
    }
  const Trim_region region(loops, 1e-6);
  ASSERT_GT(region.number_of_segments(), 200u);
  // Signed distance to the face's boundary: positive inside the face.
  auto depth = [&](double u, double v) {
    double d = 0.5 - std::max(std::abs(u - 0.5), std::abs(v - 0.5));
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) d = std::min(d, std::hypot(u - centre(i), v - centre(j)) - r);
    return d;
  };
  std::uniform_real_distribution<double> U(-0.1, 1.1);
  for (int k = 0; k < 100000; ++k) {
    const double u = U(rng), v = U(rng);
    const double d = depth(u, v);
    const Trim_location loc = region.locate(u, v);
    // The band is the tolerance around a polyline within half of it of the circles.
    if (loc != Trim_location::On_boundary) {
      ASSERT_EQ(loc, d > 0 ? Trim_location::Inside : Trim_location::Outside)
          << "(" << u << ", " << v << ")";
    } else {
      ASSERT_LE(std::abs(d), 1.5 * region.tolerance()) << "(" << u << ", " << v << ")";
    }
    if (std::abs(d) < 0.5 * region.tolerance()) {
      ASSERT_EQ(loc, Trim_location::On_boundary) << "(" << u << ", " << v << ")";
    }
  }
  std::uniform_real_distribution<double> W(0.0, 0.06);
  int claimed = 0;
  for (int k = 0; k < 20000; ++k) {
    const double u0 = U(rng), v0 = U(rng), u1 = u0 + W(rng), v1 = v0 + W(rng);
    const bool outside = region.box_outside(u0, v0, u1, v1);
    if (!outside) continue;
    ++claimed;
    // No sampled point of a claimed box lies on the face (where depth > 0).
    double most = -HUGE_VAL;
    for (int a = 0; a <= 8; ++a)
      for (int b = 0; b <= 8; ++b)
        most = std::max(most, depth(u0 + (u1 - u0) * a / 8, v0 + (v1 - v0) * b / 8));
    ASSERT_LT(most, 0.0) << "box at (" << u0 << ", " << v0 << ") holds a face point";
  }
  EXPECT_GT(claimed, 1000);
  // Well inside a hole, and beyond the square.
  EXPECT_TRUE(region.box_outside(centre(1) - 0.03, centre(2) - 0.03, centre(1) + 0.03, centre(2) + 0.03));
  EXPECT_TRUE(region.box_outside(1.01, 0.2, 1.05, 0.9));
  EXPECT_FALSE(region.box_outside(0.24, 0.24, 0.26, 0.26));
}

TEST(TrimRegion, PointsOnTheExactBoundaryAreOnBoundary) {
  std::vector<Trim_loop> loops{square_loop(0.0, 2.0, true)};
  Trim_loop hole;
  hole.is_outer = false;
  hole.curves.push_back({circle(1.0, 1.0, 0.5)});
  loops.push_back(hole);
  const Trim_region region(loops);
  for (int k = 0; k < 1000; ++k) {
    const double a = 2 * M_PI * k / 1000.0;
    EXPECT_EQ(region.locate(1.0 + 0.5 * std::cos(a), 1.0 + 0.5 * std::sin(a)),
              Trim_location::On_boundary);
    EXPECT_EQ(region.locate(2.0 * k / 1000.0, 0.0), Trim_location::On_boundary);
  }
  // Vertices of the polyline (shared by two segments) count once for the ray.
  EXPECT_EQ(region.locate(0.25, 1.0), Trim_location::Inside);
  EXPECT_EQ(region.locate(1.0, 1.0), Trim_location::Outside);
}

TEST(TrimRegion, ReversedCurvesAndOpenLoops) {
  // A triangle whose last edge is missing: closed by a straight segment, and flagged.
  Trim_loop l;
  l.curves.push_back({segment(0, 0, 1, 0)});
  l.curves.push_back({segment(0, 1, 1, 0), -1, true});  // runs (1,0) -> (0,1)
  const Trim_region r({l});
  EXPECT_FALSE(r.is_closed());  // (0,1) back to (0,0) is a gap of 1
  EXPECT_EQ(r.locate(0.2, 0.2), Trim_location::Inside);
  EXPECT_EQ(r.locate(0.8, 0.8), Trim_location::Outside);
  Trim_loop gap;
  gap.curves.push_back({segment(0, 0, 1, 0)});
  gap.curves.push_back({segment(1, 0.5, 0, 1)});
  const Trim_region g({gap});
  EXPECT_FALSE(g.is_closed());
  // Consecutive curves that meet, in either direction: closed.
  Trim_loop tri;
  tri.curves.push_back({segment(0, 0, 1, 0)});
  tri.curves.push_back({segment(0, 1, 1, 0), -1, true});
  tri.curves.push_back({segment(0, 1, 0, 0)});
  EXPECT_TRUE(Trim_region({tri}).is_closed());
}

TEST(TrimRegion, NonFiniteQueriesAreOutside) {
  const Trim_region r({square_loop(0, 1, true)});
  EXPECT_EQ(r.locate(std::nan(""), 0.5), Trim_location::Outside);
  EXPECT_EQ(r.locate(0.5, INFINITY), Trim_location::Outside);
}

TEST(TrimRegion, FaceContainsChecksDomainAndTrim) {
  Face f(make_plane(2.0, 2.0), "plane");
  EXPECT_TRUE(f.contains(0.5, 0.5));
  EXPECT_FALSE(f.contains(1.5, 0.5));  // outside the patch domain [0, 1]^2
  Trim_loop hole;
  hole.is_outer = false;
  hole.curves.push_back({circle(0.5, 0.5, 0.2)});
  f.trims.push_back(square_loop(0, 1, true));
  f.trims.push_back(hole);
  f.update_trim_region();
  EXPECT_FALSE(f.contains(0.5, 0.5));
  EXPECT_TRUE(f.contains(0.1, 0.1));
  // Tight box of the trimmed plane is the plane: the hole does not touch the border.
  Body b;
  b.faces.push_back(f);
  const Bbox_3 box = b.trimmed_bbox();
  EXPECT_NEAR(box.xmin(), -1.0, 1e-12);
  EXPECT_NEAR(box.xmax(), 1.0, 1e-12);
}

TEST(TrimRegion, TrimmedBboxOfASphereIsExact) {
  Body b = make_sphere_body(2.0);
  const Bbox_3 box = b.trimmed_bbox();
  EXPECT_NEAR(box.xmin(), -2.0, 1e-12);
  EXPECT_NEAR(box.ymax(), 2.0, 1e-12);
  EXPECT_NEAR(box.zmax(), 2.0, 1e-12);
  const Bbox_3 rot = b.trimmed_bbox(Rigid_pose_3::from_quaternion(Vec3(1, 2, 3), 0.9, 0.1, 0.3, 0.2));
  EXPECT_NEAR(rot.xmin(), -1.0, 1e-9);
  EXPECT_NEAR(rot.zmax(), 5.0, 1e-9);
}

}  // namespace
}  // namespace extremal
