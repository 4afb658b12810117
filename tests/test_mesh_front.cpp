// The mesh hierarchy (algorithms/mesh/Mesh_bvh.h) and the front carried across steps
// (Mesh_front.h): box bounds never above the distance of the boxes' triangles, closest points
// and insides against brute force, and the carried front against a cold solve and brute force
// at every step of seeded random motions.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "algorithms/body_pair/internal/Body_pair_support.h"
#include "algorithms/mesh/Mesh_bvh.h"
#include "algorithms/mesh/Mesh_front.h"
#include "support/Mesh_test_support.h"
#include "kernel/Error.h"
#include "support/Random.h"

namespace extremal {
namespace {

using test::brute_force_distance;
using test::torus_mesh;
using test::uv_sphere;

Rigid_pose_3 random_pose(std::mt19937_64& rng, double reach) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Vec3 axis = Vec3(u(rng), u(rng), u(rng)).normalized();
  return Rigid_pose_3(Eigen::AngleAxisd(3.0 * u(rng), axis).toRotationMatrix(),
                      reach * Vec3(u(rng), u(rng), u(rng)));
}

// The triangles of a node's subtree (leaf slots).
void node_triangles(const Mesh_bvh& h, int ref, std::vector<int>& slots) {
  if (Mesh_bvh::is_leaf(ref)) {
    slots.push_back(Mesh_bvh::leaf_slot(ref));
    return;
  }
  for (int child : h.node(ref).child) node_triangles(h, child, slots);
}

TEST(TriangleDistance, EqualsTheLeastOverCornersToTrianglesAndEdgePairs) {
  // Random pairs, many close and near-parallel: against the minimum over the six corners'
  // closest points on the other triangle (Ericson's Voronoi regions) and the nine edge pairs,
  // and against points sampled on both.
  auto rng = test::seeded_rng();
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int near = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    Vec3 a[3], b[3];
    const double flat = trial % 3 == 0 ? 1e-3 : 1.0;  // near-parallel pairs
    for (int k = 0; k < 3; ++k) {
      a[k] = Vec3(u(rng), u(rng), flat * u(rng));
      b[k] = Vec3(u(rng), u(rng), flat * u(rng) + 0.4 + 0.3 * u(rng));
    }
    const Triangle_closest c = triangle_distance(a, b);
    double least = HUGE_VAL;
    double uv[2];
    for (int k = 0; k < 3; ++k) {
      least = std::min(least, (a[k] - closest_on_triangle(a[k], b[0], b[1], b[2], uv)).norm());
      least = std::min(least, (b[k] - closest_on_triangle(b[k], a[0], a[1], a[2], uv)).norm());
    }
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        Vec3 x, y;
        least = std::min(least, std::sqrt(segment_segment_squared(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3], x, y)));
      }
    if (c.distance == 0.0) {  // crossing: the common point lies on both
      double uv2[2];
      ASSERT_LT((c.point_a - closest_on_triangle(c.point_a, a[0], a[1], a[2], uv2)).norm(), 1e-12);
      ASSERT_LT((c.point_a - closest_on_triangle(c.point_a, b[0], b[1], b[2], uv2)).norm(), 1e-12);
      continue;
    }
    ASSERT_NEAR(c.distance, least, 1e-14) << "trial " << trial;
    ASSERT_NEAR((c.point_b - c.point_a).norm(), c.distance, 1e-14) << "trial " << trial;
    near += c.distance < 0.05;
    if (trial % 100 == 0) {  // no sampled pair is closer
      for (int i = 0; i <= 20; ++i)
        for (int j = 0; i + j <= 20; ++j) {
          const Vec3 p = a[0] + (i / 20.0) * (a[1] - a[0]) + (j / 20.0) * (a[2] - a[0]);
          const Vec3 q = b[0] + (j / 20.0) * (b[1] - b[0]) + (i / 20.0) * (b[2] - b[0]);
          ASSERT_GE((p - q).norm(), c.distance - 1e-14);
        }
    }
  }
  EXPECT_GT(near, 20);
}

TEST(MeshBvh, BoxBoundsNeverExceedTheDistance) {
  auto rng = test::seeded_rng();
  const Triangle_mesh ma = uv_sphere(1.0, 16, 8), mb = torus_mesh(2.0, 0.5, 24, 12);
  const Mesh_bvh a(ma, "sphere"), b(mb, "torus");
  // References: inner nodes and leaves alike.
  std::uniform_int_distribution<int> pick_a(-a.triangle_count(), a.inner_count() - 1);
  std::uniform_int_distribution<int> pick_b(-b.triangle_count(), b.inner_count() - 1);
  int positive = 0, triangle_positive = 0;
  for (int trial = 0; trial < 1500; ++trial) {
    const Rigid_pose_3 X = random_pose(rng, 3.0);
    const int na = pick_a(rng), nb = pick_b(rng);
    const double bound = obb_lower_bound(a.box(na), b.box(nb), X.rotation(), X.translation());
    std::vector<int> sa, sb;
    node_triangles(a, na, sa);
    node_triangles(b, nb, sb);
    double least = HUGE_VAL;
    for (int s : sa)
      for (int r : sb) {
        Vec3 tb[3];
        for (int k = 0; k < 3; ++k) tb[k] = X.apply_point(b.corners(r)[k]);
        least = std::min(least, triangle_distance(a.corners(s), tb).distance);
      }
    ASSERT_LE(bound, least) << "trial " << trial;
    if (bound > 0.0) ++positive;
    if (Mesh_bvh::is_leaf(na) && !Mesh_bvh::is_leaf(nb)) {  // a triangle against a box
      const Obb& box = b.node(nb).box;
      const double tri = triangle_box_lower_bound(a.corners(Mesh_bvh::leaf_slot(na)),
                                                  X.apply_point(box.centre), X.rotation() * box.axes, box.half);
      ASSERT_LE(tri, least) << "trial " << trial;
      triangle_positive += tri > 0.0;
    }
  }
  EXPECT_GT(positive, 100);  // the bounds do separate
  EXPECT_GT(triangle_positive, 20);
}

TEST(MeshBvh, ClosestPointsAndInsidesMatchBruteForce) {
  auto rng = test::seeded_rng();
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  const Triangle_mesh m = torus_mesh(2.0, 0.7, 32, 16);
  Triangle_mesh flipped = m;  // inward normals: the same inside
  for (auto& t : flipped.triangles) std::swap(t[1], t[2]);
  const Mesh_bvh h(m, "torus"), hf(flipped, "torus flipped");
  ASSERT_TRUE(h.closed()) << h.closedness_reason();
  ASSERT_TRUE(hf.closed()) << hf.closedness_reason();
  int inside = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const Vec3 p(u(rng), u(rng), 0.5 * u(rng));
    double least = HUGE_VAL;
    for (int t = 0; t < h.triangle_count(); ++t) {
      const Vec3* c = h.triangle(t);
      least = std::min(least, closest_on_triangle_feature(p, c[0], c[1], c[2]).distance);
    }
    const Mesh_point q = h.closest_point(p);
    ASSERT_NEAR(q.distance, least, 1e-14) << "trial " << trial;
    // The tessellated torus's inside: within the tube by more than the chordal error, or
    // outside it by more (the points between are left out).
    const double tube = std::hypot(std::hypot(p.x(), p.y()) - 2.0, p.z());
    if (std::abs(tube - 0.7) < 0.05) continue;
    EXPECT_EQ(h.inside(p), tube < 0.7) << "trial " << trial << " tube " << tube;
    EXPECT_EQ(hf.inside(p), tube < 0.7) << "trial " << trial;
    inside += tube < 0.7;
  }
  EXPECT_GT(inside, 10);
}

TEST(MeshBvh, AMeshWhoseCornersRepeatPerTriangleIsWeldedAndClosed) {
  // As STL stores it: every triangle its own three vertices.
  const Triangle_mesh m = uv_sphere(1.0, 12, 6);
  Triangle_mesh soup;
  for (const auto& t : m.triangles) {
    const int base = static_cast<int>(soup.vertices.size());
    for (int k : t) soup.vertices.push_back(m.vertices[static_cast<std::size_t>(k)]);
    soup.triangles.push_back({base, base + 1, base + 2});
  }
  const Mesh_bvh h(soup, "soup");
  ASSERT_TRUE(h.closed()) << h.closedness_reason();
  EXPECT_TRUE(h.inside(Vec3(0.1, -0.2, 0.3)));
  EXPECT_FALSE(h.inside(Vec3(0.1, -0.2, 1.3)));
  // A vertex's pseudo-normal sums its welded triangles: a point just off a vertex, outside.
  const Vec3 v = to_vec3(m.vertices[5]);
  EXPECT_FALSE(h.inside(1.01 * v));
  EXPECT_TRUE(h.inside(0.9 * v));
}

TEST(MeshBvh, HoldsUnder300BytesATriangleWithTheMesh) {
  // The hierarchy (n - 1 boxes, corners, orders, adjacency, pseudo-normals) and the mesh
  // itself, for a closed mesh of 10^5 triangles.
  const Triangle_mesh m = torus_mesh(2.0, 0.6, 500, 100);
  const Mesh_bvh h(m, "torus");
  ASSERT_TRUE(h.closed());
  const double n = static_cast<double>(m.triangles.size());
  const double mesh_bytes = static_cast<double>(m.vertices.size() * sizeof(Point_3) +
                                                m.triangles.size() * sizeof(m.triangles[0]));
  const double per_triangle = (static_cast<double>(h.memory_bytes()) + mesh_bytes) / n;
  std::printf("[ case     ] %.0f triangles: %.0f bytes a triangle\n", n, per_triangle);
  EXPECT_LT(per_triangle, 300.0);
  EXPECT_EQ(h.inner_count(), static_cast<int>(n) - 1);
}

TEST(MeshBvh, AnOpenOrInconsistentMeshIsNotClosedAndSaysWhere) {
  Triangle_mesh open = uv_sphere(1.0, 8, 4);
  open.triangles.pop_back();
  const Mesh_bvh h(open, "holed");
  EXPECT_FALSE(h.closed());
  EXPECT_NE(h.closedness_reason().find("has 1 triangle(s), not 2"), std::string::npos)
      << h.closedness_reason();
  EXPECT_NE(h.closedness_reason().find("'holed'"), std::string::npos);
  Triangle_mesh twisted = uv_sphere(1.0, 8, 4);
  std::swap(twisted.triangles[3][1], twisted.triangles[3][2]);
  const Mesh_bvh g(twisted, "twisted");
  EXPECT_FALSE(g.closed());
  EXPECT_NE(g.closedness_reason().find("not consistently oriented"), std::string::npos)
      << g.closedness_reason();
  Triangle_mesh bad = uv_sphere(1.0, 8, 4);
  bad.triangles[0][0] = 1000;
  EXPECT_THROW(Mesh_bvh(bad, "bad"), Invalid_input);
}

// A smooth random motion: B's pose at step i, turning and drifting near A.
struct Drift {
  Vec3 axis, velocity, start;
  double spin;
  Rigid_pose_3 at(double t) const {
    return Rigid_pose_3(Eigen::AngleAxisd(spin * t, axis).toRotationMatrix(), start + t * velocity);
  }
};

TEST(MeshFront, TheCarriedFrontEqualsAColdSolveAndBruteForceAtEveryStep) {
  auto rng = test::seeded_rng();
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Triangle_mesh ma = torus_mesh(2.0, 0.6, 40, 16), mb = uv_sphere(0.8, 20, 10);
  const Mesh_bvh a(ma, "torus"), b(mb, "ball");
  for (int run = 0; run < 3; ++run) {
    Drift d{Vec3(u(rng), u(rng), u(rng)).normalized(), Vec3(1.0, 0.3 * u(rng), 0.2 * u(rng)),
            Vec3(-3.5, 0.5 * u(rng), 1.2 + 0.3 * u(rng)), 2.0 * u(rng)};
    Mesh_front front(a, &b);
    Rigid_pose_3 last = d.at(0.0);
    long cold_opened = 0;
    // 100 steps a second: the carried front re-bounds what the motion brought near.
    for (int i = 0; i <= 700; ++i) {
      const double t = i * 0.01;
      const Rigid_pose_3 X = d.at(t);
      const double closer = internal::approach_bound(a.box(), b.box(), last, X).closer;
      last = X;
      const Mesh_closest& c = front.update(X, closer, 1e-13);
      Mesh_front cold(a, &b);
      const Mesh_closest& k = cold.update(X, 0.0, 1e-13);
      cold_opened += cold.statistics().opened;
      ASSERT_NEAR(c.distance, k.distance, 1e-12 * std::max(1.0, k.distance)) << "run " << run << " step " << i;
      if (i % 35 == 0) {
        const double exact = brute_force_distance(ma, Rigid_pose_3(), mb, X);
        ASSERT_NEAR(c.distance, exact, 1e-12 * std::max(1.0, exact)) << "run " << run << " step " << i;
      }
      // The witnesses are the distance apart, on their triangles.
      ASSERT_NEAR((c.point_b - c.point_a).norm(), c.distance, 1e-12 * std::max(1.0, c.distance));
    }
    std::printf("[ case     ] run %d: %ld entries opened by the carried front, %ld by cold solves\n",
                run, front.statistics().opened, cold_opened);
    EXPECT_LT(front.statistics().opened, cold_opened);
  }
}

TEST(MeshFront, APointAgainstAMeshEqualsBruteForce) {
  auto rng = test::seeded_rng();
  std::uniform_real_distribution<double> u(-4.0, 4.0);
  const Triangle_mesh ma = torus_mesh(2.0, 0.6, 40, 16);
  const Mesh_bvh a(ma, "torus");
  Mesh_front front(a, nullptr);
  Vec3 last(0, 0, 3);
  for (int i = 0; i < 200; ++i) {
    const Vec3 p = last + 0.1 * Vec3(u(rng), u(rng), u(rng));
    const double closer = (p - last).norm();
    last = p;
    const Mesh_closest& c = front.update(Rigid_pose_3(Mat3::Identity(), p), i == 0 ? 0.0 : closer, 1e-13);
    double least = HUGE_VAL;
    for (int t = 0; t < a.triangle_count(); ++t) {
      const Vec3* k = a.triangle(t);
      least = std::min(least, closest_on_triangle_feature(p, k[0], k[1], k[2]).distance);
    }
    ASSERT_NEAR(c.distance, least, 1e-13) << "step " << i;
  }
}

}  // namespace
}  // namespace extremal
