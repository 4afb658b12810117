// Scene files: motions reproduce their poses, and every error names the JSON path and reason.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/Scene.h"
#include "kernel/Error.h"
#include "kernel/Shapes.h"
#include "support/Cli_run.h"

namespace extremal {
namespace {

std::string with_bodies(const std::string& bodies, const std::string& extra = "") {
  return R"({"time": {"start": 0, "end": 1, "step": 0.1}, "bodies": [)" + bodies + "]" + extra +
         "}";
}

// Parses and expects an Invalid_input whose message contains `expected`.
void expect_error(const std::string& json, const std::string& expected) {
  try {
    io::parse_scene(json, "scene.json");
    ADD_FAILURE() << "no error; expected: " << expected;
  } catch (const Invalid_input& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos)
        << "message: " << e.what() << "\nexpected to contain: " << expected;
    EXPECT_EQ(std::string(e.what()).rfind("scene.json: ", 0), 0u) << e.what();
  }
}

const char* k_sphere = R"({"name": "A", "shape": {"type": "sphere", "radius": 1}})";
const char* k_other = R"({"name": "other", "shape": {"type": "sphere", "radius": 1}})";

TEST(Scene, PoseTableRowsAndErrorsNamingTheLine) {
  // Header, comment and blank lines skipped; poses as written (unit quaternions).
  std::istringstream good("t,x,y,z,qw,qx,qy,qz\n# a comment\n\n0, 1,2,3, 1,0,0,0\n"
                          "0.5,4,5,6,0,0,0,1\r\n");
  const std::vector<Keyframe> frames = io::parse_pose_table(good, "poses.csv");
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[1].t, 0.5);
  EXPECT_EQ(frames[1].pose.translation(), Vec3(4, 5, 6));
  EXPECT_NEAR((frames[1].pose.rotation() - Mat3(Eigen::AngleAxisd(M_PI, Vec3::UnitZ()))).norm(), 0.0,
              1e-15);
  // Each bad table names the file and the line.
  auto expect_error = [](const std::string& text, const std::string& what) {
    std::istringstream in(text);
    try {
      (void)io::parse_pose_table(in, "poses.csv");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const Invalid_input& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  expect_error("", "poses.csv: pose table has no rows");
  expect_error("t,x,y,z,qw,qx,qy\n", "poses.csv:1: header");
  expect_error("0,0,0,0,1,0,0,0\n0,0,0,0,1,0,0,0\n", "poses.csv:2: times must increase");
  expect_error("0,0,0,nan,1,0,0,0\n", "poses.csv:1: column 4: 'nan' is not a finite number");
  expect_error("0,0,0,0,1,0,0,0,\n", "poses.csv:1: expected 8 columns");
  expect_error("\n\n0,0,0,0,0.5,0,0,0\n", "poses.csv:3: not a unit quaternion");
}

TEST(Scene, TwistMotionReproducesItsPoses) {
  const auto scene = io::parse_scene(with_bodies(std::string(k_sphere) + R"(,
    {"name": "B", "shape": {"type": "ellipsoid", "axes": [1, 2, 3]},
     "pose": {"position": [5, 0, 0], "quaternion": [0, 0, 0, 1]},
     "motion": {"type": "twist", "velocity": [1, 2, 3], "angular_velocity": [0, 0, 0.5]}})"),
                                     "scene.json");
  ASSERT_EQ(scene.bodies.size(), 2u);
  EXPECT_EQ(scene.step_count(), 11);
  const Motion& m = scene.bodies[1].motion;
  const Rigid_pose_3 p = m.pose_at(2.0);
  EXPECT_NEAR((p.translation() - Vec3(7, 4, 6)).norm(), 0.0, 1e-14);
  // R(t) = exp([w] t) R0 with R0 = rotation by pi about z.
  const Mat3 expected = Eigen::AngleAxisd(1.0 + M_PI, Vec3::UnitZ()).toRotationMatrix();
  EXPECT_NEAR((p.rotation() - expected).norm(), 0.0, 1e-12);
  EXPECT_EQ(m.twist_at(0.3).linear, Vec3(1, 2, 3));
  EXPECT_EQ(scene.pairs.size(), 1u);  // "all" by default
  EXPECT_EQ(scene.tracker.own_basin_gap, 1e-3);  // the default
  const auto watched = io::parse_scene(
      with_bodies(std::string(k_sphere) + "," + R"({"name": "B", "shape": {"type": "point"}})",
                  R"(, "tracker": {"audit_every": 5, "own_basin_gap": 0.01})"),
      "scene.json");
  EXPECT_EQ(watched.tracker.audit_every, 5);
  EXPECT_EQ(watched.tracker.own_basin_gap, 0.01);
  EXPECT_EQ(scene.tolerance.absolute, 1e-9);  // the default error budget
  EXPECT_EQ(scene.tolerance.relative, 1e-9);
  const auto budget = io::parse_scene(
      with_bodies(std::string(k_sphere) + "," + R"({"name": "B", "shape": {"type": "point"}})",
                  R"(, "tolerance": {"absolute": 1e-3, "relative": 1e-6})"),
      "scene.json");
  EXPECT_EQ(budget.tolerance.absolute, 1e-3);
  EXPECT_EQ(budget.tolerance.relative, 1e-6);
}

TEST(Scene, KeyframesInterpolateAndHoldOutside) {
  const double s = std::sqrt(0.5);
  const auto scene = io::parse_scene(
      with_bodies(R"({"name": "A", "shape": {"type": "point"}, "motion": {"type": "keyframes",
        "keyframes": [{"t": 1, "position": [0, 0, 0], "quaternion": [1, 0, 0, 0]},
                      {"t": 3, "position": [4, 0, 2], "quaternion": [)" +
                  std::to_string(s) + ", 0, 0, " + std::to_string(s) + R"(]}]}}, )" + k_other),
      "scene.json");
  const Motion& m = scene.bodies[0].motion;
  EXPECT_NEAR((m.pose_at(0.0).translation()).norm(), 0.0, 0.0);
  EXPECT_NEAR((m.pose_at(2.0).translation() - Vec3(2, 0, 1)).norm(), 0.0, 1e-14);
  // Halfway: rotation by pi/4 about z (slerp).
  const Mat3 half = Eigen::AngleAxisd(M_PI / 4, Vec3::UnitZ()).toRotationMatrix();
  EXPECT_NEAR((m.pose_at(2.0).rotation() - half).norm(), 0.0, 1e-6);
  EXPECT_NEAR((m.pose_at(5.0).translation() - Vec3(4, 0, 2)).norm(), 0.0, 1e-14);
  EXPECT_NEAR((m.twist_at(2.0).angular - Vec3(0, 0, M_PI / 4)).norm(), 0.0, 1e-6);
  EXPECT_TRUE(m.twist_at(4.0).is_zero());
}

TEST(Scene, TableMotionReadsPosesRelativeToTheScene) {
  const auto dir = test::scratch_dir() / "extremal_scene_test";
  std::filesystem::create_directories(dir);
  {
    std::ofstream f(dir / "poses.csv");
    f << "t,x,y,z,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n1,1,0,0,1,0,0,0\n2,1,1,0,1,0,0,0\n";
  }
  {
    std::ofstream f(dir / "scene.json");
    f << with_bodies(R"({"name": "A", "shape": {"type": "point"},
                         "motion": {"type": "table", "file": "poses.csv"}}, )" +
                    std::string(k_other));
  }
  const auto scene = io::read_scene((dir / "scene.json").string());
  const Motion& m = scene.bodies[0].motion;
  EXPECT_NEAR((m.pose_at(1.5).translation() - Vec3(1, 0.5, 0)).norm(), 0.0, 1e-14);
  EXPECT_NEAR((m.twist_at(0.5).linear - Vec3(1, 0, 0)).norm(), 0.0, 1e-14);
}

TEST(Scene, ErrorsNameThePathAndTheReason) {
  expect_error(with_bodies(R"({"name": "A", "shape": {"type": "point"}, "motion": {"type": "keyframes",
      "keyframes": [{"t": 1, "position": [0,0,0]}, {"t": 1, "position": [1,0,0]}]}})"),
               "bodies[0].motion.keyframes[1].t: times must increase");
  expect_error(with_bodies(R"({"name": "A", "shape": {"type": "sphere", "radius": 1}, "colour": 3})"),
               "bodies[0].colour: unknown key");
  expect_error(with_bodies(R"({"name": "A", "shape": {"type": "sphere", "radius": -1}})"),
               "bodies[0].shape.radius: must be > 0");
  expect_error(with_bodies(R"({"name": "A", "shape": {"type": "cube", "size": 1}})"),
               "bodies[0].shape.type: unknown shape type 'cube'");
  expect_error(with_bodies(R"({"name": "A", "shape": {"type": "point"},
      "pose": {"quaternion": [1, 1, 0, 0]}})"),
               "bodies[0].pose.quaternion: not a unit quaternion");
  expect_error(with_bodies(k_sphere, R"(, "pairs": [["A", "B"]])"), "pairs[0][1]: no body named 'B'");
  expect_error(with_bodies(std::string(k_sphere) + "," + k_sphere), "bodies[1].name: duplicate body name");
  expect_error(with_bodies(R"({"name": "A", "file": "missing.step"})"), "bodies[0].file");
  expect_error(with_bodies(R"({"name": "A", "shape": {"type": "point"}, "motion": {"type": "table", "file": "nope.csv"}})"),
               "bodies[0].motion.file: cannot open pose table");
  expect_error(R"({"time": {"end": 1, "step": 0}, "bodies": []})", "time.step: must be > 0");
  expect_error(R"({"time": {"end": 1, "step": 0.1}})", "missing key 'bodies'");
  expect_error(with_bodies(k_sphere, R"(, "tracker": {"gain": 10, "substep": 2})"),
               "tracker.substep: unknown key");
  expect_error(with_bodies(k_sphere, R"(, "tracker": {"own_basin_gap": 1.5})"),
               "tracker.own_basin_gap: must be >= 0 and < 1");
  expect_error("{not json", "not valid JSON");
  expect_error(with_bodies(k_sphere, R"(, "units": "furlong")"), "units: unknown unit 'furlong'");
}


TEST(Scene, MultiSolidEntriesNameTheirBodiesAndPairAmongThemselves) {
  // A loader standing in for a CAD file with three solids (their geometry does not matter here).
  const io::File_loader three_solids = [](const std::string&, const std::string&,
                                          const std::string&) {
    std::vector<Body> out;
    for (int k = 0; k < 3; ++k) out.push_back(make_sphere_body(1.0 + k, "solid"));
    return out;
  };
  const auto scene = io::parse_scene(
      with_bodies(R"({"name": "part", "file": "three.step"}, )" + std::string(k_sphere),
                  R"(, "pairs": [["part", "part"], ["A", "part/2"]])"),
      "scene.json", three_solids);
  ASSERT_EQ(scene.bodies.size(), 4u);
  EXPECT_EQ(scene.bodies[0].name, "part/1");
  EXPECT_EQ(scene.bodies[2].name, "part/3");
  EXPECT_EQ(scene.bodies[2].entry, "part");
  ASSERT_EQ(scene.pairs.size(), 4u);  // the three among the solids, then A - part/2
  EXPECT_EQ(scene.pairs[0], std::make_pair(0, 1));
  EXPECT_EQ(scene.pairs[2], std::make_pair(1, 2));
  EXPECT_EQ(scene.pairs[3], std::make_pair(3, 1));
}

TEST(Scene, KeysGivenTwiceAreErrorsWithTheirPath) {
  expect_error(with_bodies(std::string(k_sphere) + R"(, {"name": "B", "shape": {"type": "point"},
      "motion": {"type": "keyframes", "keyframes": [{"t": 0, "position": [0, 0, 0]},
                                                    {"t": 1, "t": 2, "position": [1, 0, 0]}]}})"),
               "bodies[1].motion.keyframes[1].t: key given twice");
  expect_error(with_bodies(k_sphere, R"(, "time": {"end": 2, "step": 0.1})"),
               "time: key given twice");
}

TEST(Scene, MissingSceneFileNamesThePath) {
  try {
    io::read_scene("/nonexistent/dir/scene.json");
    FAIL();
  } catch (const Invalid_input& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/scene.json"), std::string::npos);
  }
}

}  // namespace
}  // namespace extremal
