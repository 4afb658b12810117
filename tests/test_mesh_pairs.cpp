// Mesh bodies through the body-pair tracker: known answers for tessellated spheres (their
// polyhedra's closed forms, and the depth of two convex polyhedra from the hull of their
// Minkowski difference), a mesh box against a NURBS plane, the carried front against brute
// force at every step of seeded random motions, and the sign and depth of closed meshes and of
// a point through contact.
#include <gtest/gtest.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "algorithms/body_pair/Body_pair_tracker.h"
#include "algorithms/mesh/Mesh_bvh.h"
#include "kernel/Shapes.h"
#include "support/Mesh_test_support.h"
#include "support/Random.h"

namespace extremal {
namespace {

using test::brute_force_distance;
using test::mesh_body;
using test::uv_sphere;

const Twist_3 still{};

// The signed distance of two convex polyhedra (the vertices of A and of B, posed): apart, the
// least triangle distance; overlapping, minus the distance from the origin to the boundary of
// conv(A - B), the minimum translation distance, from its facets' planes (the origin is
// inside when it is behind every outward facet).
double convex_depth(const Triangle_mesh& A, const Rigid_pose_3& X_A, const Triangle_mesh& B,
                    const Rigid_pose_3& X_B) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  std::vector<K::Point_3> diff;
  diff.reserve(A.vertices.size() * B.vertices.size());
  for (const Point_3& a : A.vertices)
    for (const Point_3& b : B.vertices) {
      const Vec3 d = X_A.apply_point(to_vec3(a)) - X_B.apply_point(to_vec3(b));
      diff.emplace_back(d.x(), d.y(), d.z());
    }
  CGAL::Surface_mesh<K::Point_3> hull;
  CGAL::convex_hull_3(diff.begin(), diff.end(), hull);
  double least = HUGE_VAL;
  for (auto f : hull.faces()) {
    auto h = hull.halfedge(f);
    const K::Point_3 p = hull.point(hull.target(h)), q = hull.point(hull.target(hull.next(h))),
                     r = hull.point(hull.target(hull.next(hull.next(h))));
    const Vec3 P(p.x(), p.y(), p.z()), Q(q.x(), q.y(), q.z()), R(r.x(), r.y(), r.z());
    const Vec3 n = (Q - P).cross(R - P).normalized();  // outward (the hull's faces turn out)
    least = std::min(least, n.dot(P));
  }
  if (least < 0.0) return brute_force_distance(A, X_A, B, X_B);  // the origin outside: apart
  return -least;
}

Rigid_pose_3 at(const Vec3& t) { return Rigid_pose_3(Mat3::Identity(), t); }

TEST(MeshPairs, TwoTessellatedSpheresPoleToPoleReadTheirPolyhedraClosedForm) {
  // A uv sphere's poles are vertices at radius r: stacked along z, the poles are the pair.
  const double r = 1.0;
  const Body a = mesh_body(uv_sphere(r, 24, 12), "a"), b = mesh_body(uv_sphere(r, 18, 9), "b");
  Body_pair_tracker tracker(a, b);
  for (int i = 0; i <= 20; ++i) {
    const double gap = 2.0 - 0.09 * i;
    const Pair_report& p =
        tracker.step(0.01 * i, at(Vec3::Zero()), still, at(Vec3(0, 0, 2 * r + gap)), still, 0.01);
    ASSERT_NEAR(p.distance, gap, 1e-13) << "step " << i;
    ASSERT_EQ(p.status, Pair_status::Tracking);
    EXPECT_NEAR(p.point_a.z(), r, 1e-13);
    EXPECT_NEAR(p.point_b.z(), r + gap, 1e-13);
    EXPECT_NEAR(p.normal.z(), 1.0, 1e-12);
  }
}

TEST(MeshPairs, TheCarriedFrontEqualsBruteForceAtEveryStepOfRandomMotions) {
  auto rng = test::seeded_rng();
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Triangle_mesh ma = test::torus_mesh(2.0, 0.6, 28, 12), mb = uv_sphere(0.7, 12, 6);
  const Body a = mesh_body(ma, "torus"), b = mesh_body(mb, "ball");
  for (int run = 0; run < 3; ++run) {
    Body_pair_tracker tracker(a, b);
    const Vec3 axis = Vec3(u(rng), u(rng), u(rng)).normalized();
    const Vec3 start(-3.5, 0.6 * u(rng), 1.3 + 0.2 * u(rng)), velocity(1.0, 0.2 * u(rng), 0.1 * u(rng));
    const double spin = 2.0 * u(rng);
    for (int i = 0; i <= 350; ++i) {
      const double t = 0.02 * i;
      const Rigid_pose_3 X_WA(Eigen::AngleAxisd(0.3 * t, Vec3::UnitZ()).toRotationMatrix(), Vec3::Zero());
      const Rigid_pose_3 X_WB(Eigen::AngleAxisd(spin * t, axis).toRotationMatrix(), start + t * velocity);
      const Pair_report& p = tracker.step(t, X_WA, still, X_WB, still, 0.02);
      if (i % 5 != 0) continue;
      const double exact = brute_force_distance(ma, X_WA, mb, X_WB);
      if (exact == 0.0) continue;  // (surfaces crossing: the next test's)
      ASSERT_NEAR(p.distance, exact, 1e-12 * std::max(1.0, exact)) << "run " << run << " step " << i;
      // The witnesses lie on the reported triangles, the distance apart.
      ASSERT_NEAR((p.point_b - p.point_a).norm(), exact, 1e-12);
      Vec3 ta[3];
      test::corners(ma, p.feature_a, X_WA, ta);
      const Vec3 on_a = ta[0] + p.params[0] * (ta[1] - ta[0]) + p.params[1] * (ta[2] - ta[0]);
      ASSERT_NEAR((on_a - p.point_a).norm(), 0.0, 1e-12) << "run " << run << " step " << i;
      Vec3 tb[3];
      test::corners(mb, p.feature_b, X_WB, tb);
      const Vec3 on_b = tb[0] + p.params[2] * (tb[1] - tb[0]) + p.params[3] * (tb[2] - tb[0]);
      ASSERT_NEAR((on_b - p.point_b).norm(), 0.0, 1e-12) << "run " << run << " step " << i;
    }
  }
}

TEST(MeshPairs, TwoClosedMeshesThroughContactReadTheirDepthAndComeOutApart) {
  // Two convex polyhedra (tessellated balls) pushed through each other along a tilted line and
  // out: apart, the exact distance; overlapping, minus the minimum translation distance.
  const Triangle_mesh ma = uv_sphere(1.0, 20, 10), mb = uv_sphere(0.6, 14, 7);
  const Body a = mesh_body(ma, "a"), b = mesh_body(mb, "b");
  Body_pair_tracker tracker(a, b);
  const Vec3 dir = Vec3(0.3, -0.2, 1.0).normalized();
  int inside = 0, apart_after = 0;
  bool was_inside = false;
  for (int i = 0; i <= 60; ++i) {
    const double s = 2.2 - 0.07 * i;  // centre distance: 2.2 down to -2.0 (through and out)
    const Rigid_pose_3 X_WB(Eigen::AngleAxisd(0.02 * i, Vec3::UnitX()).toRotationMatrix(), s * dir);
    const Pair_report& p = tracker.step(0.01 * i, at(Vec3::Zero()), still, X_WB, still, 0.01);
    const double expected = convex_depth(ma, Rigid_pose_3(), mb, X_WB);
    ASSERT_NEAR(p.distance, expected, 1e-7 * std::max(1.0, std::abs(expected))) << "step " << i;
    ASSERT_EQ(p.distance < -1e-9, p.status == Pair_status::Penetrating) << "step " << i;
    ASSERT_FALSE(std::isnan(p.normal.x()));
    if (p.distance < 0.0) {
      ++inside;
      was_inside = true;
      // The depth's witnesses are support points along its normal: n.(b - a) = s.
      EXPECT_NEAR(p.normal.dot(p.point_b - p.point_a), p.distance, 1e-7) << "step " << i;
    } else if (was_inside) {
      ++apart_after;
    }
  }
  EXPECT_GT(inside, 20);
  EXPECT_GT(apart_after, 2);
}

TEST(MeshPairs, ABallInsideAClosedMeshIsNestedAndReadsTheHullsDepth) {
  // Surfaces apart, one inside the other: not apart (one vertex of each decides).
  const Triangle_mesh big = uv_sphere(2.0, 24, 12), small = uv_sphere(0.5, 12, 6);
  const Body a = mesh_body(big, "big"), b = mesh_body(small, "small");
  Body_pair_tracker tracker(a, b);
  const Rigid_pose_3 X_WB = at(Vec3(0.4, 0.2, -0.3));
  const Pair_report& p = tracker.step(0.0, at(Vec3::Zero()), still, X_WB, still, 0.01);
  ASSERT_EQ(p.status, Pair_status::Penetrating);
  EXPECT_NEAR(p.distance, convex_depth(big, Rigid_pose_3(), small, X_WB), 1e-7);
  // And from the other side: the big one read against the small.
  Body_pair_tracker swapped(b, a);
  const Pair_report& q = swapped.step(0.0, X_WB, still, at(Vec3::Zero()), still, 0.01);
  EXPECT_NEAR(q.distance, p.distance, 1e-7);
}

TEST(MeshPairs, APointThroughAClosedMeshReadsItsSignedDistanceToTheSurface) {
  // A convex polyhedron: inside, the distance to the surface is the least over its face planes.
  const Triangle_mesh m = uv_sphere(1.0, 16, 8);
  const Body a = mesh_body(m, "ball"), probe = make_point_body("probe");
  for (int order = 0; order < 2; ++order) {
    Body_pair_tracker tracker = order == 0 ? Body_pair_tracker(a, probe) : Body_pair_tracker(probe, a);
    int inside = 0;
    for (int i = 0; i <= 80; ++i) {
      const Vec3 q = Vec3(-1.6, 0.3, 0.2) + 0.04 * i * Vec3(1.0, -0.1, 0.05);
      const Pair_report& p = order == 0
                                 ? tracker.step(0.01 * i, at(Vec3::Zero()), still, at(q), still, 0.01)
                                 : tracker.step(0.01 * i, at(q), still, at(Vec3::Zero()), still, 0.01);
      double plane = -HUGE_VAL, surface = HUGE_VAL;  // plane: max over faces of n.(q - p0)
      for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        Vec3 c[3];
        test::corners(m, static_cast<int>(t), Rigid_pose_3(), c);
        surface = std::min(surface, closest_on_triangle_feature(q, c[0], c[1], c[2]).distance);
        const Vec3 n = (c[1] - c[0]).cross(c[2] - c[0]);
        if (n.norm() < 1e-14) continue;  // (the poles' slivers)
        plane = std::max(plane, n.normalized().dot(q - c[0]));
      }
      const double exact = plane < 0.0 ? plane : surface;
      ASSERT_NEAR(p.distance, exact, 1e-12) << "order " << order << " step " << i;
      ASSERT_NEAR(p.normal.dot(p.point_b - p.point_a), p.distance, 1e-12);
      inside += p.distance < 0.0;
    }
    EXPECT_GT(inside, 30);
  }
}

TEST(MeshPairs, AnOpenMeshIsASheetItsDistanceUnsigned) {
  Triangle_mesh cap = uv_sphere(1.0, 16, 8);
  cap.triangles.resize(cap.triangles.size() / 2);  // half a ball: open
  const Body a = mesh_body(cap, "cap"), probe = make_point_body("probe");
  Body_pair_tracker tracker(a, probe);
  const Pair_report& p = tracker.step(0.0, at(Vec3::Zero()), still, at(Vec3(0.0, 0.0, 0.1)), still, 0.01);
  EXPECT_GT(p.distance, 0.0);
  EXPECT_EQ(p.status, Pair_status::Tracking);
}

TEST(MeshPairs, AMeshBoxAboveANurbsPlaneReadsItsLowestCorner) {
  // A box of 12 triangles turning above a 10 x 10 plane patch: the lowest corner's height.
  Triangle_mesh box;
  for (int k = 0; k < 8; ++k) box.vertices.emplace_back(k & 1 ? 0.5 : -0.5, k & 2 ? 0.3 : -0.3, k & 4 ? 0.2 : -0.2);
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    box.triangles.push_back({f[0], f[1], f[2]});
    box.triangles.push_back({f[0], f[2], f[3]});
  }
  const Body a = mesh_body(box, "box"), plane = make_plane_body(10.0, 10.0);
  Body_pair_tracker tracker(a, plane);
  for (int i = 0; i <= 40; ++i) {
    const Rigid_pose_3 X_WA(
        Eigen::AngleAxisd(0.05 * i, Vec3(1.0, 0.4, 0.2).normalized()).toRotationMatrix(),
        Vec3(0.1 * i - 2.0, 0.3, 1.0));
    const Pair_report& p = tracker.step(0.01 * i, X_WA, still, Rigid_pose_3(), still, 0.01);
    double lowest = HUGE_VAL;
    for (const Point_3& v : box.vertices) lowest = std::min(lowest, X_WA.apply_point(to_vec3(v)).z());
    ASSERT_NEAR(p.distance, lowest, 1e-9) << "step " << i;
  }
}

}  // namespace
}  // namespace extremal
