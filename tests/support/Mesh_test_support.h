// Meshes for tests: tessellated spheres and tori (closed, outward), boxes, and brute-force
// distances over every triangle pair.
#pragma once

#include <array>
#include <cmath>
#include <vector>

#include "algorithms/distance/Triangle_distance.h"
#include "kernel/Body.h"
#include "kernel/Rigid_pose_3.h"

namespace extremal::test {

// A UV sphere of radius r about c: nu segments around, nv rings from pole to pole, outward.
inline Triangle_mesh uv_sphere(double r, int nu, int nv, const Vec3& c = Vec3::Zero()) {
  Triangle_mesh m;
  const double pi = 3.14159265358979323846;
  m.vertices.emplace_back(c.x(), c.y(), c.z() + r);  // north pole
  for (int j = 1; j < nv; ++j) {
    const double th = pi * j / nv;
    for (int i = 0; i < nu; ++i) {
      const double ph = 2 * pi * i / nu;
      m.vertices.emplace_back(c.x() + r * std::sin(th) * std::cos(ph),
                              c.y() + r * std::sin(th) * std::sin(ph), c.z() + r * std::cos(th));
    }
  }
  m.vertices.emplace_back(c.x(), c.y(), c.z() - r);  // south pole
  const int south = static_cast<int>(m.vertices.size()) - 1;
  auto ring = [nu](int j, int i) { return 1 + (j - 1) * nu + (i % nu); };
  for (int i = 0; i < nu; ++i) m.triangles.push_back({0, ring(1, i), ring(1, i + 1)});
  for (int j = 1; j < nv - 1; ++j)
    for (int i = 0; i < nu; ++i) {
      m.triangles.push_back({ring(j, i), ring(j + 1, i), ring(j + 1, i + 1)});
      m.triangles.push_back({ring(j, i), ring(j + 1, i + 1), ring(j, i + 1)});
    }
  for (int i = 0; i < nu; ++i) m.triangles.push_back({south, ring(nv - 1, i + 1), ring(nv - 1, i)});
  return m;
}

// A torus about the z axis: radii R, r; nu segments around the axis, nv around the tube.
inline Triangle_mesh torus_mesh(double R, double r, int nu, int nv) {
  Triangle_mesh m;
  const double pi = 3.14159265358979323846;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * pi * i / nu, v = 2 * pi * j / nv;
      m.vertices.emplace_back((R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u),
                              r * std::sin(v));
    }
  auto id = [&](int i, int j) { return (i % nu) * nv + (j % nv); };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

inline Body mesh_body(Triangle_mesh m, const std::string& name) {
  Body b;
  b.name = name;
  b.mesh = std::move(m);
  return b;
}

inline void corners(const Triangle_mesh& m, int t, const Rigid_pose_3& X, Vec3 out[3]) {
  for (int k = 0; k < 3; ++k)
    out[k] = X.apply_point(to_vec3(m.vertices[static_cast<std::size_t>(m.triangles[static_cast<std::size_t>(t)][static_cast<std::size_t>(k)])]));
}

// The least distance over every pair of triangles of A (posed X_A) and B (posed X_B).
inline double brute_force_distance(const Triangle_mesh& A, const Rigid_pose_3& X_A,
                                   const Triangle_mesh& B, const Rigid_pose_3& X_B) {
  std::vector<std::array<Vec3, 3>> tb(B.triangles.size());
  for (std::size_t t = 0; t < B.triangles.size(); ++t) corners(B, static_cast<int>(t), X_B, tb[t].data());
  double least = HUGE_VAL;
  Vec3 ta[3];
  for (std::size_t s = 0; s < A.triangles.size(); ++s) {
    corners(A, static_cast<int>(s), X_A, ta);
    for (const auto& b : tb) least = std::min(least, triangle_distance(ta, b.data()).distance);
  }
  return least;
}

}  // namespace extremal::test
