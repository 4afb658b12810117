// bench/compare scenario (e): mesh bodies against FCL on the same meshes and poses.
//
// Each pair: body B moves past body A (a line and a turn, apart throughout), sampled at 100 Hz
// and at 1 kHz over the same motion. Our Body_pair_tracker steps every frame (its certified
// front carried across steps, Mesh_front.h); FCL's distance query (BVHModel<OBBRSS>, Debian's
// libfcl) answers each frame from scratch, as FCL has no distance front. Both timed per frame
// in the same run; the distances compared frame by frame (relative difference). The front's
// statistics say where our time goes.
#include "compare_meshes.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "algorithms/body_pair/Body_pair_tracker.h"
#include "algorithms/mesh/Mesh_bvh.h"
#include "io/Model_reader.h"
#include "kernel/Error.h"
#include "support/Fcl_bridge.h"

#include <fcl/narrowphase/distance.h>
#include <fcl/narrowphase/detail/traversal/collision_node.h>
#include <fcl/narrowphase/detail/traversal/distance/mesh_distance_traversal_node.h>

namespace extremal::bench {

namespace {

using Clock = std::chrono::steady_clock;

double micros_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
}
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n == 0 ? NAN : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}
double mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return v.empty() ? NAN : s / static_cast<double>(v.size());
}

Body mesh_of(const std::string& path) {
  io::Model m = io::read_model(path);
  for (Body& b : m.bodies)
    if (!b.mesh.empty()) {
      // The mesh in its file frame (the motions place the file frame).
      for (Point_3& p : b.mesh.vertices) p = b.placement(p);
      b.placement = Rigid_pose_3();
      return std::move(b);
    }
  throw Invalid_input("'" + path + "' holds no mesh");
}

Vec3 centre(const Bbox_3& b) {
  return Vec3(0.5 * (b.xmin() + b.xmax()), 0.5 * (b.ymin() + b.ymax()), 0.5 * (b.zmin() + b.zmax()));
}
double diagonal(const Bbox_3& b) {
  return std::sqrt((b.xmax() - b.xmin()) * (b.xmax() - b.xmin()) + (b.ymax() - b.ymin()) * (b.ymax() - b.ymin()) +
                   (b.zmax() - b.zmin()) * (b.zmax() - b.zmin()));
}

// B passes A: from one side to the other along x, `clearance` above A's box in z, turning
// about a tilted axis through its centre.
struct Pass {
  Vec3 from, to, axis;
  double turn = 0.0;  // radians over the pass
  Rigid_pose_3 at(double s, const Vec3& b_centre) const {
    const Mat3 R = Eigen::AngleAxisd(turn * s, axis).toRotationMatrix();
    const Vec3 c = from + s * (to - from);
    return Rigid_pose_3(R, c - R * b_centre);  // B's box centre on the line
  }
};

struct Pair_case {
  std::string label;
  Body a, b;
  Pass pass;
};

Pair_case make_case(const std::string& label, Body a, Body b, double clearance) {
  Pair_case c{label, std::move(a), std::move(b), {}};
  const Bbox_3 ba = Mesh_bvh(c.a.mesh, c.a.name).box(), bb = Mesh_bvh(c.b.mesh, c.b.name).box();
  const Vec3 ca = centre(ba);
  const double ra = 0.5 * diagonal(ba), rb = 0.5 * diagonal(bb);
  // Over the top of A's box, B's bounding ball `clearance` (of A's size) above it: apart.
  const double z = ba.zmax() + rb + clearance * ra;
  c.pass.from = Vec3(ca.x() - 1.5 * (ra + rb), ca.y(), z);
  c.pass.to = Vec3(ca.x() + 1.5 * (ra + rb), ca.y() + 0.2 * ra, z - 0.9 * clearance * ra);  // (descending to a tenth of it)
  c.pass.axis = Vec3(0.3, 0.5, 1.0).normalized();
  c.pass.turn = 2.0;
  return c;
}

void run_case(const Pair_case& c, double rate, double duration) {
  const int frames = static_cast<int>(std::lround(rate * duration)) + 1;
  const Vec3 b_centre = centre(Mesh_bvh(c.b.mesh, c.b.name).box());
  std::vector<Rigid_pose_3> poses;
  for (int k = 0; k < frames; ++k) poses.push_back(c.pass.at(static_cast<double>(k) / (frames - 1), b_centre));

  // Ours: the hierarchies built once (timed apart), then a step per frame.
  const auto t_build = Clock::now();
  Body_pair_tracker tracker(c.a, c.b);
  const double ours_build_ms = micros_since(t_build) * 1e-3;
  std::vector<double> ours_us, ours_d;
  const Twist_3 still{};
  for (int k = 0; k < frames; ++k) {
    const auto t0 = Clock::now();
    const Pair_report& r = tracker.step(k / rate, Rigid_pose_3(), still, poses[static_cast<std::size_t>(k)], still, 1.0 / rate);
    ours_us.push_back(micros_since(t0));
    ours_d.push_back(r.distance);
  }
  const auto t_fcl = Clock::now();
  const auto A = fcl_model(c.a.mesh), B = fcl_model(c.b.mesh);
  const double fcl_build_ms = micros_since(t_fcl) * 1e-3;
  // Where the time goes: FCL's own counters on the same frames (not timed).
  long fcl_bv = 0, fcl_leaves = 0;
  for (int k = 0; k < frames; ++k) {
    fcl::detail::MeshDistanceTraversalNodeOBBRSS<double> node;
    fcl::DistanceRequestd counted;
    fcl::DistanceResultd res;
    fcl::detail::initialize(node, *A, fcl::Transform3d::Identity(), *B, fcl_pose(poses[static_cast<std::size_t>(k)]),
                            counted, res);
    node.enable_statistics = true;
    fcl::detail::distance(&node, nullptr, 2);
    fcl_bv += node.num_bv_tests;
    fcl_leaves += node.num_leaf_tests;
  }
  std::vector<double> fcl_us, fcl_d;
  fcl::DistanceRequestd request;
  for (int k = 0; k < frames; ++k) {
    fcl::DistanceResultd result;
    const auto t0 = Clock::now();
    fcl::distance(A.get(), fcl::Transform3d::Identity(), B.get(), fcl_pose(poses[static_cast<std::size_t>(k)]), request, result);
    fcl_us.push_back(micros_since(t0));
    fcl_d.push_back(result.min_distance);
  }
  double worst = 0.0, least = HUGE_VAL;
  for (int k = 0; k < frames; ++k) {
    const double d = fcl_d[static_cast<std::size_t>(k)];
    least = std::min(least, d);
    worst = std::max(worst, std::abs(ours_d[static_cast<std::size_t>(k)] - d) / std::max(std::abs(d), 1e-300));
  }
  // The first frame builds the front from the roots: the steps after it are the carried ones.
  std::vector<double> carried(ours_us.begin() + 1, ours_us.end());
  const Pair_statistics& st = tracker.statistics();
  const double per = static_cast<double>(frames);
  std::printf("| %s | %.0f Hz | %d | %.1f | %.1f | %.1f | %.1f | **%.2fx** | %.2fx | %.1e | %.3g | %.0f / %.0f | %.0f / %.0f | %.0f%% | %.0f / %.0f |\n",
              c.label.c_str(), rate, frames, median(carried), mean(carried), median(fcl_us), mean(fcl_us),
              median(fcl_us) / median(carried), mean(fcl_us) / mean(carried), worst, least,
              st.front_box_bounds / per, fcl_bv / per, st.front_triangle_pairs / per, fcl_leaves / per,
              100.0 * st.front_traversals / per, ours_build_ms, fcl_build_ms);
  std::fflush(stdout);
}

}  // namespace

int run_mesh_scenario(bool quick, const std::string& data, const std::string& large_mesh) {
  std::printf("\n### (e) meshes: our certified front against FCL (OBBRSS), same meshes and poses\n\n");
  std::printf("B passes over A, turning, apart throughout; time per frame in us (ours: the steps after "
              "the first, which builds the front); distances compared frame by frame.\n\n");
  std::printf("| pair | rate | frames | ours median | ours mean | FCL median | FCL mean | median ratio | "
              "mean ratio | max rel. diff. | least d | box tests per frame, ours / FCL | triangle pairs "
              "per frame, ours / FCL | steps from the roots | build ms ours / FCL |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  std::vector<Pair_case> cases;
  const std::string mesh_dir = data + "/mesh/";
  cases.push_back(make_case("Spider (1,368) past PGP torus (9,216)", mesh_of(mesh_dir + "mesh.modifier.PGPRemesh.torus.ply"),
                            mesh_of(mesh_dir + "Spider_binary.stl"), 0.05));
  cases.push_back(make_case("shape.stl past sphereWithHole.stl", mesh_of(mesh_dir + "sphereWithHole.stl"),
                            mesh_of(mesh_dir + "shape.stl"), 0.05));
  if (!large_mesh.empty())
    cases.push_back(make_case("Spider past " + large_mesh.substr(large_mesh.find_last_of('/') + 1), mesh_of(large_mesh),
                              mesh_of(mesh_dir + "Spider_binary.stl"), 0.05));
  const double duration = quick ? 0.5 : 2.0;
  for (const Pair_case& c : cases) {
    std::printf("| %s: %zu + %zu triangles | | | | | | | | | | | | | | |\n", c.label.c_str(),
                c.a.mesh.triangles.size(), c.b.mesh.triangles.size());
    for (double rate : {100.0, 1000.0}) run_case(c, rate, duration);
  }
  return 0;
}

}  // namespace extremal::bench
