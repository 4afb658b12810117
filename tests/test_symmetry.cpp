// Centres and axes of symmetry (algorithms/Symmetry.h): found on the shapes that have them and
// on none that lack them, and the radial ranges of Bezier pieces enclose the sampled distances,
// exactly on a sphere about its centre and a cylinder about its axis.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "algorithms/distance/Symmetry.h"
#include "kernel/Nurbs_refinement.h"
#include "kernel/Shapes.h"
#include "support/Random.h"

namespace extremal {
namespace {

using test::random_pose;

double distance_to(const Symmetry& s, const Vec3& x) { return s.offset(x).norm(); }

// The line (point, direction) is s's axis: both its points lie on s's line.
void expect_axis(const Symmetry& s, const Vec3& point, const Vec3& direction, double tol) {
  ASSERT_EQ(s.kind, Symmetry::Kind::Axis);
  EXPECT_NEAR(s.direction.norm(), 1.0, 1e-12);
  EXPECT_LE(s.direction.cross(direction.normalized()).norm(), 1e-9);
  EXPECT_LE(distance_to(s, point), tol);
  EXPECT_LE(distance_to(s, point + direction), tol);
}

TEST(Symmetry, FoundOnSpheresCylindersToriDiscsAndCirclesOnly) {
  auto rng = test::seeded_rng();
  for (int trial = 0; trial < 5; ++trial) {
    const Rigid_pose_3 X = random_pose(rng, 100.0);
    const Vec3 origin = X.translation(), z = X.apply_vector(Vec3::UnitZ());
    SCOPED_TRACE(::testing::Message() << "trial " << trial);
    const Symmetry sphere = find_symmetry(transformed(make_sphere(2.5), X));
    ASSERT_EQ(sphere.kind, Symmetry::Kind::Centre);
    EXPECT_LE((sphere.point - origin).norm(), 1e-9);
    expect_axis(find_symmetry(transformed(make_cylinder_side(1.5, 4.0), X)), origin, z, 1e-9);
    expect_axis(find_symmetry(transformed(make_torus(3.0, 1.0), X)), origin, z, 1e-9);
    expect_axis(find_symmetry(transformed(make_disk(2.0, 1.0, true), X)), origin, z, 1e-9);
    expect_axis(find_symmetry(transformed(make_circle(0.7), X)), origin, z, 1e-9);
    // A spheroid is a surface of revolution about its third axis; a general ellipsoid is not.
    expect_axis(find_symmetry(transformed(make_ellipsoid(2.0, 2.0, 3.0), X)), origin, z, 1e-9);
    EXPECT_FALSE(find_symmetry(transformed(make_ellipsoid(1.0, 2.0, 3.0), X)).any());
    EXPECT_FALSE(find_symmetry(transformed(make_plane(2.0, 3.0), X)).any());
  }
  // A freeform patch with wavy poles.
  std::vector<Point_3> poles;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) poles.emplace_back(i, j, 0.3 * std::sin(i + 2.0 * j));
  EXPECT_FALSE(find_symmetry(make_freeform(3, 3, 5, 5, poles)).any());
}

// Radial ranges of every Bezier piece of s, and of its quarters, against distances sampled on
// them; returns the largest excess of the range over the sampled one.
double check_ranges(const Nurbs_surface_3& s, const Symmetry& sym) {
  double excess = 0.0;
  for (const Nurbs_surface_3& piece : extract_bezier(s).patches) {
    const auto [left, right] =
        split(piece, Parameter_direction::U, 0.5 * (piece.u_min() + piece.u_max()));
    for (const Nurbs_surface_3& p : {piece, left, right}) {
      const Bezier_patches bp = extract_bezier(p);
      const Nurbs_surface_3& b = bp.patches.front();
      double lo = 0.0, hi = 0.0;
      EXPECT_TRUE(radial_range(b.homogeneous_poles().data(), b.degree_u() + 1, b.degree_v() + 1,
                               sym, lo, hi));
      double seen_lo = HUGE_VAL, seen_hi = 0.0;
      for (int i = 0; i <= 12; ++i)
        for (int j = 0; j <= 12; ++j) {
          const double u = b.u_min() + (b.u_max() - b.u_min()) * i / 12.0;
          const double v = b.v_min() + (b.v_max() - b.v_min()) * j / 12.0;
          const double rho = distance_to(sym, to_vec3(b.point(u, v)));
          EXPECT_LE(lo, rho * (1 + 1e-14) + 1e-14);
          EXPECT_GE(hi, rho * (1 - 1e-14) - 1e-14);
          seen_lo = std::min(seen_lo, rho);
          seen_hi = std::max(seen_hi, rho);
        }
      excess = std::max({excess, seen_lo - lo, hi - seen_hi});
    }
  }
  return excess;
}

TEST(Symmetry, RadialRangesEncloseSampledDistancesAndAreExactOnASphereAndACylinder) {
  auto rng = test::seeded_rng();
  std::uniform_real_distribution<double> unit(-1.0, 1.0), log_weight(-3.0, 3.0);
  for (int trial = 0; trial < 6; ++trial) {
    SCOPED_TRACE(::testing::Message() << "trial " << trial);
    // Rational freeform patches, weights 1e-3 to 1e3, about random centres and axes.
    std::vector<Point_3> poles;
    std::vector<double> weights;
    for (int k = 0; k < 20; ++k) {
      poles.emplace_back(k / 5 + 0.3 * unit(rng), k % 5 + 0.3 * unit(rng), unit(rng));
      weights.push_back(std::pow(10.0, log_weight(rng)));
    }
    const Nurbs_surface_3 freeform = make_freeform(2, 3, 4, 5, poles, weights);
    Symmetry centre, axis;
    centre.kind = Symmetry::Kind::Centre;
    centre.point = Vec3(2 * unit(rng), 2 * unit(rng), 2 * unit(rng));
    axis.kind = Symmetry::Kind::Axis;
    axis.point = centre.point;
    axis.direction = Vec3(unit(rng), unit(rng), unit(rng)).normalized();
    check_ranges(freeform, centre);
    check_ranges(freeform, axis);
    // Exact (to rounding) on a sphere about its centre and a cylinder about its axis, far from
    // the origin.
    const Rigid_pose_3 X = random_pose(rng, 1e3);
    const Nurbs_surface_3 sphere = transformed(make_sphere(2.5), X);
    const Nurbs_surface_3 cylinder = transformed(make_cylinder_side(1.5, 4.0), X);
    EXPECT_LE(check_ranges(sphere, find_symmetry(sphere)), 1e-11);
    EXPECT_LE(check_ranges(cylinder, find_symmetry(cylinder)), 1e-11);
  }
}

TEST(Symmetry, RadialRangesAboveTheirDegreeLimitAreRefused) {
  std::vector<Eigen::Vector4d> net(14 * 2, Eigen::Vector4d(0, 0, 0, 1));
  Symmetry s;
  s.kind = Symmetry::Kind::Centre;
  double lo = -1.0, hi = -1.0;
  EXPECT_FALSE(radial_range(net.data(), 14, 2, s, lo, hi));
  EXPECT_TRUE(radial_range(net.data(), 13, 2, s, lo, hi));
  EXPECT_EQ(lo, 0.0);
}

// Weights far below the normal range make the weight products underflow: the range must
// still hold the net's points (here the first pole, 10 from the centre), or be refused.
TEST(Symmetry, RadialRangesOfNetsWhoseWeightProductsUnderflowStaySound) {
  const double w0 = 1e-170;
  const std::vector<Eigen::Vector4d> net = {Eigen::Vector4d(10.0 * w0, 0, 0, w0),
                                            Eigen::Vector4d(1, 0, 0, 1), Eigen::Vector4d(1, 1, 0, 1)};
  Symmetry s;
  s.kind = Symmetry::Kind::Centre;
  double lo = 0.0, hi = 0.0;
  const bool made = radial_range(net.data(), 3, 1, s, lo, hi);
  EXPECT_TRUE(!made || hi >= 10.0) << "hi " << hi;
}

}  // namespace
}  // namespace extremal
