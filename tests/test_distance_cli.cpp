// `extremal distance` end to end: the JSON contract of ../shared/CLI.md against the certified
// ellipsoid reference, intersections as exactly zero, and exit codes for bad input and usage.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "algorithms/Ellipsoid_distance.h"
#include "support/Cli_run.h"

namespace extremal {
namespace {

using test::Cli_run;

Cli_run run(const std::string& args) { return test::run_cli(args); }

Vec3 vec(const nlohmann::json& j) { return Vec3(j[0].get<double>(), j[1].get<double>(), j[2].get<double>()); }

TEST(DistanceCli, JsonCarriesACertificateThatHoldsTheTruth) {
  const Cli_run r = run(
      "distance ellipsoid:3,2,1.5 ellipsoid:2,1.2,1 --pose-a 0,0,0,0.9,0.1,0.3,0.2 "
      "--pose-b 6.5,1,0.5,0.7,0.2,0.1,0.6 --tolerance 1e-10 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* key : {"distance", "lower_bound", "upper_bound", "point_a", "point_b", "normal",
                          "face_a", "face_b", "status"})
    EXPECT_TRUE(j.contains(key)) << key;
  const auto truth = ellipsoid_distance(
      {Rigid_pose_3::from_quaternion(Vec3::Zero(), 0.9, 0.1, 0.3, 0.2), Vec3(3, 2, 1.5)},
      {Rigid_pose_3::from_quaternion(Vec3(6.5, 1, 0.5), 0.7, 0.2, 0.1, 0.6), Vec3(2, 1.2, 1)});
  const double d = j["distance"], lo = j["lower_bound"], hi = j["upper_bound"];
  EXPECT_EQ(j["status"], "converged");
  EXPECT_LE(lo, truth.upper_bound + 1e-14);
  EXPECT_GE(hi, truth.lower_bound - 1e-14);
  EXPECT_LE(hi - lo, 1e-10);
  EXPECT_NEAR(d, truth.upper_bound, 1e-10);
  EXPECT_EQ(j["face_a"], 0);
  EXPECT_EQ(j["face_b"], 0);
  EXPECT_LE((vec(j["point_b"]) - vec(j["point_a"]) - d * vec(j["normal"])).norm(), 1e-12);
}

TEST(DistanceCli, OverlappingSpheresAreExactlyZeroApart) {
  const Cli_run r = run("distance sphere:1 sphere:1 --pose-b 1.2,0.3,0 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["status"], "intersecting");
  EXPECT_EQ(j["distance"].get<double>(), 0.0);
  EXPECT_EQ(j["lower_bound"].get<double>(), 0.0);
  EXPECT_EQ(j["upper_bound"].get<double>(), 0.0);
  const Vec3 p = vec(j["point_a"]);
  EXPECT_NEAR(p.norm(), 1.0, 1e-12);                          // on A
  EXPECT_NEAR((p - Vec3(1.2, 0.3, 0)).norm(), 1.0, 1e-12);  // and on B
}

TEST(DistanceCli, TextOutputAndPointBodies) {
  const Cli_run r = run("distance point sphere:2 --pose-a 0,0,5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("distance 3"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("converged"), std::string::npos) << r.out;
}

TEST(DistanceCli, BadInputNamesTheArgumentAndExitsOne) {
  Cli_run r = run("distance sphere:-1 point");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("sphere:-1"), std::string::npos) << r.err;
  r = run("distance point point --pose-b 1,2");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("--pose-b"), std::string::npos) << r.err;
  r = run("distance /nonexistent/part.step point");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("/nonexistent/part.step"), std::string::npos) << r.err;
}

TEST(DistanceCli, UsageErrorsExitTwo) {
  EXPECT_EQ(run("distance point").exit_code, 2);
  EXPECT_EQ(run("distance point point --tolerance -1").exit_code, 2);
}

}  // namespace
}  // namespace extremal
