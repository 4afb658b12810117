// `extremal distance` end to end: the JSON contract of docs/cli.md against the certified
// ellipsoid reference, intersections as exactly zero, and exit codes for bad input and usage.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "algorithms/distance/Ellipsoid_distance.h"
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
  // --max-cells belongs to --signed, and must be positive.
  EXPECT_EQ(run("distance point sphere:1 --max-cells 100").exit_code, 2);
  EXPECT_EQ(run("distance point sphere:1 --signed --max-cells 0").exit_code, 2);
  EXPECT_EQ(run("distance point sphere:1 --signed --max-cells x").exit_code, 2);
}

// --signed: overlapping spheres report minus the depth (|c_B - c_A| - r_A - r_B), status
// `penetrating`, the same keys as the plain output, and bounds that hold the truth.
TEST(DistanceCli, SignedOverlappingSpheresReportTheirDepth) {
  const Cli_run r = run("distance sphere:1 sphere:0.7 --pose-b 1.2,0.3,0 --signed --json "
                        "--tolerance 1e-10");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* key : {"distance", "lower_bound", "upper_bound", "point_a", "point_b", "normal",
                          "face_a", "face_b", "status"})
    EXPECT_TRUE(j.contains(key)) << key;
  const double truth = Vec3(1.2, 0.3, 0).norm() - 1.7;
  EXPECT_EQ(j["status"], "penetrating");
  EXPECT_EQ(j["overlap"], "surfaces_meet");
  EXPECT_EQ(j["depth"], "translation");
  EXPECT_NEAR(j["distance"].get<double>(), truth, 1e-10);
  EXPECT_LE(j["lower_bound"].get<double>(), truth + 1e-12);
  EXPECT_GE(j["upper_bound"].get<double>(), truth - 1e-12);
  EXPECT_NEAR((vec(j["normal"]) - Vec3(1.2, 0.3, 0).normalized()).norm(), 0.0, 1e-4);

  // Apart, --signed gives exactly the plain answer.
  const Cli_run plain = run("distance ellipsoid:3,2,1.5 sphere:1 --pose-b 6,1,0 --json");
  const Cli_run signed_apart =
      run("distance ellipsoid:3,2,1.5 sphere:1 --pose-b 6,1,0 --json --signed");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  ASSERT_EQ(signed_apart.exit_code, 0) << signed_apart.err;
  const auto jp = nlohmann::json::parse(plain.out), js = nlohmann::json::parse(signed_apart.out);
  for (const char* key : {"distance", "lower_bound", "upper_bound", "point_a", "point_b", "normal",
                          "face_a", "face_b", "status"})
    EXPECT_EQ(jp[key], js[key]) << key;
  EXPECT_EQ(js["overlap"], "none");

  // Text output names the overlap.
  const Cli_run text = run("distance point sphere:2 --pose-a 0.3,0,0 --signed");
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("distance -1.7"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("a_inside_b"), std::string::npos) << text.out;
}

// A STEP file (bug24283_spheres.stp: a unit sphere at the origin and a second one near
// (3, 0, 0)) against an ellipsoid pushed through the unit sphere's surface at c: the deepest
// pair is the unit sphere and the ellipsoid; the truth is the minimum of the analytic
// overlap(n) = 1 + n.(0 - c) + sqrt(n^T diag(s^2) n) over a fine grid, zoomed.
TEST(DistanceCli, SignedStepPartWithAShapeThroughIt) {
  const std::string file = std::string(EXTREMAL_SHARED_DATA) + "/step/bug24283_spheres.stp";
  const Vec3 c(0.9, 0.4, -0.3), axes(0.6, 0.4, 0.3);
  const Cli_run r = run("distance " + file + " ellipsoid:0.6,0.4,0.3 --pose-b 0.9,0.4,-0.3 --signed "
                        "--json --tolerance 1e-9");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  auto overlap = [&](double th, double ph) {
    const Vec3 n(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
    return 1.0 - n.dot(c) + std::sqrt(n.cwiseProduct(axes).squaredNorm());
  };
  double best = HUGE_VAL, bt = 0, bp = 0, h = M_PI / 200;
  for (int i = 0; i <= 200; ++i)
    for (int k = 0; k < 400; ++k)
      if (overlap(h * i, h * k) < best) {
        best = overlap(h * i, h * k);
        bt = h * i;
        bp = h * k;
      }
  for (int level = 0; level < 40; ++level, h *= 0.5) {
    const double t0 = bt, p0 = bp;
    for (int i = -10; i <= 10; ++i)
      for (int k = -10; k <= 10; ++k)
        if (overlap(t0 + h * i / 5, p0 + h * k / 5) < best) {
          best = overlap(t0 + h * i / 5, p0 + h * k / 5);
          bt = t0 + h * i / 5;
          bp = p0 + h * k / 5;
        }
  }
  const double truth = -best;
  EXPECT_EQ(j["status"], "penetrating");
  EXPECT_EQ(j["overlap"], "surfaces_meet");
  EXPECT_EQ(j["depth"], "hull");  // a trimmed STEP sphere face is not certified convex
  EXPECT_EQ(j["closed_a"]["closed"], true);
  EXPECT_EQ(j["closed_b"]["closed"], true);
  EXPECT_EQ(j["body_a"], "NAUO1");
  EXPECT_NEAR(j["distance"].get<double>(), truth, 1e-9);
  EXPECT_LE(j["lower_bound"].get<double>(), truth + 1e-12);
  EXPECT_GE(j["upper_bound"].get<double>(), truth - 1e-12);
}

// OCC22459-TEST2.stp holds three open sheets of ruled B-spline faces (about 3.4 x 1.8 x 1.7 m).
// The file against itself moved by (3, 1, -2) mm: the first sheet meets its copy, so the
// distance is exactly 0 and certified, although the third sheet against its own copy (nearly
// parallel, 2.7 mm apart over a metre) runs out of the solver's node budget; a pair whose lower
// bound stays at or above the answer cannot change it. The CLI called this budget_exhausted.
TEST(DistanceCli, SetsThatMeetAreCertifiedWhateverTheOtherPairs) {
  const std::string file = std::string(EXTREMAL_SHARED_DATA) + "/step/OCC22459-TEST2.stp";
  const Cli_run r = run("distance " + file + " " + file + " --pose-b 3,1,-2 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["status"], "intersecting");
  EXPECT_EQ(j["certified"], true);
  EXPECT_EQ(j["distance"].get<double>(), 0.0);
  EXPECT_EQ(j["lower_bound"].get<double>(), 0.0);
  EXPECT_EQ(j["upper_bound"].get<double>(), 0.0);
  EXPECT_EQ(j["body_a"], "COMPOUND#1");
}

// The body pairs of a file are queried nearest box first, each cut off at the best distance so
// far, and pairs whose boxes lie beyond it are skipped: the answer must be the nearest body
// whatever the boxes say. bug24283_spheres.stp holds two unit spheres, NAUO1 at the origin and
// NAUO2 at c2 (the middle of its box). At (-1.7, 3, 2) a ball of radius 0.5 has NAUO1's box
// nearer (1.59 against 1.75) but NAUO2's sphere nearer (2.34 against 2.49); at (2.5, -0.5, 0.3)
// NAUO1 is nearer by both, and NAUO2's box lies beyond the answer.
TEST(DistanceCli, TheNearestBodyOfAFileWinsWhateverItsBox) {
  const std::string file = std::string(EXTREMAL_SHARED_DATA) + "/step/bug24283_spheres.stp";
  const Vec3 c2(-0.11847810259174475, 1.6863172135334625, -1.2439655293919430);
  // Body pairs queried: both in the first place (the nearer box is the farther body), one in
  // the second (NAUO2's box beyond the first answer).
  struct Place {
    Vec3 at;
    const char* nearest;
    int queried;
  };
  for (const auto& [at, nearest, queried] : {Place{Vec3(-1.7, 3.0, 2.0), "NAUO2", 2},
                                             Place{Vec3(2.5, -0.5, 0.3), "NAUO1", 1}}) {
    std::ostringstream pose;
    pose << std::setprecision(17) << at.x() << "," << at.y() << "," << at.z();
    const Cli_run r = run("distance " + file + " sphere:0.5 --pose-b " + pose.str() + " --json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    const double truth = std::min(at.norm(), (at - c2).norm()) - 1.5;
    EXPECT_EQ(j["status"], "converged");
    EXPECT_EQ(j["body_a"], nearest) << at.transpose();
    EXPECT_NEAR(j["distance"].get<double>(), truth, 1e-9) << at.transpose();
    EXPECT_LE(j["lower_bound"].get<double>(), truth + 1e-12);
    EXPECT_EQ(j["work"]["body_pairs_queried"].get<int>(), queried) << at.transpose();
    EXPECT_EQ(j["work"]["body_pairs_bounded_by_boxes"].get<int>(), 2 - queried);
    // Signed: apart, the same answer (the second pair's apart query cut off at the first's).
    const Cli_run s = run("distance " + file + " sphere:0.5 --pose-b " + pose.str() + " --signed --json");
    ASSERT_EQ(s.exit_code, 0) << s.err;
    const auto k = nlohmann::json::parse(s.out);
    EXPECT_EQ(k["status"], "converged");
    EXPECT_EQ(k["overlap"], "none");
    EXPECT_EQ(k["body_a"], nearest) << at.transpose();
    EXPECT_NEAR(k["distance"].get<double>(), truth, 1e-9) << at.transpose();
    EXPECT_LE(k["lower_bound"].get<double>(), truth + 1e-12);
  }
}

// pr2ct.stp is a closed 200 mm box [0, 200]^3 (six trimmed planar faces): a ball of radius 30
// at its centre is inside it with surfaces 70 mm apart (b_inside_a, found by the winding
// number), and leaves the box's hull after 100 + 30 mm along any axis; a ball through its
// +x face at x = 190 leaves it after 200 - 190 + 30 = 40 mm along +x.
TEST(DistanceCli, SignedStepBoxNestsABall) {
  const std::string file = std::string(EXTREMAL_SHARED_DATA) + "/step/pr2ct.stp";
  Cli_run r = run("distance " + file + " sphere:30 --pose-b 100,100,100 --signed --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["status"], "penetrating");
  EXPECT_EQ(j["overlap"], "b_inside_a");
  EXPECT_EQ(j["closed_a"]["closed"], true);
  EXPECT_GT(j["work"]["winding_cells"].get<long>(), 0);
  EXPECT_NEAR(j["distance"].get<double>(), -130.0, 1e-9);
  EXPECT_LE(j["lower_bound"].get<double>(), -130.0 + 1e-12);
  EXPECT_GE(j["upper_bound"].get<double>(), -130.0 - 1e-12);

  r = run("distance " + file + " sphere:30 --pose-b 190,100,120 --signed --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["overlap"], "surfaces_meet");
  EXPECT_NEAR(j["distance"].get<double>(), -40.0, 1e-9);
  EXPECT_LE(j["lower_bound"].get<double>(), -40.0 + 1e-12);
  EXPECT_GE(j["upper_bound"].get<double>(), -40.0 - 1e-12);
  EXPECT_NEAR((vec(j["normal"]) - Vec3(1, 0, 0)).norm(), 0.0, 1e-6);
}

}  // namespace
}  // namespace extremal
