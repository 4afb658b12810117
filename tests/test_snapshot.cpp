// glTF snapshots (io/Snapshot_writer.h), read back with assimp's importer:
//  - one mesh per body and per witness segment, named as given; body meshes are triangles,
//    segments a single line whose end points are the witness points;
//  - vertices, taken through the node transforms back to scene coordinates, lie on the posed
//    surfaces and span the posed bodies' boxes; normals point outward;
//  - trimmed faces keep their holes: no triangle of the bracket's end caps lies in the slot;
//  - `extremal report --snapshot OUT.glb --at T` on the demo: every body and watched pair, the
//    segments ending at the report's witness points at T; --at outside the run is bad input.
#include "io/Snapshot_writer.h"
#include "kernel/Bracket.h"
#include "kernel/Error.h"
#include "kernel/Shapes.h"
#include "support/Cli_run.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include <assimp/Importer.hpp>
#include <assimp/scene.h>

// Under LeakSanitizer (EXTREMAL_SANITIZE): assimp's importer statics are process-lifetime.
extern "C" const char* __lsan_default_suppressions() { return "leak:libassimp.so\n"; }

namespace extremal {
namespace {

const std::string binary_dir = EXTREMAL_BINARY_DIR;

struct Read_mesh {
  std::string name;
  unsigned primitive_types = 0;
  std::vector<Vec3> points;   // scene coordinates (the root's glTF map undone)
  std::vector<Vec3> normals;  // scene frame
  std::vector<std::vector<unsigned>> faces;
};

// Meshes by name, with the node transforms applied and the root's (x, z, -y) * unit map undone.
std::map<std::string, Read_mesh> read_back(const std::string& path, double unit_in_metres) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path, 0);
  EXPECT_NE(scene, nullptr) << importer.GetErrorString();
  std::map<std::string, Read_mesh> out;
  if (!scene) return out;
  std::vector<std::pair<const aiNode*, aiMatrix4x4>> stack = {{scene->mRootNode, aiMatrix4x4()}};
  while (!stack.empty()) {
    auto [node, parent] = stack.back();
    stack.pop_back();
    const aiMatrix4x4 m = parent * node->mTransformation;
    for (unsigned i = 0; i < node->mNumChildren; ++i) stack.push_back({node->mChildren[i], m});
    for (unsigned k = 0; k < node->mNumMeshes; ++k) {
      const aiMesh* mesh = scene->mMeshes[node->mMeshes[k]];
      Read_mesh r;
      r.name = mesh->mName.C_Str();
      r.primitive_types = mesh->mPrimitiveTypes;
      aiMatrix3x3 rot(m);
      for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
        const aiVector3D p = m * mesh->mVertices[v];
        // glTF (x, y, z) in metres = s (x, z, -y) in scene units.
        r.points.emplace_back(p.x / unit_in_metres, -p.z / unit_in_metres, p.y / unit_in_metres);
        if (mesh->mNormals) {
          aiVector3D n = rot * mesh->mNormals[v];
          n.Normalize();
          r.normals.emplace_back(n.x, -n.z, n.y);
        }
      }
      for (unsigned f = 0; f < mesh->mNumFaces; ++f)
        r.faces.emplace_back(mesh->mFaces[f].mIndices,
                             mesh->mFaces[f].mIndices + mesh->mFaces[f].mNumIndices);
      out[r.name] = std::move(r);
    }
  }
  return out;
}

TEST(Snapshot, BodiesAndWitnessSegmentsReadBackPosed) {
  const Body ellipsoid = make_ellipsoid_body(3, 2, 1.5, "A");
  const Body bracket = make_bracket_body();
  const Rigid_pose_3 pose_a =
      Rigid_pose_3::from_quaternion(Vec3(1, 2, 3), std::cos(0.4), std::sin(0.4), 0, 0);
  const Rigid_pose_3 pose_b =
      Rigid_pose_3::from_quaternion(Vec3(-5, 1, 0), std::cos(0.25), 0, 0, std::sin(0.25));
  const Vec3 wa(1, 2, 1.5), wb(-1.5, 2.2, 0.75);
  const std::string path = binary_dir + "/test_snapshot.glb";
  io::write_snapshot_glb(path, {{"A", &ellipsoid, pose_a}, {"bracket", &bracket, pose_b}},
                         {{"A - bracket", wa, wb}});

  const auto meshes = read_back(path, 0.001);
  ASSERT_EQ(meshes.size(), 3u);
  ASSERT_TRUE(meshes.count("A") && meshes.count("bracket") && meshes.count("A - bracket"));

  // The witness segment: one line from the point on A to the point on B.
  const Read_mesh& seg = meshes.at("A - bracket");
  EXPECT_EQ(seg.primitive_types, static_cast<unsigned>(aiPrimitiveType_LINE));
  ASSERT_EQ(seg.faces.size(), 1u);
  ASSERT_EQ(seg.faces[0].size(), 2u);
  EXPECT_LT((seg.points[seg.faces[0][0]] - wa).norm(), 1e-5);  // float precision in the file
  EXPECT_LT((seg.points[seg.faces[0][1]] - wb).norm(), 1e-5);

  // The ellipsoid: every vertex on the posed surface, normals along the gradient, outward.
  const Read_mesh& a = meshes.at("A");
  EXPECT_EQ(a.primitive_types, static_cast<unsigned>(aiPrimitiveType_TRIANGLE));
  EXPECT_GT(a.faces.size(), 500u);
  ASSERT_EQ(a.normals.size(), a.points.size());
  Vec3 lo = Vec3::Constant(1e9), hi = Vec3::Constant(-1e9);
  const Rigid_pose_3 to_a = pose_a.inverse();
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    const Vec3 q = to_a.apply_point(a.points[i]);
    const Vec3 axes(3, 2, 1.5);
    EXPECT_NEAR(q.cwiseQuotient(axes).norm(), 1.0, 1e-5) << "vertex " << i;
    const Vec3 gradient = q.cwiseQuotient(axes.cwiseProduct(axes)).normalized();
    EXPECT_GT(to_a.apply_vector(a.normals[i]).dot(gradient), 0.999) << "vertex " << i;
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  EXPECT_NEAR(hi.x(), 3.0, 1e-5);
  EXPECT_NEAR(lo.z(), -1.5, 1e-5);
  // Triangle winding agrees with the normals (outward).
  int agree = 0;
  for (const auto& f : a.faces) {
    const Vec3 n = (a.points[f[1]] - a.points[f[0]]).cross(a.points[f[2]] - a.points[f[0]]);
    if (n.dot(a.normals[f[0]] + a.normals[f[1]] + a.normals[f[2]]) > 0.0) ++agree;
  }
  EXPECT_EQ(agree, static_cast<int>(a.faces.size()));

  // The bracket: its posed box, and nothing in the slot (the caps are trimmed by the profile).
  const Read_mesh& b = meshes.at("bracket");
  const Rigid_pose_3 to_b = pose_b.inverse();
  lo = Vec3::Constant(1e9);
  hi = Vec3::Constant(-1e9);
  for (const Vec3& p : b.points) {
    const Vec3 q = to_b.apply_point(p);
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  EXPECT_LT((lo - Vec3(-4, -5, 0)).norm(), 1e-5);
  EXPECT_LT((hi - Vec3(4, 5, 4)).norm(), 1e-5);
  int in_slot = 0;
  for (const auto& f : b.faces) {
    const Vec3 c = to_b.apply_point((b.points[f[0]] + b.points[f[1]] + b.points[f[2]]) / 3.0);
    if (std::abs(c.x()) < 2.5 - 1e-6 && c.z() > 2.0 + 1e-6) ++in_slot;  // above the fillets
  }
  EXPECT_EQ(in_slot, 0);
}

TEST(Snapshot, ReportCommandWritesTheDemoAtT) {
  const std::string glb = binary_dir + "/test_snapshot_demo.glb";
  const std::string csv = binary_dir + "/test_snapshot_demo.csv";
  const std::string scene = std::string(EXTREMAL_SOURCE_DIR) + "/data/demo/demo.json";
  const test::Cli_run run =
      test::run_cli("report " + scene + " --quiet -o " + csv + " --snapshot " + glb + " --at 2.2");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto meshes = read_back(glb, 0.001);
  for (const char* name : {"A", "B", "bracket", "A - B", "A - bracket"})
    EXPECT_TRUE(meshes.count(name)) << name;
  // The report's witness points at t = 2.2 are the segments' ends.
  std::ifstream in(csv);
  std::string line;
  int rows = 0;
  while (std::getline(in, line)) {
    if (line.rfind("2.2000000000000002,", 0) != 0) continue;
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
    const Vec3 a(std::stod(f[4]), std::stod(f[5]), std::stod(f[6]));
    const Vec3 b(std::stod(f[7]), std::stod(f[8]), std::stod(f[9]));
    const Read_mesh& seg = meshes.at(f[1] + " - " + f[2]);
    ASSERT_EQ(seg.points.size(), 2u);
    EXPECT_LT((seg.points[0] - a).norm(), 1e-5) << line;
    EXPECT_LT((seg.points[1] - b).norm(), 1e-5) << line;
    ++rows;
  }
  EXPECT_EQ(rows, 2);
  const test::Cli_run late = test::run_cli("report " + scene + " --quiet -o " + csv +
                                           " --snapshot " + glb + " --at 7");
  EXPECT_EQ(late.exit_code, 1);
  EXPECT_NE(late.err.find("--at 7"), std::string::npos) << late.err;
}

TEST(Snapshot, BadInputNamesThePath) {
  const Body e = make_sphere_body(1, "S");
  try {
    io::write_snapshot_glb(binary_dir + "/no/such/dir/x.glb", {{"S", &e, Rigid_pose_3()}}, {});
    FAIL() << "no exception";
  } catch (const Invalid_input& ex) {
    EXPECT_NE(std::string(ex.what()).find("x.glb"), std::string::npos) << ex.what();
  }
  EXPECT_THROW(io::write_snapshot_glb(binary_dir + "/y.glb", {{"", &e, Rigid_pose_3()}}, {}),
               Invalid_input);
}

}  // namespace
}  // namespace extremal
