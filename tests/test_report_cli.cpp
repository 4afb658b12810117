// End-to-end: runs the `extremal` binary on scenes and checks its rows against exact answers.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <functional>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "algorithms/distance/Ellipsoid_distance.h"
#include <nlohmann/json.hpp>

#include "cli/Progress_bar.h"
#include "algorithms/scene/Step_times.h"
#include "io/Report_plot.h"
#include "support/Cli_run.h"
#include "kernel/Motion.h"

namespace extremal {
namespace {

using test::Cli_run;

Cli_run run(const std::string& args) { return test::run_cli(args); }

std::string write_scene(const std::string& name, const std::string& json) {
  const auto path = test::scratch_dir() / name;
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
    if (!line.empty() && line.back() == ',') cells.emplace_back();  // a last empty field
    rows.push_back(cells);
  }
  return rows;
}

std::string format_double(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

std::string slurp(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

std::string temp_path(const std::string& name) {
  return (test::scratch_dir() / name).string();
}

Vec3 cells_vec(const std::vector<std::string>& row, int first) {
  return Vec3(std::stod(row[first]), std::stod(row[first + 1]), std::stod(row[first + 2]));
}

// An ellipsoid with semi-axes `axes` at pose (R, c) above the plane z = 0: the signed distance
// c_z - h, h = sqrt(sum a_i^2 (R^T e_z)_i^2) its support in -z, and its lowest point (exact).
struct Plane_answer {
  double distance;
  Vec3 lowest;
};
Plane_answer ellipsoid_over_floor(const Vec3& axes, const Mat3& R, const Vec3& c) {
  const Vec3 local = R.transpose() * Vec3::UnitZ();
  const Vec3 a2 = axes.cwiseProduct(axes);
  const double h = std::sqrt(local.dot(a2.cwiseProduct(local)));
  return {c.z() - h, c - R * a2.cwiseProduct(local) / h};
}

// Runs a report of an ellipsoid (3, 2, 1.5) named "egg" under `motion_json` above a 60 x 60
// floor plane and checks every row against `pose_at(t)`: distance, both witness points, normal.
void expect_egg_rows(const std::string& name, const std::string& egg_json,
                     const std::function<Rigid_pose_3(double)>& pose_at, double end) {
  const std::string scene = write_scene(name, R"({
    "time": {"start": 0, "end": )" + std::to_string(end) + R"(, "step": 0.01},
    "bodies": [
      {"name": "floor", "shape": {"type": "plane", "size": [60, 60]}},
      )" + egg_json + R"(],
    "pairs": [["floor", "egg"]]})");
  const Cli_run r = run("report " + scene + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = parse_csv(r.out);
  ASSERT_EQ(rows.size(), static_cast<std::size_t>(std::lround(end / 0.01)) + 2);
  const Vec3 axes(3, 2, 1.5);
  double worst_distance = 0.0, worst_point = 0.0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const double t = std::stod(rows[i][0]);
    const Rigid_pose_3 X = pose_at(t);
    const Plane_answer exact = ellipsoid_over_floor(axes, X.rotation(), X.translation());
    const double d = std::stod(rows[i][3]);
    const Vec3 a = cells_vec(rows[i], 4), b = cells_vec(rows[i], 7), n = cells_vec(rows[i], 10);
    worst_distance = std::max(worst_distance, std::abs(d - exact.distance));
    worst_point = std::max({worst_point, (b - exact.lowest).norm(),
                            (a - Vec3(exact.lowest.x(), exact.lowest.y(), 0.0)).norm(),
                            (n - Vec3::UnitZ()).norm()});
    ASSERT_EQ(rows[i][1], "floor");
    ASSERT_EQ(rows[i][2], "egg");
  }
  // The distance is second order in the pair's residual, the witness points first order.
  EXPECT_LE(worst_distance, 1e-10) << name;
  EXPECT_LE(worst_point, 1e-6) << name;
  std::printf("%s: worst distance error %.3g, worst witness error %.3g\n", name.c_str(),
              worst_distance, worst_point);
}

// Slerp on the shortest arc, as the keyframe motion does.
Mat3 slerp(const Eigen::Quaterniond& q0, const Eigen::Quaterniond& q1, double s) {
  return q0.slerp(s, q1).toRotationMatrix();
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


TEST(ReportCli, SpheresThroughContactExactWithSummary) {
  // B (radius 0.5) moves into A (radius 1) and out: d = |c| - 1.5, witnesses on the centre line.
  const std::string scene = write_scene("extremal_spheres.json", R"({
    "time": {"start": 0, "end": 3, "step": 0.01},
    "bodies": [
      {"name": "A", "shape": {"type": "sphere", "radius": 1}},
      {"name": "B", "shape": {"type": "sphere", "radius": 0.5},
       "motion": {"type": "keyframes", "keyframes": [
         {"t": 0, "position": [3, 0.2, 0]}, {"t": 1.5, "position": [1.2, 0.2, 0]},
         {"t": 3, "position": [3, 0.2, 0]}]}}],
    "pairs": [["A", "B"]]})");
  auto centre = [](double t) {
    return Vec3(t <= 1.5 ? 3 - 1.2 * t : 1.2 + 1.2 * (t - 1.5), 0.2, 0);
  };
  const std::string csv = temp_path("extremal_spheres_report.csv");
  const std::string json = temp_path("extremal_spheres_report.json");
  Cli_run r = run("report " + scene + " -o " + csv);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = parse_csv(slurp(csv));
  ASSERT_EQ(rows.size(), 302u);
  double worst = 0.0, worst_point = 0.0, first_inside = -1, last_inside = -1;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const double t = std::stod(rows[i][0]);
    const Vec3 c = centre(t), u = c.normalized();
    const double exact = c.norm() - 1.5;
    worst = std::max(worst, std::abs(std::stod(rows[i][3]) - exact));
    worst_point = std::max({worst_point, (cells_vec(rows[i], 4) - u).norm(),
                      (cells_vec(rows[i], 7) - (c - 0.5 * u)).norm(),
                      (cells_vec(rows[i], 10) - u).norm()});
    EXPECT_EQ(rows[i][15], exact < -1e-9 ? "penetrating" : "tracking") << "t = " << t;
    // The certified lower bound: at most the true distance, within the default budget of the
    // row's; none while the balls overlap.
    ASSERT_EQ(rows[i].size(), 22u);
    if (exact > 1e-9) {
      const double d = std::stod(rows[i][3]), lower = std::stod(rows[i][21]);
      EXPECT_LE(lower, exact + 1e-12) << "t = " << t;
      EXPECT_GE(lower, d - std::max(1e-9, 1e-9 * d) * (1 + 1e-12)) << "t = " << t;
    } else if (exact < -1e-6) {
      EXPECT_EQ(rows[i][21], "") << "t = " << t;
    }
    if (exact < -1e-9) {
      if (first_inside < 0) first_inside = t;
      last_inside = t;
    }
  }
  EXPECT_LE(worst, 1e-9);
  EXPECT_LE(worst_point, 1e-6);  // first order in the pair's residual
  // The summary is on stdout when the rows go to a file.
  EXPECT_NE(r.out.find("A - B: minimum clearance -0.283447 at t = 1.5"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("penetrating t = 1.27 to 1.73; deepest 0.283447 at t = 1.5"),
            std::string::npos)
      << r.out;

  r = run("report " + scene + " -o " + json + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "");  // --quiet: no summary
  EXPECT_EQ(r.err, "");
  const auto j = nlohmann::json::parse(slurp(json));
  ASSERT_EQ(j["rows"].size(), 301u);
  for (const char* key : {"t", "body_a", "body_b", "distance", "point_a", "point_b", "normal",
                          "face_a", "face_b", "status"})
    EXPECT_TRUE(j["rows"][0].contains(key)) << key;
  const auto& s = j["summary"].at(0);
  const double deepest = 1.5 - std::hypot(1.2, 0.2);
  EXPECT_EQ(s["body_a"], "A");
  EXPECT_EQ(s["body_b"], "B");
  EXPECT_NEAR(s["min_distance"].get<double>(), -deepest, 1e-9);
  EXPECT_NEAR(s["min_time"].get<double>(), 1.5, 1e-12);
  EXPECT_NEAR(s["deepest_penetration"].get<double>(), deepest, 1e-9);
  EXPECT_NEAR(s["deepest_time"].get<double>(), 1.5, 1e-12);
  ASSERT_EQ(s["penetration"].size(), 1u);
  EXPECT_NEAR(s["penetration"][0]["start"].get<double>(), first_inside, 1e-12);
  EXPECT_NEAR(s["penetration"][0]["end"].get<double>(), last_inside, 1e-12);
  EXPECT_NEAR(first_inside, 1.27, 1e-12);  // d = 0 at t = (3 - sqrt(2.21)) / 1.2 = 1.2612
  ASSERT_EQ(s["contact"].size(), 1u);
  EXPECT_EQ(s["contact"][0], s["penetration"][0]);
  EXPECT_TRUE(s["farther"].empty());
}

TEST(ReportCli, StaticMotionReproducesItsPose) {
  // Two static bodies: the pair is stepped once and its row stands, across the run's blocks of
  // 512 steps too.
  const Rigid_pose_3 X = Rigid_pose_3::from_quaternion(Vec3(1, 2, 2.5), 0.8, 0.36, 0.48, 0.0);
  expect_egg_rows("extremal_egg_static.json", R"({"name": "egg",
      "shape": {"type": "ellipsoid", "axes": [3, 2, 1.5]},
      "pose": {"position": [1, 2, 2.5], "quaternion": [0.8, 0.36, 0.48, 0]},
      "motion": {"type": "static"}})",
                  [&](double) { return X; }, 6.0);
}

TEST(ReportCli, TwistMotionReproducesItsPoses) {
  // p(t) = p0 + v t, R(t) = exp([w] t) R0: down through the floor while turning.
  const Eigen::Quaterniond q0(std::cos(0.3), std::sin(0.3), 0, 0);
  const Vec3 p0(0, 0, 3), v(0.5, -0.2, -0.6), w(0.3, 0.2, -0.5);
  expect_egg_rows("extremal_egg_twist.json", R"({"name": "egg",
      "shape": {"type": "ellipsoid", "axes": [3, 2, 1.5]},
      "pose": {"position": [0, 0, 3], "quaternion": [)" + format_double(q0.w()) + ", " +
                      format_double(q0.x()) + R"(, 0, 0]},
      "motion": {"type": "twist", "velocity": [0.5, -0.2, -0.6], "angular_velocity": [0.3, 0.2, -0.5]}})",
                  [&](double t) {
                    const Mat3 R = Eigen::AngleAxisd(w.norm() * t, w.normalized()) *
                                   q0.toRotationMatrix();
                    return Rigid_pose_3(R, p0 + v * t);
                  },
                  2.5);
}

TEST(ReportCli, KeyframeMotionTakesAnEllipsoidThroughAPlaneExactly) {
  // Linear positions and shortest-arc slerp between keyframes, at rest before the first and
  // after the last; the egg sinks 0.69 into the floor around t = 1.
  const Eigen::Quaterniond q0 = Eigen::Quaterniond::Identity();
  const Eigen::Quaterniond q1(Eigen::AngleAxisd(M_PI / 3, Vec3::UnitX()));
  const Eigen::Quaterniond q2(Eigen::AngleAxisd(M_PI / 2, Vec3(0.3, 1, 0.2).normalized()));
  auto quat = [](const Eigen::Quaterniond& q) {
    return "[" + format_double(q.w()) + ", " + format_double(q.x()) + ", " + format_double(q.y()) +
           ", " + format_double(q.z()) + "]";
  };
  const Vec3 p0(0, 0, 4), p1(1, 0.5, 1.2), p2(-1, 0, 3.5);
  expect_egg_rows("extremal_egg_keyframes.json", R"({"name": "egg",
      "shape": {"type": "ellipsoid", "axes": [3, 2, 1.5]},
      "motion": {"type": "keyframes", "keyframes": [
        {"t": 0.2, "position": [0, 0, 4], "quaternion": )" + quat(q0) + R"(},
        {"t": 1, "position": [1, 0.5, 1.2], "quaternion": )" + quat(q1) + R"(},
        {"t": 2, "position": [-1, 0, 3.5], "quaternion": )" + quat(q2) + R"(}]}})",
                  [&](double t) {
                    if (t <= 0.2) return Rigid_pose_3(q0.toRotationMatrix(), p0);
                    if (t <= 1) {
                      const double s = (t - 0.2) / 0.8;
                      return Rigid_pose_3(slerp(q0, q1, s), p0 + s * (p1 - p0));
                    }
                    if (t <= 2) {
                      const double s = t - 1;
                      return Rigid_pose_3(slerp(q1, q2, s), p1 + s * (p2 - p1));
                    }
                    return Rigid_pose_3(q2.toRotationMatrix(), p2);
                  },
                  2.5);
}

TEST(ReportCli, TableMotionReproducesItsPoses) {
  // Rows t,x,y,z,qw,qx,qy,qz read relative to the scene's folder; between rows as keyframes.
  const auto dir = test::scratch_dir() / "extremal_table_scene";
  std::filesystem::create_directories(dir);
  const Eigen::Quaterniond q[3] = {
      Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Vec3::UnitZ())),
      Eigen::Quaterniond(Eigen::AngleAxisd(0.9, Vec3(1, 1, 0).normalized())),
      Eigen::Quaterniond(Eigen::AngleAxisd(-0.5, Vec3(0, 0.2, 1).normalized()))};
  const Vec3 p[3] = {Vec3(0, 0, 3), Vec3(0.5, 0.2, 2.2), Vec3(-0.3, 0.4, 2.8)};
  const double t[3] = {0, 0.6, 1.5};
  {
    std::ofstream f(dir / "egg_poses.csv");
    f << "t,x,y,z,qw,qx,qy,qz\n";
    for (int i = 0; i < 3; ++i)
      f << format_double(t[i]) << "," << format_double(p[i].x()) << "," << format_double(p[i].y())
        << "," << format_double(p[i].z()) << "," << format_double(q[i].w()) << ","
        << format_double(q[i].x()) << "," << format_double(q[i].y()) << ","
        << format_double(q[i].z()) << "\n";
  }
  expect_egg_rows("extremal_table_scene/scene.json", R"({"name": "egg",
      "shape": {"type": "ellipsoid", "axes": [3, 2, 1.5]},
      "motion": {"type": "table", "file": "egg_poses.csv"}})",
                  [&](double time) {
                    if (time >= t[2]) return Rigid_pose_3(q[2].toRotationMatrix(), p[2]);
                    const int i = time < t[1] ? 0 : 1;
                    const double s = (time - t[i]) / (t[i + 1] - t[i]);
                    return Rigid_pose_3(slerp(q[i], q[i + 1], s), p[i] + s * (p[i + 1] - p[i]));
                  },
                  2.0);
}

TEST(ReportCli, MultiSolidStepFileInSceneUnits) {
  // The STEP file (millimetres) holds two unit spheres; in a scene in centimetres they are
  // part/1 and part/2 (in `extremal info` order), radius 0.1, and the entry "part" stands for
  // both.
  const std::string step = std::string(EXTREMAL_SHARED_DATA) + "/step/bug24283_spheres.stp";
  const Cli_run info = run("info " + step + " --json");
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const auto bodies = nlohmann::json::parse(info.out)["bodies"];
  ASSERT_EQ(bodies.size(), 2u);
  Vec3 centre[2];
  for (int k = 0; k < 2; ++k) {
    const auto& bb = bodies[k]["bbox"];
    for (int c = 0; c < 3; ++c)
      centre[k][c] = 0.05 * (bb[c].get<double>() + bb[c + 3].get<double>());  // mm -> cm
  }
  const std::string scene = write_scene("extremal_step_cm.json", R"({
    "units": "cm",
    "time": {"start": 0, "end": 1, "step": 0.01},
    "bodies": [
      {"name": "part", "file": ")" + step + R"(", "units": "mm"},
      {"name": "ball", "shape": {"type": "sphere", "radius": 0.05},
       "motion": {"type": "twist", "velocity": [0, 0.1, 0]}, "pose": {"position": [0.3, 0, 0]}}],
    "pairs": [["part", "ball"]]})");
  const Cli_run r = run("report " + scene + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = parse_csv(r.out);
  ASSERT_EQ(rows.size(), 1u + 2u * 101u);
  double worst = 0.0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const int k = (i - 1) % 2;
    EXPECT_EQ(rows[i][1], "part/" + std::to_string(k + 1));
    EXPECT_EQ(rows[i][2], "ball");
    const double t = std::stod(rows[i][0]);
    const double exact = (Vec3(0.3, 0.1 * t, 0) - centre[k]).norm() - 0.15;
    worst = std::max(worst, std::abs(std::stod(rows[i][3]) - exact));
  }
  EXPECT_LE(worst, 1e-9);
}

TEST(ReportCli, ThreadsGiveTheSameRowsAsOneThread) {
  const std::string scene = write_scene("extremal_threads.json", R"({
    "time": {"start": 0, "end": 1, "step": 0.005},
    "bodies": [
      {"name": "A", "shape": {"type": "ellipsoid", "axes": [3, 2, 1.5]},
       "motion": {"type": "twist", "angular_velocity": [0.2, -0.1, 0.3]}},
      {"name": "B", "shape": {"type": "ellipsoid", "axes": [2, 1.2, 1]},
       "pose": {"position": [7.5, 1, 0.5], "quaternion": [0.8, 0, 0.6, 0]},
       "motion": {"type": "twist", "velocity": [-0.35, 0.1, 0.05], "angular_velocity": [-0.1, 0.3, 0.2]}},
      {"name": "C", "shape": {"type": "sphere", "radius": 1}, "pose": {"position": [0, 6, 0]},
       "motion": {"type": "twist", "velocity": [0, -1, 0]}},
      {"name": "D", "shape": {"type": "torus", "major": 2, "minor": 0.5},
       "pose": {"position": [-6, 0, 0]}}],
    "pairs": "all"})");
  const Cli_run one = run("report " + scene + " --threads 1");
  const Cli_run two = run("report " + scene + " --threads 2");
  ASSERT_EQ(one.exit_code, 0) << one.err;
  ASSERT_EQ(two.exit_code, 0) << two.err;
  EXPECT_EQ(parse_csv(one.out).size(), 1u + 6u * 201u);
  EXPECT_TRUE(one.out == two.out);  // byte for byte
}

// Well-formed XML as far as a plot needs: every element closed in order.
bool is_well_formed_svg(const std::string& svg) {
  std::vector<std::string> open;
  std::size_t i = 0;
  while ((i = svg.find('<', i)) != std::string::npos) {
    const std::size_t end = svg.find('>', i);
    if (end == std::string::npos) return false;
    const std::string tag = svg.substr(i + 1, end - i - 1);
    i = end + 1;
    if (tag.empty()) return false;
    const std::string name = tag.substr(tag[0] == '/', tag.find_first_of(" />", 1) - (tag[0] == '/'));
    if (tag[0] == '/') {
      if (open.empty() || open.back() != name) return false;
      open.pop_back();
    } else if (tag.back() != '/') {
      open.push_back(name);
    }
  }
  return open.empty() && svg.rfind("<svg", 0) == 0;
}

TEST(ReportCli, PlotIsAValidSvgWithAxesLegendAndShading) {
  const std::string scene = write_scene("extremal_plot.json", R"({
    "time": {"start": 0, "end": 3, "step": 0.01},
    "bodies": [
      {"name": "A", "shape": {"type": "sphere", "radius": 1}},
      {"name": "B", "shape": {"type": "sphere", "radius": 0.5},
       "motion": {"type": "keyframes", "keyframes": [
         {"t": 0, "position": [3, 0.2, 0]}, {"t": 1.5, "position": [1.2, 0.2, 0]},
         {"t": 3, "position": [3, 0.2, 0]}]}},
      {"name": "C", "shape": {"type": "sphere", "radius": 0.5}, "pose": {"position": [0, 4, 0]}}],
    "pairs": [["A", "B"], ["A", "C"]]})");
  const std::string svg_path = temp_path("extremal_plot.svg");
  std::filesystem::remove(svg_path);
  const Cli_run r = run("report " + scene + " -o " + temp_path("extremal_plot.csv") +
                        " --plot " + svg_path + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string svg = slurp(svg_path);
  EXPECT_TRUE(is_well_formed_svg(svg)) << svg.substr(0, 400);
  for (const char* text : {">time (s)<", ">signed distance (mm; &lt; 0: penetration depth)<",
                           ">A - B<", ">A - C<", ">penetration (A - B)<", ">contact (distance 0)<",
                           ">minimum of each pair<"})
    EXPECT_NE(svg.find(text), std::string::npos) << text;
  // One line per pair, the penetration shaded (red), both minima marked.
  std::size_t lines = 0, circles = 0;
  for (std::size_t i = 0; (i = svg.find("<polyline", i)) != std::string::npos; ++i) ++lines;
  for (std::size_t i = 0; (i = svg.find("<circle", i)) != std::string::npos; ++i) ++circles;
  EXPECT_EQ(lines, 2u);
  EXPECT_EQ(circles, 3u);  // two minima and the legend's dot
  EXPECT_NE(svg.find("fill=\"#d62728\" fill-opacity"), std::string::npos);
}

TEST(ReportCli, ThresholdReportsAFartherPairOnce) {
  const std::string scene = write_scene("extremal_threshold.json", R"({
    "time": {"start": 0, "end": 2, "step": 0.01},
    "bodies": [
      {"name": "A", "shape": {"type": "sphere", "radius": 1}},
      {"name": "B", "shape": {"type": "sphere", "radius": 0.5},
       "motion": {"type": "keyframes", "keyframes": [
         {"t": 0, "position": [3, 0, 0]}, {"t": 1, "position": [13, 0, 0]},
         {"t": 2, "position": [3, 0, 0]}]}}],
    "threshold": 5})");
  const std::string json = temp_path("extremal_threshold.json.out.json");
  const Cli_run r = run("report " + scene + " -o " + json + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(slurp(json));
  // Beyond the threshold while the boxes are more than 5 apart: x - 1.5 > 5, x = 3 + 10 t.
  int farther_rows = 0, expected_farther = 0;
  for (int i = 0; i <= 200; ++i) {
    const double t = i * 0.01, x = t <= 1 ? 3 + 10 * t : 13 - 10 * (t - 1);
    expected_farther += x - 1.5 > 5 + 1e-9;
  }
  for (const auto& row : j["rows"]) {
    farther_rows += row["status"] == "farther";
    if (row["status"] != "farther") {
      const double t = row["t"], x = t <= 1 ? 3 + 10 * t : 13 - 10 * (t - 1);
      EXPECT_NEAR(row["distance"].get<double>(), x - 1.5, 1e-9) << "t = " << t;
    }
  }
  EXPECT_EQ(farther_rows, 1);
  EXPECT_EQ(j["rows"].size(), 201u - (expected_farther - 1));
  const auto& s = j["summary"][0];
  ASSERT_EQ(s["farther"].size(), 1u);
  EXPECT_EQ(s["rows"], 201);
  EXPECT_EQ(s["tracked_rows"], 201 - expected_farther);
  EXPECT_NEAR(s["min_distance"].get<double>(), 1.5, 1e-9);
}

// The four statistics of a step_time_us object: present, finite, >= 0, and in their order.
// Timing decides nothing else.
void expect_sane_step_times(const nlohmann::json& times, const std::string& what) {
  ASSERT_TRUE(times.is_object()) << what;
  EXPECT_EQ(times.size(), 4u) << what;
  for (const char* key : {"mean", "median", "p99", "max"}) {
    ASSERT_TRUE(times.contains(key) && times[key].is_number()) << what << " " << key;
    const double x = times[key];
    EXPECT_TRUE(std::isfinite(x) && x >= 0.0) << what << " " << key << " = " << x;
  }
  const double mean = times["mean"], median = times["median"], p99 = times["p99"],
               max = times["max"];
  EXPECT_LE(mean, max) << what;
  EXPECT_LE(median, p99) << what;
  EXPECT_LE(p99, max) << what;
}

TEST(ReportCli, StepTimeStatisticsAreNearestRank) {
  using report::step_time_stats;
  const report::Step_time_stats five = step_time_stats({5, 1, 4, 2, 3});
  EXPECT_EQ(five.samples, 5u);
  EXPECT_EQ(five.mean, 3.0);
  EXPECT_EQ(five.median, 3.0);  // the ceil(2.5) = 3rd smallest
  EXPECT_EQ(five.p99, 5.0);     // the ceil(4.95) = 5th
  EXPECT_EQ(five.max, 5.0);
  const report::Step_time_stats four = step_time_stats({4, 3, 2, 1});
  EXPECT_EQ(four.median, 2.0);  // the lower middle one: ceil(2) = 2nd
  EXPECT_EQ(four.p99, 4.0);
  std::vector<float> hundred;
  for (int i = 100; i >= 1; --i) hundred.push_back(static_cast<float>(i));
  const report::Step_time_stats h = step_time_stats(hundred);
  EXPECT_EQ(h.median, 50.0);
  EXPECT_EQ(h.p99, 99.0);
  EXPECT_EQ(h.max, 100.0);
  EXPECT_EQ(h.mean, 50.5);
  const report::Step_time_stats one = step_time_stats({7});
  EXPECT_EQ(one.median, 7.0);
  EXPECT_EQ(one.p99, 7.0);
  EXPECT_EQ(one.mean, 7.0);
  EXPECT_EQ(step_time_stats({}).samples, 0u);
  // The scene's step time is the sum of its pairs' at each step.
  const report::Report_timing timing = report::report_timing({{1, 2, 3}, {10, 0, 30}}, {{0, 5, 0}, {0, 0, 7}});
  ASSERT_EQ(timing.pairs.size(), 2u);
  EXPECT_EQ(timing.pairs[1].median, 10.0);
  EXPECT_EQ(timing.scene.max, 33.0);  // steps 11, 2, 33
  EXPECT_EQ(timing.scene.median, 11.0);
  // Audits apart: their own statistics, per pair and summed per step.
  ASSERT_EQ(timing.audit_pairs.size(), 2u);
  EXPECT_EQ(timing.audit_pairs[0].max, 5.0);
  EXPECT_EQ(timing.audit_scene.max, 7.0);  // steps 0, 5, 7
  EXPECT_EQ(timing.audit_scene.median, 5.0);
  EXPECT_EQ(report::report_timing({{1, 2}}).audit_pairs.at(0).max, 0.0);
}

// Three spheres: B goes beyond the threshold of A and comes back, C stays near A.
const char* const every_scene = R"({
    "time": {"start": 0, "end": 2, "step": 0.01},
    "bodies": [
      {"name": "A", "shape": {"type": "sphere", "radius": 1}},
      {"name": "B", "shape": {"type": "sphere", "radius": 0.5},
       "motion": {"type": "keyframes", "keyframes": [
         {"t": 0, "position": [3, 0, 0]}, {"t": 1, "position": [13, 0, 0]},
         {"t": 2, "position": [3, 0, 0]}]}},
      {"name": "C", "shape": {"type": "sphere", "radius": 1}, "pose": {"position": [0, 4, 0]}}],
    "threshold": 5})";

TEST(ReportCli, JsonSummaryHasStepTimesPerPairAndForTheScene) {
  const std::string scene = write_scene("extremal_step_times.json", every_scene);
  const std::string json = temp_path("extremal_step_times.out.json");
  const Cli_run r = run("report " + scene + " -o " + json + " --threads 2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(slurp(json));
  ASSERT_EQ(j["summary"].size(), 3u);
  expect_sane_step_times(j["step_time_us"], "scene");
  double sum_of_means = 0.0;
  for (const auto& s : j["summary"]) {
    const std::string pair = s["body_a"].get<std::string>() + " - " + s["body_b"].get<std::string>();
    expect_sane_step_times(s["step_time_us"], pair);
    sum_of_means += s["step_time_us"]["mean"].get<double>();
    // A scene's step is its pairs' steps together: never shorter than one of them.
    EXPECT_GE(j["step_time_us"]["max"].get<double>(), s["step_time_us"]["max"].get<double>());
  }
  EXPECT_NEAR(j["step_time_us"]["mean"].get<double>(), sum_of_means, 1e-4 * sum_of_means + 1e-9);
  // The readable summary prints them: the scene's, and one line per pair.
  EXPECT_NE(r.out.find("  step time of the scene (its pairs' together): mean "), std::string::npos)
      << r.out;
  std::size_t lines = 0;
  for (std::size_t at = 0; (at = r.out.find("    step time: mean ", at)) != std::string::npos; ++at)
    ++lines;
  EXPECT_EQ(lines, 3u) << r.out;
}

TEST(ReportCli, EveryWritesTheRowsOfEveryNthStepAndTheLast) {
  const std::string scene = write_scene("extremal_every.json", every_scene);
  const Cli_run full = run("report " + scene + " --quiet");
  const Cli_run every = run("report " + scene + " --quiet --every 3");
  ASSERT_EQ(full.exit_code, 0) << full.err;
  ASSERT_EQ(every.exit_code, 0) << every.err;
  EXPECT_TRUE(run("report " + scene + " --quiet --every 1").out == full.out);  // byte for byte
  EXPECT_TRUE(run("report " + scene + " --quiet --every 3 --threads 2").out == every.out);
  // The rows by pair, as lines, in order.
  auto by_pair = [](const std::string& csv) {
    std::map<std::string, std::vector<std::string>> lines;
    std::stringstream ss(csv);
    std::string line;
    std::getline(ss, line);  // the header
    while (std::getline(ss, line)) {
      const auto cells = parse_csv(line).at(0);
      lines[cells.at(1) + " - " + cells.at(2)].push_back(line);
    }
    return lines;
  };
  const auto all = by_pair(full.out), some = by_pair(every.out);
  ASSERT_EQ(all.size(), 3u);
  ASSERT_EQ(some.size(), 3u);
  // A - C is near throughout: a row at each of the 201 steps, 68 of them written with
  // --every 3 (steps 0, 3, ..., 198 and the last, 200).
  const std::vector<std::string>& near = all.at("A - C");
  ASSERT_EQ(near.size(), 201u);
  EXPECT_EQ(some.at("A - C").size(), 68u);
  std::vector<std::string> times;  // each step's t as written
  for (const auto& line : near) times.push_back(parse_csv(line)[0][0]);
  for (const auto& [pair, lines] : all) {
    std::map<std::string, std::string> at;  // t -> the full report's row
    for (const auto& line : lines) at[parse_csv(line)[0][0]] = line;
    // The expected rows: the full report's at the written steps, a farther pair once when it
    // is farther at a written step and was not at the one before.
    std::vector<std::string> expected;
    bool was_farther = false;
    std::size_t farther_rows = 0;
    for (std::size_t k = 0; k < times.size(); ++k) {
      if (k % 3 != 0 && k != times.size() - 1) continue;
      const auto it = at.find(times[k]);
      const bool farther = it == at.end() || parse_csv(it->second)[0][15] == "farther";
      if (!farther) expected.push_back(it->second);
      else if (!was_farther) expected.push_back("farther at t = " + times[k]);
      was_farther = farther;
    }
    const std::vector<std::string>& got = some.at(pair);
    ASSERT_EQ(got.size(), expected.size()) << pair;
    for (std::size_t i = 0; i < got.size(); ++i) {
      const auto cells = parse_csv(got[i])[0];
      if (cells[15] == "farther") {
        ++farther_rows;
        EXPECT_EQ("farther at t = " + cells[0], expected[i]) << pair;
      } else {
        EXPECT_EQ(got[i], expected[i]) << pair;
      }
    }
    if (pair == "A - B") {
      EXPECT_EQ(farther_rows, 1u);
    }
  }
  // The summary covers every step: the same as --every 1's but for the step times.
  const std::string json1 = temp_path("extremal_every1.json"), json3 = temp_path("extremal_every3.json");
  ASSERT_EQ(run("report " + scene + " -o " + json1 + " --quiet").exit_code, 0);
  ASSERT_EQ(run("report " + scene + " -o " + json3 + " --quiet --every 3").exit_code, 0);
  auto j1 = nlohmann::json::parse(slurp(json1)), j3 = nlohmann::json::parse(slurp(json3));
  for (auto* j : {&j1, &j3}) {
    j->erase("step_time_us");
    for (auto& s : (*j)["summary"]) s.erase("step_time_us");
  }
  EXPECT_EQ(j1["summary"], j3["summary"]);
  EXPECT_EQ(j3["summary"][0]["rows"], 201);
  EXPECT_EQ(j3["rows"].size(), parse_csv(every.out).size() - 1);  // the CSV's rows
}

TEST(ReportCli, EveryBelowOneIsAUsageError) {
  const std::string scene = write_scene("extremal_every_bad.json", every_scene);
  for (const char* n : {"0", "-3", "x", "1.5"}) {
    const Cli_run r = run("report " + scene + " --quiet --every " + n);
    EXPECT_EQ(r.exit_code, 2) << n;
    EXPECT_NE(r.err.find("--every"), std::string::npos) << n << ": " << r.err;
    EXPECT_EQ(r.out, "") << n;
  }
  const Cli_run r = run("report " + scene + " --quiet --every 0");
  EXPECT_NE(r.err.find("must be an integer from 1"), std::string::npos) << r.err;
}

// The error budget from the command line overrides the scene's "tolerance" key; every apart
// row's lower bound is within it, and bad values are usage errors.
TEST(ReportCli, ToleranceFlagsSetTheErrorBudgetOfTheLowerBounds) {
  const std::string scene = write_scene("extremal_budget.json", R"({
    "time": {"start": 0, "end": 1, "step": 0.05},
    "bodies": [
      {"name": "A", "shape": {"type": "torus", "major": 3, "minor": 1}},
      {"name": "B", "shape": {"type": "sphere", "radius": 0.5}, "pose": {"position": [5, 1, 2]},
       "motion": {"type": "twist", "velocity": [-4, 0, -1], "angular_velocity": [0, 1, 0]}}],
    "tolerance": {"absolute": 1e-12, "relative": 1e-12},
    "pairs": [["A", "B"]]})");
  const std::string csv = temp_path("extremal_budget.csv");
  for (const std::string flags : {"", " --tolerance 1e-3 --relative-tolerance 1e-3"}) {
    const Cli_run r = run("report " + scene + " -o " + csv + " --quiet" + flags);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const double budget = flags.empty() ? 1e-12 : 1e-3;
    const auto rows = parse_csv(slurp(csv));
    EXPECT_EQ(rows.at(0).back(), "lower_bound");
    int bounded = 0;
    for (std::size_t i = 1; i < rows.size(); ++i) {
      if (rows[i][15] != "tracking" && rows[i][15] != "boundary") continue;
      const double d = std::stod(rows[i][3]), lower = std::stod(rows[i][21]);
      EXPECT_LE(lower, d);
      EXPECT_GE(lower, d - std::max(budget, budget * d) * (1 + 1e-12)) << flags << " row " << i;
      ++bounded;
    }
    EXPECT_GT(bounded, 10) << flags;
  }
  for (const char* bad : {"--tolerance 0", "--tolerance -1", "--relative-tolerance 1",
                          "--relative-tolerance x"}) {
    const Cli_run r = run("report " + scene + " --quiet " + bad);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.err.find(std::string(bad).substr(0, std::string(bad).find(' '))), std::string::npos)
        << bad << ": " << r.err;
  }
}

TEST(ReportCli, SeveralScenesRunAsABatch) {
  const auto dir = test::scratch_dir() / "extremal_batch";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  auto scene = [&](const std::string& name, double gap) {
    std::ofstream(dir / name) << R"({"time": {"end": 0.1, "step": 0.05}, "bodies": [
      {"name": "A", "shape": {"type": "sphere", "radius": 1}},
      {"name": "B", "shape": {"type": "sphere", "radius": 1}, "pose": {"position": [)"
                              << 2 + gap << R"(, 0, 0]}}]})";
    return (dir / name).string();
  };
  const std::string a = scene("near.json", 0.5), b = scene("far.json", 3);
  Cli_run r = run("report " + a + " " + b + " -o " + (dir / "out.csv").string() + " --plot " +
                  (dir / "plot.svg").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* f : {"out.near.csv", "out.far.csv", "plot.near.svg", "plot.far.svg"})
    EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;
  const auto near_rows = parse_csv(slurp((dir / "out.near.csv").string()));
  const auto far_rows = parse_csv(slurp((dir / "out.far.csv").string()));
  ASSERT_EQ(near_rows.size(), 4u);
  ASSERT_EQ(far_rows.size(), 4u);
  EXPECT_NEAR(std::stod(near_rows[1][3]), 0.5, 1e-12);
  EXPECT_NEAR(std::stod(far_rows[1][3]), 3.0, 1e-12);
  EXPECT_NE(r.out.find("near.json"), std::string::npos);  // a summary per scene
  EXPECT_NE(r.out.find("far.json"), std::string::npos);
  // To stdout: one header, a trailing scene column.
  r = run("report " + a + " " + b + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = parse_csv(r.out);
  ASSERT_EQ(rows.size(), 7u);
  EXPECT_EQ(rows[0].back(), "scene");
  EXPECT_EQ(rows[1].back(), a);
  EXPECT_EQ(rows[6].back(), b);
  // Two scenes with one stem: numbered.
  std::filesystem::create_directories(dir / "other");
  std::filesystem::copy_file(a, dir / "other" / "near.json");
  r = run("report " + a + " " + (dir / "other" / "near.json").string() + " -o " +
          (dir / "out.json").string() + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "out.1-near.json"));
  EXPECT_TRUE(std::filesystem::exists(dir / "out.2-near.json"));
}

TEST(ReportCli, RowsOnStdoutSummaryOnStderrNoProgressBarWhenPiped) {
  const std::string scene = write_scene("extremal_stdout.json", R"({
    "time": {"end": 0.1, "step": 0.05}, "bodies": [
      {"name": "A", "shape": {"type": "sphere", "radius": 1}},
      {"name": "B", "shape": {"type": "sphere", "radius": 1}, "pose": {"position": [3, 0, 0]}}]})");
  const Cli_run r = run("report " + scene);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(parse_csv(r.out).size(), 4u);
  EXPECT_NE(r.err.find("A - B: minimum clearance 1 at t = 0"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find('\r'), std::string::npos);  // stderr is a file here: no bar
}

// Runs a scene with one error and expects exit code 1 and exactly this message.
void expect_scene_error(const std::string& json, const std::string& message) {
  const std::string scene = write_scene("extremal_schema.json", json);
  const Cli_run r = run("report " + scene);
  EXPECT_EQ(r.exit_code, 1) << json;
  EXPECT_EQ(r.err, "extremal report: " + scene + ": " + message + "\n");
  EXPECT_EQ(r.out, "");
}

TEST(ReportCli, SchemaErrorsNameTheJsonPathAndTheReason) {
  const std::string two = R"({"name": "A", "shape": {"type": "sphere", "radius": 1}},
                             {"name": "B", "shape": {"type": "point"}, "pose": {"position": [3, 0, 0]}})";
  auto scene = [&](const std::string& bodies, const std::string& extra = "") {
    return R"({"time": {"start": 0, "end": 1, "step": 0.1}, "bodies": [)" + bodies + "]" + extra +
           "}";
  };
  expect_scene_error(
      scene(R"({"name": "A", "shape": {"type": "sphere", "radius": 1}},
               {"name": "B", "shape": {"type": "point"}, "motion": {"type": "keyframes",
                "keyframes": [{"t": 0, "position": [3, 0, 0]}, {"t": 0, "position": [4, 0, 0]}]}})"),
      "bodies[1].motion.keyframes[1].t: times must increase");
  expect_scene_error(scene(two, R"(, "colour": "red")"),
                     "colour: unknown key (expected one of: units, time, bodies, pairs, threshold, "
                     "tracker, tolerance, clearance)");
  expect_scene_error(scene(two, R"(, "tolerance": {"absolute": 0})"), "tolerance.absolute: must be > 0");
  expect_scene_error(scene(two, R"(, "tolerance": {"relative": 1})"),
                     "tolerance.relative: must be > 0 and < 1");
  expect_scene_error(scene(two, R"(, "tolerance": {"abs": 1e-3})"),
                     "tolerance.abs: unknown key (expected one of: absolute, relative)");
  expect_scene_error(scene(R"({"name": "A", "shape": {"type": "sphere", "radius": 1, "centre": 0}})"),
                     "bodies[0].shape.centre: unknown key (expected one of: type, radius)");
  expect_scene_error(scene(two, R"(, "tracker": {"gain": 0})"), "tracker.gain: must be > 0");
  expect_scene_error(scene(two, R"(, "tracker": {"substeps": 1.5})"),
                     "tracker.substeps: expected an integer, got a number");
  expect_scene_error(scene(two, R"(, "pairs": [["A", "C"]])"), "pairs[0][1]: no body named 'C'");
  expect_scene_error(scene(two, R"(, "pairs": [["A", "B"], ["B", "A"]])"),
                     "pairs[1]: the pair 'B', 'A' is listed twice");
  expect_scene_error(scene(two, R"(, "threshold": -1)"), "threshold: must be > 0");
  expect_scene_error(scene(R"({"name": "A", "shape": {"type": "sphere", "radius": 1}})"),
                     "pairs: no pair of bodies to watch (a scene needs at least two bodies)");
  expect_scene_error(scene(R"({"name": "A", "shape": {"type": "sphere", "radius": 1}},
                              {"name": "B", "shape": {"type": "sphere", "radius": 1, "radius": 2}})"),
                     "bodies[1].shape.radius: key given twice");
  expect_scene_error(scene(R"({"name": "A", "shape": {"type": "ellipsoid", "axes": [1, 2]}})"),
                     "bodies[0].shape.axes: expected an array of 3 numbers");
  expect_scene_error(scene(R"({"name": "A", "shape": {"type": "point"}, "motion": {"type": "twist",
                              "velocity": [1, 0, "fast"]}})"),
                     "bodies[0].motion.velocity[2]: expected a number, got a string");
  expect_scene_error(scene(R"({"name": "A", "shape": {"type": "point"}, "pose": {"position": [1, 0, 0]},
                              "motion": {"type": "keyframes", "keyframes": [{"t": 0, "position": [0, 0, 0]}]}},
                              {"name": "B", "shape": {"type": "point"}})"),
                     "bodies[0].pose: differs from the pose the keyframes give at time.start = 0 "
                     "(position 0, 0, 0); drop 'pose' or make it agree");
  expect_scene_error(scene(R"({"name": "A", "shape": {"type": "point"}, "units": "mm"})"),
                     "bodies[0].units: only file entries take units");
  expect_scene_error(scene(two, R"(, "units": "furlong")"),
                     "units: unknown unit 'furlong' (mm, cm, m, in, ft, um)");
  expect_scene_error(R"({"time": {"start": 2, "end": 1, "step": 0.1}, "bodies": [)" + two + "]}",
                     "time.end: must not be before time.start");
  // A missing file names the path it tried (relative paths from the scene's folder).
  const std::string tried = temp_path("no_such_dir/part.step");
  const std::string scene_path = write_scene("extremal_schema.json", scene(
      R"({"name": "A", "file": "no_such_dir/part.step"}, {"name": "B", "shape": {"type": "point"}})"));
  const Cli_run r = run("report " + scene_path);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err.rfind("extremal report: " + scene_path + ": bodies[0].file: " + tried + ": ", 0), 0u)
      << r.err;
}

TEST(ReportCli, PoseTableErrorsNameTheFileAndLine) {
  const auto dir = test::scratch_dir() / "extremal_table_errors";
  std::filesystem::create_directories(dir);
  const std::string scene = (dir / "scene.json").string();
  std::ofstream(scene) << R"({"time": {"end": 1, "step": 0.1}, "bodies": [
      {"name": "A", "shape": {"type": "point"}, "motion": {"type": "table", "file": "poses.csv"}},
      {"name": "B", "shape": {"type": "sphere", "radius": 1}}]})";
  const std::string table = (dir / "poses.csv").string();
  auto expect = [&](const std::string& rows, const std::string& message) {
    std::ofstream(table) << rows;
    const Cli_run r = run("report " + scene);
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_EQ(r.err, "extremal report: " + scene + ": bodies[0].motion.file: " + table + ":" +
                         message + "\n");
  };
  expect("t,x,y,z,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n1,1,0,0,1,0,0\n",
         "3: expected 8 columns t,x,y,z,qw,qx,qy,qz, got 7");
  expect("t,x,y,z,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n1,1,0,0,1,0,0,0x\n",
         "3: column 8: '0x' is not a finite number");
  expect("t,x,y,z,qw,qx,qy,qz\n1,0,0,0,1,0,0,0\n0.5,1,0,0,1,0,0,0\n", "3: times must increase");
  expect("t,y,x,z,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n",
         "1: header 't,y,x,z,qw,qx,qy,qz': expected t,x,y,z,qw,qx,qy,qz");
  expect("0,0,0,0,1,0,0,0\n1,0,0,0,2,0,0,0\n", "2: not a unit quaternion (norm 2.000000)");
}

TEST(ReportCli, PlotSeriesThinsLongRunsButKeepsADipAndTheGaps) {
  io::Pair_series s(1000000);
  for (int i = 0; i < 1000000; ++i) {
    const double t = i * 1e-6;
    double d = 1.0 + 0.1 * std::sin(6 * t);
    if (i == 123457) d = -0.5;                      // one row inside
    if (i >= 500000 && i < 600000) d = std::nan("");  // farther: a gap
    s.add(t, d);
  }
  s.finish();
  EXPECT_LE(s.t().size(), 8100u);
  int gaps = 0;
  double lowest = HUGE_VAL;
  for (std::size_t i = 0; i < s.distance().size(); ++i) {
    gaps += std::isnan(s.distance()[i]);
    if (std::isfinite(s.distance()[i])) lowest = std::min(lowest, s.distance()[i]);
    if (i > 0) {
      EXPECT_LT(s.t()[i - 1], s.t()[i]);
    }
  }
  EXPECT_EQ(lowest, -0.5);
  EXPECT_EQ(gaps, 1);
  EXPECT_EQ(s.t().front(), 0.0);
  EXPECT_EQ(s.t().back(), 999999 * 1e-6);
}

TEST(ReportCli, ProgressBarLine) {
  EXPECT_EQ(cli::Progress_bar::render("demo.json", 250, 1000, 2.0, 20),
            "demo.json [#####...............]  25% 250/1000 steps, 6 s left");
  EXPECT_EQ(cli::Progress_bar::render("demo.json", 1000, 1000, 8.0, 10),
            "demo.json [##########] 100% 1000/1000 steps");
  // Not a terminal (as under ctest): never draws, whatever the run's length.
  ::testing::internal::CaptureStderr();
  {
    cli::Progress_bar bar(true, "x", 10);
    bar.update(5);
    bar.finish();
  }
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
}

TEST(ReportCli, SnapshotWritesGlbAtTheNearestStep) {
  const std::string scene = write_scene("extremal_snapshot.json", R"({
    "time": {"start": 0, "end": 1, "step": 0.1},
    "bodies": [
      {"name": "A", "shape": {"type": "sphere", "radius": 1}},
      {"name": "B", "shape": {"type": "ellipsoid", "axes": [1, 0.5, 0.5]},
       "pose": {"position": [3, 0, 0]}, "motion": {"type": "twist", "velocity": [-1, 0, 0]}}]})");
  const std::string glb = temp_path("extremal_snapshot.glb");
  std::filesystem::remove(glb);
  const Cli_run r = run("report " + scene + " -o " + temp_path("extremal_snapshot.csv") +
                        " --snapshot " + glb + " --at 0.52");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("snapshot at the nearest step, t = 0.5"), std::string::npos) << r.out;
  const std::string bytes = slurp(glb);
  ASSERT_GE(bytes.size(), 20u);
  EXPECT_EQ(bytes.substr(0, 4), "glTF");
  for (const char* name : {"\"A\"", "\"B\"", "\"A - B\""})
    EXPECT_NE(bytes.find(name), std::string::npos) << name;
  const Cli_run outside = run("report " + scene + " --snapshot " + glb + " --at 2");
  EXPECT_EQ(outside.exit_code, 1);
  EXPECT_EQ(outside.err, "extremal report: --at 2: outside the time of " + scene + " (0 to 1 s)\n");
}

TEST(ReportCli, BadSceneExitsOneAndNamesThePath) {
  const std::string scene = write_scene("extremal_bad.json", R"({
    "time": {"start": 0, "end": 1, "step": 0.1},
    "bodies": [{"name": "A", "shape": {"type": "sphere", "radius": 1}, "motion": {"type": "spin"}}]})");
  const Cli_run r = run("report " + scene);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("bodies[0].motion.type: unknown motion type 'spin'"), std::string::npos)
      << r.err;
  const Cli_run missing = run("report /nonexistent/scene.json");
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_EQ(missing.err, "extremal report: /nonexistent/scene.json: cannot open the scene file\n");
  EXPECT_EQ(run("report").exit_code, 2);
  EXPECT_EQ(run("frobnicate").exit_code, 2);
  EXPECT_EQ(run("report " + scene + " --threads 0").exit_code, 2);
  EXPECT_EQ(run("report " + scene + " --at 1").exit_code, 2);           // --at needs --snapshot
  EXPECT_EQ(run("report " + scene + " --snapshot x.glb").exit_code, 2);  // and the reverse
  EXPECT_EQ(run("report " + scene + " --bogus").exit_code, 2);
  const Cli_run bad_output = run("report " + scene + " -o out.txt");
  EXPECT_EQ(bad_output.exit_code, 1);
  EXPECT_EQ(bad_output.err,
            "extremal report: -o out.txt: expected a file name ending in .csv, .json or .html\n");
  EXPECT_EQ(run("--help").exit_code, 0);
  EXPECT_EQ(run("report --help").exit_code, 0);
}

}  // namespace
}  // namespace extremal
