// End-to-end: runs the `extremal` binary on scenes and checks its rows against exact answers.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "algorithms/Ellipsoid_distance.h"
#include "support/Cli_run.h"
#include "kernel/Motion.h"

namespace extremal {
namespace {

using test::Cli_run;

Cli_run run(const std::string& args) { return test::run_cli(args); }

std::string write_scene(const std::string& name, const std::string& json) {
  const auto path = std::filesystem::temp_directory_path() / name;
  std::ofstream(path) << json;
  return path.string();
}

std::vector<std::vector<std::string>> parse_csv(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::stringstream ss(text);
  std::string line;
  while (std::getline(ss, line)) {
    std::vector<std::string> cells;
    std::stringstream ls(line);
    std::string c;
    while (std::getline(ls, c, ',')) cells.push_back(c);
    rows.push_back(cells);
  }
  return rows;
}

TEST(ReportCli, EllipsoidSceneMatchesTheCertifiedReference) {
  const std::string scene = write_scene("extremal_ellipsoids.json", R"({
    "time": {"start": 0, "end": 2, "step": 0.001},
    "bodies": [
      {"name": "A", "shape": {"type": "ellipsoid", "axes": [3, 2, 1.5]},
       "motion": {"type": "twist", "angular_velocity": [0.2, -0.1, 0.3]}},
      {"name": "B", "shape": {"type": "ellipsoid", "axes": [2, 1.2, 1]},
       "pose": {"position": [7.5, 1, 0.5], "quaternion": [0.8, 0, 0.6, 0]},
       "motion": {"type": "twist", "velocity": [-0.35, 0.1, 0.05], "angular_velocity": [-0.1, 0.3, 0.2]}}
    ],
    "pairs": [["A", "B"]]})");
  const Cli_run r = run("report " + scene);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = parse_csv(r.out);
  ASSERT_EQ(rows.size(), 2002u);
  const std::vector<std::string> contract = {"t",  "body_a", "body_b", "distance", "ax", "ay",
                                             "az", "bx",     "by",     "bz",       "nx", "ny",
                                             "nz", "face_a", "face_b", "status"};
  ASSERT_GE(rows[0].size(), contract.size());
  for (std::size_t c = 0; c < contract.size(); ++c) EXPECT_EQ(rows[0][c], contract[c]);
  const Rigid_pose_3 A0, B0 = Rigid_pose_3::from_quaternion(Vec3(7.5, 1, 0.5), 0.8, 0, 0.6, 0);
  Twist_3 VA, VB;
  VA.angular = Vec3(0.2, -0.1, 0.3);
  VB.linear = Vec3(-0.35, 0.1, 0.05);
  VB.angular = Vec3(-0.1, 0.3, 0.2);
  double worst = 0.0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const double t = std::stod(rows[i][0]);
    const double d = std::stod(rows[i][3]);
    const auto ref = ellipsoid_distance({advance(A0, VA, t), Vec3(3, 2, 1.5)},
                                        {advance(B0, VB, t), Vec3(2, 1.2, 1)});
    worst = std::max(worst, std::abs(d - ref.upper_bound));
    const Vec3 a(std::stod(rows[i][4]), std::stod(rows[i][5]), std::stod(rows[i][6]));
    const Vec3 b(std::stod(rows[i][7]), std::stod(rows[i][8]), std::stod(rows[i][9]));
    const Vec3 n(std::stod(rows[i][10]), std::stod(rows[i][11]), std::stod(rows[i][12]));
    ASSERT_NEAR((b - a - d * n).norm(), 0.0, 1e-12) << "row " << i;
    EXPECT_EQ(rows[i][1], "A");
    EXPECT_EQ(rows[i][15], "tracking");
  }
  // Pairs start from a converged solve: no transient.
  EXPECT_LE(worst, 1e-11);
}

TEST(ReportCli, StepPartThroughContactWithAudits) {
  // The unit sphere of a real STEP file (its first body, centred at the origin) against a
  // moving sphere that passes into it and out:
  // signed distance |c| - 1 - 0.5 at every row, with global audits on.
  const std::string step = std::string(EXTREMAL_SHARED_DATA) + "/step/bug24283_spheres.stp";
  const std::string scene = write_scene("extremal_step_scene.json", R"({
    "time": {"start": 0, "end": 3, "step": 0.001},
    "bodies": [
      {"name": "part", "file": ")" + step + R"("},
      {"name": "ball", "shape": {"type": "sphere", "radius": 0.5},
       "pose": {"position": [2.5, 0.2, 0]},
       "motion": {"type": "keyframes", "keyframes": [
         {"t": 0, "position": [2.5, 0.2, 0]}, {"t": 1.5, "position": [1.2, 0.2, 0]},
         {"t": 3, "position": [2.5, 0.2, 0]}]}}
    ],
    "pairs": [["part/1", "ball"]],
    "tracker": {"audit_every": 100}})");
  const Cli_run r = run("report " + scene);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = parse_csv(r.out);
  ASSERT_EQ(rows.size(), 3002u);
  double worst = 0.0;
  int penetrating = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const double t = std::stod(rows[i][0]);
    const double x = t <= 1.5 ? 2.5 - 1.3 * t / 1.5 : 1.2 + 1.3 * (t - 1.5) / 1.5;
    const double exact = std::hypot(x, 0.2) - 1.5;
    worst = std::max(worst, std::abs(std::stod(rows[i][3]) - exact));
    penetrating += rows[i][15] == "penetrating";
  }
  EXPECT_LE(worst, 1e-9);
  EXPECT_GT(penetrating, 100);
}

TEST(ReportCli, BadSceneExitsOneAndNamesThePath) {
  const std::string scene = write_scene("extremal_bad.json", R"({
    "time": {"start": 0, "end": 1, "step": 0.1},
    "bodies": [{"name": "A", "shape": {"type": "sphere", "radius": 1}, "motion": {"type": "spin"}}]})");
  const Cli_run r = run("report " + scene);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("bodies[0].motion.type: unknown motion type 'spin'"), std::string::npos)
      << r.err;
  EXPECT_EQ(run("report /nonexistent/scene.json").exit_code, 1);
  EXPECT_EQ(run("report").exit_code, 2);
  EXPECT_EQ(run("frobnicate").exit_code, 2);
}

}  // namespace
}  // namespace extremal
