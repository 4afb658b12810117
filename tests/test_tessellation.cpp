// Tessellation (kernel/Tessellation.h), the mesh writers (io/Mesh_writer.h) and
// `extremal tessellate`:
//  - a sphere and a torus: every vertex on the exact surface (closed form, to 1e-12), every
//    sampled point of every triangle within the deflection of it, triangles outward, the face's
//    mesh closed (seams and poles welded: Euler characteristic 2 and 0);
//  - the triangle count grows as 1 / deflection;
//  - a real part: every sampled point of every triangle within the deflection of the surface
//    point at the same parameters (rational B-splines of high degree), every triangle turned
//    with its face's outward normal;
//  - a trimmed STEP face (an annulus) keeps no triangle outside its trim, and covers it;
//  - an assembly's instances are placed;
//  - STL, PLY and OBJ read back through io::read_model as one mesh body, the same triangles;
//  - bad extensions, unwritable paths, missing files, the triangle cap, usage errors.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <utility>

#include "io/Mesh_writer.h"
#include "io/Model_reader.h"
#include "kernel/Error.h"
#include "kernel/Shapes.h"
#include "kernel/Tessellation.h"
#include "support/Cli_run.h"

namespace extremal {
namespace {

std::string shared_data(const std::string& rel) {
  return std::string(EXTREMAL_SHARED_DATA) + "/" + rel;
}

Tessellation tessellate_body(const Body& body, double deflection,
                             std::size_t max_triangles = 20'000'000) {
  Tessellation t;
  Tessellation_options options;
  options.deflection = deflection;
  options.max_triangles = max_triangles;
  tessellate(body, body.placement, 0, options, t);
  return t;
}

Vec3 vertex(const Tessellation& t, int k) { return to_vec3(t.mesh.vertices[k]); }

// Points of a triangle to check: its vertices, edge midpoints, centroid and the centroids of
// its four halved sub-triangles.
std::vector<Vec3> samples(const Vec3& a, const Vec3& b, const Vec3& c) {
  std::vector<Vec3> s = {a, b, c, (a + b) / 2, (b + c) / 2, (a + c) / 2, (a + b + c) / 3};
  const Vec3 ab = (a + b) / 2, bc = (b + c) / 2, ca = (c + a) / 2;
  s.push_back((a + ab + ca) / 3);
  s.push_back((b + bc + ab) / 3);
  s.push_back((c + ca + bc) / 3);
  s.push_back((ab + bc + ca) / 3);
  return s;
}

// Largest deviation of the sampled triangle points from a surface given by its distance
// function, and the vertices' largest.
template <class Distance>
std::pair<double, double> deviations(const Tessellation& t, Distance distance) {
  double vertices = 0.0, points = 0.0;
  for (std::size_t k = 0; k < t.mesh.vertices.size(); ++k)
    vertices = std::max(vertices, distance(vertex(t, static_cast<int>(k))));
  for (const auto& tri : t.mesh.triangles)
    for (const Vec3& p : samples(vertex(t, tri[0]), vertex(t, tri[1]), vertex(t, tri[2])))
      points = std::max(points, distance(p));
  return {vertices, points};
}

// V - E + F, and whether every edge is used twice, once in each direction.
std::pair<long, bool> euler_and_closed(const Triangle_mesh& mesh) {
  std::map<std::pair<int, int>, int> directed;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  bool closed = true;
  std::set<std::pair<int, int>> edges;
  for (const auto& [e, n] : directed) {
    closed = closed && n == 1 && directed.count({e.second, e.first}) == 1;
    edges.insert({std::min(e.first, e.second), std::max(e.first, e.second)});
  }
  const long euler = static_cast<long>(mesh.vertices.size()) - static_cast<long>(edges.size()) +
                     static_cast<long>(mesh.triangles.size());
  return {euler, closed};
}

Vec3 triangle_normal(const Tessellation& t, const std::array<int, 3>& tri) {
  const Vec3 a = vertex(t, tri[0]), b = vertex(t, tri[1]), c = vertex(t, tri[2]);
  return (b - a).cross(c - a);
}

TEST(Tessellation, SphereVerticesOnTheSurfaceTrianglesWithinTheDeflection) {
  const double r = 2.0;
  const Body sphere = make_sphere_body(r);
  for (double D : {1e-2, 1e-3}) {
    const Tessellation t = tessellate_body(sphere, D);
    const auto [on, within] = deviations(t, [&](const Vec3& p) { return std::abs(p.norm() - r); });
    EXPECT_LE(on, 1e-12 * r) << D;
    EXPECT_LE(within, D) << D;
    // The bound is not wildly loose: the worst point uses a good part of the allowance.
    EXPECT_GE(within, 0.1 * D) << D;
    for (const auto& tri : t.mesh.triangles) {
      const Vec3 c = (vertex(t, tri[0]) + vertex(t, tri[1]) + vertex(t, tri[2])) / 3.0;
      ASSERT_GT(triangle_normal(t, tri).dot(c), 0.0) << "inward triangle";
    }
    const auto [euler, closed] = euler_and_closed(t.mesh);
    EXPECT_TRUE(closed);
    EXPECT_EQ(euler, 2);
    EXPECT_EQ(t.faces, 1);
    RecordProperty("triangles_at_" + std::to_string(D), static_cast<int>(t.mesh.triangles.size()));
    RecordProperty("worst_over_deflection", std::to_string(within / D));
  }
}

TEST(Tessellation, TorusVerticesOnTheSurfaceTrianglesWithinTheDeflection) {
  const double R = 3.0, r = 1.0, D = 2e-3;
  // Placed off the origin and turned, so the placement is exercised too.
  Body torus = make_torus_body(R, r);
  const Rigid_pose_3 X = Rigid_pose_3::from_quaternion(Vec3(1, -2, 5), 0.9, 0.3, -0.2, 0.1);
  torus.placement = X;
  const Tessellation t = tessellate_body(torus, D);
  auto distance = [&](const Vec3& world) {
    const Vec3 p = X.inverse().apply_point(world);
    return std::abs(std::hypot(std::hypot(p.x(), p.y()) - R, p.z()) - r);
  };
  const auto [on, within] = deviations(t, distance);
  EXPECT_LE(on, 1e-12 * (R + r));
  EXPECT_LE(within, D);
  EXPECT_GE(within, 0.1 * D);
  for (const auto& tri : t.mesh.triangles) {
    const Vec3 c =
        X.inverse().apply_point((vertex(t, tri[0]) + vertex(t, tri[1]) + vertex(t, tri[2])) / 3.0);
    const Vec3 ring = R * Vec3(c.x(), c.y(), 0).normalized();
    ASSERT_GT(X.inverse().apply_vector(triangle_normal(t, tri)).dot(c - ring), 0.0)
        << "inward triangle";
  }
  const auto [euler, closed] = euler_and_closed(t.mesh);
  EXPECT_TRUE(closed);
  EXPECT_EQ(euler, 0);
}

TEST(Tessellation, TriangleCountGrowsAsOneOverTheDeflection) {
  for (const Body& body : {make_sphere_body(1.0), make_torus_body(3.0, 1.0)}) {
    const double n3 = static_cast<double>(tessellate_body(body, 1e-3).mesh.triangles.size());
    const double n4 = static_cast<double>(tessellate_body(body, 1e-4).mesh.triangles.size());
    const double n5 = static_cast<double>(tessellate_body(body, 1e-5).mesh.triangles.size());
    EXPECT_GT(n4 / n3, 7.0) << body.name;
    EXPECT_LT(n4 / n3, 13.0) << body.name;
    EXPECT_GT(n5 / n4, 8.0) << body.name;
    EXPECT_LT(n5 / n4, 12.0) << body.name;
  }
}

// Every sampled point of every triangle of a real part lies within the deflection of the
// surface point at the same parameters (the bound's own statement, a stronger one than the
// distance to the surface), and every triangle turns with its face's outward normal. A vertex
// welded across a seam or onto a pole keeps the (u, v) of one grid node only: its triangle's
// parameters are unwrapped across the seam, and a pole's free parameter is taken from the
// other corners (the grid node it was welded from has one of theirs).
void check_real_part(const std::string& file, double relative, int& checked) {
  const io::Model model = io::read_model(shared_data(file));
  ASSERT_EQ(model.bodies.size(), 1u);
  const Body& body = model.bodies[0];
  const Bbox_3 box = body.trimmed_bbox(body.placement);
  const double D =
      relative * std::sqrt(CGAL::squared_distance(Point_3(box.xmin(), box.ymin(), box.zmin()),
                                                  Point_3(box.xmax(), box.ymax(), box.zmax())));
  const Tessellation t = tessellate_body(body, D);
  ASSERT_GT(t.mesh.triangles.size(), 1000u) << file;
  const Mat3 R = body.placement.rotation();
  const Vec3 T = body.placement.translation();
  Surface_point sp;
  double worst = 0.0;
  int worst_face = -1;
  for (std::size_t k = 0; k < t.mesh.triangles.size(); ++k) {
    const auto& tri = t.mesh.triangles[k];
    const int f = t.face_index[t.triangle_face[k]];
    const Nurbs_surface_3& s = body.faces[f].surface;
    const double period_u = s.u_max() - s.u_min(), period_v = s.v_max() - s.v_min();
    std::array<double, 2> uv[3];
    for (int c = 0; c < 3; ++c) uv[c] = t.vertex_uv[tri[c]];
    for (int c = 0; c < 3; ++c)
      for (int e = 0; e < 3; ++e) {
        if (s.is_closed_u() && uv[e][0] - uv[c][0] > 0.5 * period_u) uv[c][0] += period_u;
        if (s.is_closed_v() && uv[e][1] - uv[c][1] > 0.5 * period_v) uv[c][1] += period_v;
      }
    // Which corners are poles: the same point whatever their u (or v).
    auto pole = [&](int c, int dir) {
      const Vec3 p = to_vec3(t.mesh.vertices[tri[c]]);
      for (double x : {0.0, 0.37, 1.0}) {
        const double u = dir == 0 ? s.u_min() + x * period_u : std::min(uv[c][0], s.u_max());
        const double v = dir == 1 ? s.v_min() + x * period_v : std::min(uv[c][1], s.v_max());
        if ((body.placement.apply_point(to_vec3(s.point(u, v))) - p).norm() > 1e-9 * (1 + p.norm()))
          return false;
      }
      return true;
    };
    const Vec3 p[3] = {vertex(t, tri[0]), vertex(t, tri[1]), vertex(t, tri[2])};
    // The deviation of the triangle against the surface over the parameter triangle `q`.
    auto deviation = [&](const std::array<double, 2>(&q)[3]) {
      double e = 0.0;
      for (double a = 0.0; a <= 1.0; a += 0.25)
        for (double b = 0.0; a + b <= 1.0 + 1e-12; b += 0.25) {
          const double c = std::max(0.0, 1.0 - a - b);
          const double u = a * q[0][0] + b * q[1][0] + c * q[2][0];
          const double v = a * q[0][1] + b * q[1][1] + c * q[2][1];
          // Unwrapped parameters past the seam are the same points on the other side.
          s.evaluate_placed(u > s.u_max() ? u - period_u : u, v > s.v_max() ? v - period_v : v, R,
                            T, sp, 0);
          e = std::max(e, (a * p[0] + b * p[1] + c * p[2] - sp.p).norm());
        }
      return e;
    };
    double best = deviation(uv);
    for (int c = 0; c < 3; ++c)
      for (int dir = 0; dir < 2; ++dir)
        if (pole(c, dir))
          for (int other = 0; other < 3; ++other) {
            std::array<double, 2> q[3] = {uv[0], uv[1], uv[2]};
            q[c][dir] = uv[other][dir];
            best = std::min(best, deviation(q));
          }
    if (best > worst) worst = best, worst_face = f;
    s.evaluate_placed(std::min((uv[0][0] + uv[1][0] + uv[2][0]) / 3, s.u_max()),
                      std::min((uv[0][1] + uv[1][1] + uv[2][1]) / 3, s.v_max()), R, T, sp, 1);
    const Vec3 outward_normal = s.outward_sign() * sp.du.cross(sp.dv);
    EXPECT_GT(outward_normal.dot(triangle_normal(t, tri)), 0.0)
        << file << ": triangle " << k << " of face " << f << " turns inward";
    ++checked;
  }
  EXPECT_LE(worst, D) << file << " face " << worst_face;
  testing::Test::RecordProperty(file + "_worst_over_deflection", std::to_string(worst / D));
}

TEST(Tessellation, RealPartsWithinTheDeflectionAndOutward) {
  int turbine = 0, linkrods = 0;
  check_real_part("step/ec_turbine-A.stp", 3e-4, turbine);  // rational B-splines, degree 2 x 11
  check_real_part("step/linkrods.step", 1e-3, linkrods);    // degree 6 x 10, tori, cylinders
  EXPECT_GT(turbine + linkrods, 20000);
}

// linkrods.step's face 2 is a plane in z = 0 trimmed to an annulus (outer loop: two half
// circles; hole: one circle about the same centre).
TEST(Tessellation, TrimmedStepFaceKeepsNoTriangleOutsideItsTrim) {
  const io::Model model = io::read_model(shared_data("step/linkrods.step"));
  const Body& full = model.bodies.at(0);
  const Face& annulus = full.faces.at(2);
  ASSERT_EQ(annulus.kind, "plane");
  ASSERT_EQ(annulus.trims.size(), 2u);
  // The circles from the B-rep edges' 3D curves (body frame).
  const Trim_loop& outer = annulus.trims[0].is_outer ? annulus.trims[0] : annulus.trims[1];
  const Trim_loop& hole = annulus.trims[0].is_outer ? annulus.trims[1] : annulus.trims[0];
  auto edge_point = [&](const Trim_curve& c, double s) {
    const Edge& e = full.edges.at(c.edge);
    return to_vec3(e.curve->point(e.t_min + s * (e.t_max - e.t_min)));
  };
  const Vec3 centre =
      0.5 * (edge_point(outer.curves.at(0), 0.0) + edge_point(outer.curves.at(1), 0.0));
  const double r_out = (edge_point(outer.curves[0], 0.3) - centre).norm();
  const double r_in = (edge_point(hole.curves.at(0), 0.3) - centre).norm();
  ASSERT_NEAR((edge_point(outer.curves[1], 0.7) - centre).norm(), r_out, 1e-9);
  ASSERT_NEAR((edge_point(hole.curves[0], 0.7) - centre).norm(), r_in, 1e-9);
  ASSERT_LT(r_in, r_out);

  Body one;  // the face alone, in the body frame
  one.faces.push_back(annulus);
  // The trim region's boundary band (its polylines within half of it of the exact loops),
  // in model units: the plane's parameters scaled by its speed.
  Surface_point sp;
  const Nurbs_surface_3& s = annulus.surface;
  s.evaluate(0.5 * (s.u_min() + s.u_max()), 0.5 * (s.v_min() + s.v_max()), sp, 1);
  const double band = 2.0 * annulus.trim_region.tolerance() * std::max(sp.du.norm(), sp.dv.norm());
  const double exact = M_PI * (r_out * r_out - r_in * r_in);
  for (double D : {1e-2, 1e-3, 1e-4}) {
    const Tessellation t = tessellate_body(one, D);
    double area = 0.0;
    for (const auto& tri : t.mesh.triangles) {
      const Vec3 a = vertex(t, tri[0]), b = vertex(t, tri[1]), c = vertex(t, tri[2]);
      // Vertices lie inside the trim or on it (to the band); a chord between two points on
      // the hole's circle cuts into the hole by its sagitta, the outer circle's stays inside.
      for (const Vec3& p : {a, b, c}) {
        const double rho = (p - centre).norm();
        ASSERT_GE(rho, r_in - band) << "a vertex in the hole";
        ASSERT_LE(rho, r_out + band) << "a vertex past the outer loop";
      }
      const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
      const double sagitta = longest * longest / (8.0 * r_in);
      for (const Vec3& p : samples(a, b, c)) {
        const double rho = (p - centre).norm();
        ASSERT_GE(rho, r_in - band - sagitta) << "a triangle reaches into the hole";
        ASSERT_LE(rho, r_out + band) << "a triangle reaches past the outer loop";
      }
      area += 0.5 * (b - a).cross(c - a).norm();
    }
    // The border is the trim sampled where grid edges cross it: the area is off by the
    // circles' sagittas within the cells (the hole's add, the outer circle's take away).
    EXPECT_NEAR(area, exact, 0.03 * exact) << D;
    RecordProperty("area_fraction_at_" + std::to_string(D), std::to_string(area / exact));
    RecordProperty("triangles_at_" + std::to_string(D), static_cast<int>(t.mesh.triangles.size()));
  }
}

TEST(Tessellation, AssemblyInstancesArePlaced) {
  const io::Model model = io::read_model(shared_data("step/as1-oc-214-mat.stp"));
  ASSERT_GT(model.bodies.size(), 10u);
  Tessellation t;
  Tessellation_options options;
  options.deflection = 0.05;
  Bbox_3 expected;
  for (std::size_t k = 0; k < model.bodies.size(); ++k) {
    tessellate(model.bodies[k], model.bodies[k].placement, static_cast<int>(k), options, t);
    expected += model.bodies[k].trimmed_bbox(model.bodies[k].placement);
  }
  Bbox_3 got;
  for (const Point_3& p : t.mesh.vertices) got += p.bbox();
  for (int i = 0; i < 3; ++i) {
    EXPECT_GE(got.min(i), expected.min(i) - 1e-6);
    EXPECT_LE(got.max(i), expected.max(i) + 1e-6);
    // Jagged trims stay within a grid cell of the box; the cells here are a few mm at most.
    EXPECT_NEAR(got.min(i), expected.min(i), 5.0);
    EXPECT_NEAR(got.max(i), expected.max(i), 5.0);
  }
  EXPECT_EQ(t.face_body.size(), t.face_index.size());
  EXPECT_EQ(t.face_body.back(), static_cast<int>(model.bodies.size()) - 1);
}

TEST(Tessellation, BadOptionsAndTheCap) {
  const Body sphere = make_sphere_body(1.0);
  Tessellation t;
  Tessellation_options options;
  options.deflection = 0.0;
  EXPECT_THROW(tessellate(sphere, Rigid_pose_3(), 0, options, t), Precondition_violation);
  options.deflection = std::nan("");
  EXPECT_THROW(tessellate(sphere, Rigid_pose_3(), 0, options, t), Precondition_violation);
  // Far past the cap: refused from the plan, before any vertex is made.
  options.deflection = 1e-12;
  options.max_triangles = 1000;
  try {
    tessellate(sphere, Rigid_pose_3(), 0, options, t);
    ADD_FAILURE() << "no error";
  } catch (const Tessellation_too_large& e) {
    EXPECT_TRUE(e.estimated());
    EXPECT_GT(e.triangles(), 1e9);
    EXPECT_TRUE(t.mesh.vertices.empty());
  }
  // Just past the cap: stopped while building.
  options.deflection = 1e-3;
  const std::size_t needed = tessellate_body(sphere, 1e-3).mesh.triangles.size();
  options.max_triangles = needed - 1;
  try {
    tessellate(sphere, Rigid_pose_3(), 0, options, t);
    ADD_FAILURE() << "no error";
  } catch (const Tessellation_too_large& e) {
    EXPECT_FALSE(e.estimated());
    EXPECT_LE(t.mesh.triangles.size(), needed - 1);
  }
}

// The written file read back as the project reads meshes: one body, the same triangles in the
// same order and turn, at single precision (assimp's).
void check_round_trip(const Tessellation& t, const std::string& name) {
  const std::string path = (test::scratch_dir() / name).string();
  io::write_mesh(path, t.mesh);
  const io::Model back = io::read_model(path);
  ASSERT_EQ(back.bodies.size(), 1u) << name;
  const Triangle_mesh& m = back.bodies[0].mesh;
  ASSERT_EQ(m.triangles.size(), t.mesh.triangles.size()) << name;
  EXPECT_TRUE(back.bodies[0].faces.empty()) << name;
  double size = 0.0;
  for (const Point_3& p : t.mesh.vertices) size = std::max(size, to_vec3(p).cwiseAbs().maxCoeff());
  double worst = 0.0;
  for (std::size_t k = 0; k < m.triangles.size(); ++k)
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, (to_vec3(m.vertices[m.triangles[k][c]]) -
                               to_vec3(t.mesh.vertices[t.mesh.triangles[k][c]]))
                                  .norm());
  EXPECT_LE(worst, 1e-6 * size) << name;
  std::filesystem::remove(path);
}

TEST(Tessellation, WrittenMeshesReadBackAsMeshBodies) {
  Body torus = make_torus_body(3.0, 1.0);
  torus.placement = Rigid_pose_3::from_quaternion(Vec3(10, 0, -4), 1, 0, 0, 0);
  const Tessellation t = tessellate_body(torus, 1e-2);
  for (const char* name :
       {"tess_round_trip.stl", "tess_round_trip.ply", "tess_round_trip.obj", "tess_round_trip.STL"})
    check_round_trip(t, name);
  // A real part of many faces (vertices repeated along its edges).
  const io::Model screw = io::read_model(shared_data("step/screw.step"));
  const Tessellation s = tessellate_body(screw.bodies.at(0), 0.05);
  check_round_trip(s, "tess_screw.ply");
  check_round_trip(s, "tess_screw.stl");
}

TEST(Tessellation, WriterErrorsNameTheFileAndTheReason) {
  const Tessellation t = tessellate_body(make_sphere_body(1.0), 1e-2);
  try {
    io::write_mesh("mesh.xyz", t.mesh);
    ADD_FAILURE() << "no error";
  } catch (const Invalid_input& e) {
    EXPECT_NE(std::string(e.what()).find("mesh.xyz"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("use .stl, .ply or .obj"), std::string::npos) << e.what();
  }
  EXPECT_THROW(io::mesh_file_format("mesh"), Invalid_input);
  try {
    io::write_mesh("/nonexistent-folder/mesh.stl", t.mesh);
    ADD_FAILURE() << "no error";
  } catch (const Invalid_input& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-folder/mesh.stl"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("No such file"), std::string::npos) << e.what();
  }
  EXPECT_THROW(io::check_writable("/nonexistent-folder/mesh.stl"), Invalid_input);
  EXPECT_THROW(io::check_writable(test::scratch_dir().string()), Invalid_input);
  EXPECT_NO_THROW(io::check_writable((test::scratch_dir() / "new.stl").string()));
  Triangle_mesh bad = t.mesh;
  bad.triangles.push_back({0, 1, static_cast<int>(bad.vertices.size())});
  EXPECT_THROW(io::write_mesh((test::scratch_dir() / "bad.obj").string(), bad),
               Precondition_violation);
}

TEST(TessellateCli, WritesAMeshThatReadsBackAndSummarises) {
  const std::string out = (test::scratch_dir() / "cli_screw.stl").string();
  const test::Cli_run r = test::run_cli("tessellate " + shared_data("step/screw.step") + " -o " +
                                        out + " --deflection 2e-4 --relative");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* word : {"10 faces", "triangles", "vertices", "deflection", " s "})
    EXPECT_NE(r.err.find(word), std::string::npos) << word << " in " << r.err;
  const io::Model back = io::read_model(out);
  ASSERT_EQ(back.bodies.size(), 1u);
  const std::size_t n = back.bodies[0].mesh.triangles.size();
  EXPECT_NE(r.err.find(std::to_string(n) + " triangles"), std::string::npos) << r.err;
  EXPECT_GT(n, 10000u);
  std::filesystem::remove(out);

  // Absolute deflection on a shape spec, OBJ.
  const std::string obj = (test::scratch_dir() / "cli_sphere.obj").string();
  const test::Cli_run s = test::run_cli("tessellate sphere:1 -o " + obj + " --deflection 1e-3");
  ASSERT_EQ(s.exit_code, 0) << s.err;
  EXPECT_NE(s.err.find("deflection 0.001 mm"), std::string::npos) << s.err;
  EXPECT_EQ(io::read_model(obj).bodies.at(0).mesh.triangles.size(),
            tessellate_body(make_sphere_body(1.0), 1e-3).mesh.triangles.size());
  std::filesystem::remove(obj);
}

TEST(TessellateCli, ErrorsNameTheFileAndExitOne) {
  const std::string step = shared_data("step/screw.step");
  const std::string dir = test::scratch_dir().string();
  test::Cli_run r = test::run_cli("tessellate " + step + " -o " + dir + "/out.xyz");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("out.xyz"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("use .stl, .ply or .obj"), std::string::npos) << r.err;

  r = test::run_cli("tessellate " + step + " -o /nonexistent-folder/out.stl");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("/nonexistent-folder/out.stl"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("does not exist"), std::string::npos) << r.err;

  r = test::run_cli("tessellate /nonexistent/part.step -o " + dir + "/out.stl");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("/nonexistent/part.step"), std::string::npos) << r.err;

  r = test::run_cli("tessellate point -o " + dir + "/out.stl");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("nothing to tessellate"), std::string::npos) << r.err;

  // The cap: named with the file and the count, and no file is left behind.
  const std::string capped = dir + "/capped.stl";
  r = test::run_cli("tessellate " + step + " -o " + capped + " --max-triangles 1000");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(step), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("1000 triangles"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(capped));
  r = test::run_cli("tessellate sphere:1 -o " + capped + " --deflection 1e-12");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("grid has"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(capped));

  // Usage errors.
  EXPECT_EQ(test::run_cli("tessellate sphere:1 -o " + capped + " --deflection -1").exit_code, 2);
  EXPECT_EQ(test::run_cli("tessellate sphere:1").exit_code, 2);
  EXPECT_EQ(test::run_cli("tessellate sphere:1 -o " + capped + " --max-triangles 0").exit_code, 2);
  EXPECT_EQ(test::run_cli("tessellate --help").exit_code, 0);
}

}  // namespace
}  // namespace extremal
