// bench/compare scenario (d): a moving body over a real assembly, the time of a scene step.
//
// The as1 assembly of the shared data set (step/as1-oc-214-mat.stp, 18 solids) stands still;
// one body moves over it on a straight line at constant speed, apart from every solid
// throughout, and Scene_stepper steps all the moving body's pairs with the solids:
//   (d1) a ball (the sphere of the shape specs, make_sphere_body) of radius 5% of the assembly's
//        box diagonal, spinning slowly, passes above all 18 solids along x, 3% of the diagonal
//        above the assembly's box and 2% off its plane of symmetry (18 pairs);
//   (d2) a point probe (make_point_body) passes over the highest solid, 1% of that solid's box
//        diagonal above its box top (18 pairs; and the passed solid's pair alone, for the cost
//        of that one pair).
// Each at 100 Hz and 1 kHz over the same motion (--quick: its middle tenth). A step is timed
// around Scene_stepper::step (all its pairs; the stepper evaluates the bodies' motions itself,
// timed apart below, well under a microsecond a body); the first step, which seeds every pair
// by the certified solver, is reported apart. The 18-pair cases run a second time pair by pair,
// as `extremal report` runs a scene (one stepper per pair, each pair through all its steps in
// turn; a scene step's time the sum of its pairs' there): the same work, in another order for
// the caches. Accuracy: at evenly spread frames, the tracked
// minimum over the pairs (and each pair's distance) against the certified one-shot solver
// (extremal_distance at 1e-12) at the same poses, computed once per case before the runs.
#include "compare_assembly.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "algorithms/distance/Global_distance.h"
#include "algorithms/scene/Scene_stepper.h"
#include "io/Model_reader.h"
#include "kernel/Motion.h"
#include "kernel/Shapes.h"

namespace extremal::bench {

namespace {

using Clock = std::chrono::steady_clock;

constexpr double k_ball_radius = 0.05;     // of the assembly's box diagonal
constexpr double k_ball_clearance = 0.03;  // ball above the assembly's box top, of the diagonal
// The ball's line off the assembly's plane of symmetry (y = 75 mm), on which the rod's and four
// nuts' axes lie: a ball centred over an axis has its witnesses on the seams (bench/RESULTS.md).
constexpr double k_ball_offset = 0.02;  // of the diagonal, along y
const Vec3 k_ball_spin(0.4, 0.7, 1.0);  // rad/s about its centre
constexpr double k_probe_clearance = 0.01;  // probe above the passed solid's box, of its diagonal
constexpr double k_probe_run_out = 0.25;    // probe's start and end beyond that box, of its diagonal
constexpr double k_pass_seconds = 1.0;      // the whole pass
constexpr double k_quick_from = 0.45, k_quick_to = 0.55;  // --quick: the pass's middle tenth
constexpr int k_checked_frames = 11;        // frames checked against the certified solver
constexpr int k_quick_checked_frames = 3;
constexpr double k_certified_tolerance = 1e-12;

volatile double g_sink = 0.0;

double micros_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
}

// Nearest rank, as the CLI's step-time summary (cli/Step_times): the ceil(p n / 100)-th smallest.
double percentile(std::vector<double> v, int percent) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  const std::size_t rank = (static_cast<std::size_t>(percent) * v.size() + 99) / 100;
  return v[std::clamp<std::size_t>(rank, 1, v.size()) - 1];
}
double mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return v.empty() ? std::numeric_limits<double>::quiet_NaN() : s / static_cast<double>(v.size());
}

// A body moving over the assembly, paired with some of its solids.
struct Pass_case {
  std::string label;
  Body mover;
  Motion motion = Motion::still(Rigid_pose_3());
  std::vector<int> solids;  // indices into the assembly's solids
  // The certified distance of each pair at the checked times (filled before the runs).
  std::vector<double> check_times;
  std::vector<std::vector<double>> certified;  // [check][pair]
  int uncertified = 0;
};

struct Assembly {
  std::vector<Body> solids;
  std::vector<Distance_hierarchy> hierarchies;
  Motion still = Motion::still(Rigid_pose_3());
};

void certify(const Assembly& as, Pass_case& c, double t_begin, double t_end, int frames) {
  const Distance_hierarchy mover(c.mover);
  Distance_workspace ws;
  Distance_request request;
  request.absolute_tolerance = request.relative_tolerance = k_certified_tolerance;
  for (int j = 0; j < frames; ++j) {
    const double t = t_begin + (t_end - t_begin) * j / (frames - 1);
    const Rigid_pose_3 X = c.motion.pose_at(t) * c.mover.placement;
    std::vector<double> d;
    for (int i : c.solids) {
      const Distance_result r = extremal_distance(as.hierarchies[static_cast<std::size_t>(i)],
                                                  as.solids[static_cast<std::size_t>(i)].placement,
                                                  mover, X, request, ws);
      if (!r.is_certified()) ++c.uncertified;
      d.push_back(r.distance);
    }
    c.check_times.push_back(t);
    c.certified.push_back(std::move(d));
  }
}

void run_case(const Assembly& as, const Pass_case& c, double rate, double t_begin, double t_end,
              bool pair_by_pair) {
  const double dt = 1.0 / rate;
  const long steps = std::lround((t_end - t_begin) * rate);
  std::vector<Scene_stepper_body> bodies;
  for (const Body& b : as.solids) bodies.push_back({&b, &as.still});
  const int mover = static_cast<int>(bodies.size());
  bodies.push_back({&c.mover, &c.motion});
  std::vector<std::pair<int, int>> pairs;
  for (int i : c.solids) pairs.emplace_back(i, mover);
  // The checked times' frames at this rate (the times lie on both rates' grids).
  std::vector<long> checked;
  for (double t : c.check_times) checked.push_back(std::lround((t - t_begin) * rate));

  // Every step's reports (distance, solved, status) and time, in either order.
  const std::size_t n = static_cast<std::size_t>(steps) + 1;
  std::vector<std::vector<Pair_report>> reports(n, std::vector<Pair_report>(pairs.size()));
  std::vector<double> times(n, 0.0);
  std::vector<Pair_statistics> statistics;
  if (!pair_by_pair) {
    Scene_stepper stepper(bodies, pairs, Body_pair_options{});
    for (std::size_t i = 0; i < n; ++i) {
      const auto t0 = Clock::now();
      const std::vector<Pair_report>& r = stepper.step(t_begin + static_cast<double>(i) * dt, dt);
      times[i] = micros_since(t0);
      reports[i] = r;
    }
    for (std::size_t k = 0; k < pairs.size(); ++k) statistics.push_back(stepper.statistics(k));
  } else {
    // As `extremal report` runs a scene (cli/Scene_run): one stepper per pair, each pair
    // through all its steps in turn, a scene step's time the sum of its pairs' times there.
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      Scene_stepper stepper({bodies[static_cast<std::size_t>(pairs[k].first)], bodies.back()},
                            {{0, 1}}, Body_pair_options{});
      for (std::size_t i = 0; i < n; ++i) {
        const auto t0 = Clock::now();
        reports[i][k] = stepper.step(t_begin + static_cast<double>(i) * dt, dt).front();
        times[i] += micros_since(t0);
      }
      statistics.push_back(stepper.statistics(0));
    }
  }
  const double start_us = times[0];
  const std::vector<double> step_us(times.begin() + 1, times.end());
  std::vector<double> tracked_min(n);
  std::vector<std::vector<double>> tracked_at_checks;
  long solved = 0, off_apart = 0;
  for (std::size_t i = 0; i < n; ++i) {
    double least = HUGE_VAL;
    for (const Pair_report& r : reports[i]) {
      least = std::min(least, std::isfinite(r.distance) ? r.distance : -HUGE_VAL);
      solved += r.solved;
      off_apart += r.status != Pair_status::Tracking && r.status != Pair_status::Boundary;
    }
    tracked_min[i] = least;
    if (std::find(checked.begin(), checked.end(), static_cast<long>(i)) != checked.end()) {
      std::vector<double> d;
      for (const Pair_report& r : reports[i]) d.push_back(r.distance);
      tracked_at_checks.push_back(std::move(d));
    }
  }
  // The motions' poses and twists, as Scene_stepper::step evaluates them, timed apart.
  const auto t_motion = Clock::now();
  double sink = 0.0;
  for (long i = 0; i <= steps; ++i)
    for (const Scene_stepper_body& b : bodies) {
      const double t = t_begin + static_cast<double>(i) * dt;
      sink += (b.motion->pose_at(t) * b.body->placement).translation().x() +
              b.motion->twist_at(t).linear.x();
    }
  const double motion_us = micros_since(t_motion) / static_cast<double>(steps + 1);
  g_sink = sink;  // (kept, so that the loop is not optimised away)

  double err_min = 0.0, err_pair = 0.0;
  std::size_t worst_pair = 0, worst_check = 0;
  for (std::size_t j = 0; j < tracked_at_checks.size(); ++j) {
    const std::vector<double>& got = tracked_at_checks[j];
    const std::vector<double>& want = c.certified[j];
    double got_min = HUGE_VAL, want_min = HUGE_VAL;
    for (std::size_t k = 0; k < got.size(); ++k) {
      got_min = std::min(got_min, got[k]);
      want_min = std::min(want_min, want[k]);
      const double e = std::isfinite(got[k]) ? std::abs(got[k] - want[k]) : HUGE_VAL;
      if (e > err_pair) err_pair = e, worst_pair = k, worst_check = j;
    }
    err_min = std::max(err_min, std::abs(got_min - want_min));
  }
  long restricted = 0;
  for (const Pair_statistics& st : statistics) restricted += st.vacated_solves;
  // Where the time goes (stderr): the slowest steps, and the pairs whose restricted solves made
  // the most sub-patch nodes (a repeatable measure of their work).
  std::vector<std::size_t> order(step_us.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  const std::size_t shown = std::min<std::size_t>(5, order.size());
  std::partial_sort(order.begin(), order.begin() + static_cast<long>(shown), order.end(),
                    [&](std::size_t x, std::size_t y) { return step_us[x] > step_us[y]; });
  std::fprintf(stderr, "(d) %s%s, %g Hz: slowest steps", c.label.c_str(),
               pair_by_pair ? ", pair by pair" : "", rate);
  for (std::size_t i = 0; i < shown; ++i)
    std::fprintf(stderr, " %zu (%.0f us)", order[i] + 1, step_us[order[i]]);
  std::vector<std::size_t> by_nodes(pairs.size());
  for (std::size_t k = 0; k < by_nodes.size(); ++k) by_nodes[k] = k;
  std::sort(by_nodes.begin(), by_nodes.end(), [&](std::size_t x, std::size_t y) {
    return statistics[x].vacated_nodes > statistics[y].vacated_nodes;
  });
  std::fprintf(stderr, "; pairs by restricted-solve nodes:");
  for (std::size_t i = 0; i < std::min<std::size_t>(3, by_nodes.size()); ++i) {
    const Pair_statistics& st = statistics[by_nodes[i]];
    std::fprintf(stderr, " %s (%ld solves, %ld nodes, %ld seeds, %ld broad phases, %d candidates)",
                 as.solids[static_cast<std::size_t>(pairs[by_nodes[i]].first)].name.c_str(),
                 st.vacated_solves, st.vacated_nodes, st.seeds, st.broad_phases, st.candidates);
  }
  if (err_pair > 0.0)
    std::fprintf(stderr, "; largest pair error %.1e: %s at t = %g (tracked %.12g, certified %.12g)",
                 err_pair, as.solids[static_cast<std::size_t>(pairs[worst_pair].first)].name.c_str(),
                 c.check_times[worst_check], tracked_at_checks[worst_check][worst_pair],
                 c.certified[worst_check][worst_pair]);
  std::fprintf(stderr, "\n");
  std::printf("| %s | %zu | %.0f Hz | %ld | %.1f | %.0f | **%.0f** | %.0f | %.0f | %.2f | %.2f | "
              "%ld | %ld | %.4g | %zu | %.1e | %.1e |\n",
              (c.label + (pair_by_pair ? ", pair by pair" : "")).c_str(), pairs.size(), rate, steps,
              start_us * 1e-3, mean(step_us),
              percentile(step_us, 50), percentile(step_us, 99), percentile(step_us, 100),
              motion_us, static_cast<double>(restricted) / static_cast<double>(steps),
              solved, off_apart, *std::min_element(tracked_min.begin(), tracked_min.end()),
              tracked_at_checks.size(), err_min, err_pair);
  std::fflush(stdout);
}

Bbox_3 box_of(const Body& b) { return b.trimmed_bbox(b.placement); }

}  // namespace

int run_assembly_scenario(bool quick, const std::string& data) {
  const std::string file = data + "/step/as1-oc-214-mat.stp";
  Assembly as;
  try {
    as.solids = io::load_bodies(file, "mm", "mm");
  } catch (const std::exception& e) {
    std::printf("\n(d) skipped: %s\n", e.what());
    return 0;
  }
  for (const Body& b : as.solids) as.hierarchies.emplace_back(b);
  Bbox_3 box;
  for (const Body& b : as.solids) box += box_of(b);
  const double diagonal = box_diagonal(box);
  const Vec3 centre = box_centre(box);
  const double t_begin = quick ? k_quick_from * k_pass_seconds : 0.0;
  const double t_end = quick ? k_quick_to * k_pass_seconds : k_pass_seconds;
  const int frames = quick ? k_quick_checked_frames : k_checked_frames;
  std::vector<int> all;
  for (int i = 0; i < static_cast<int>(as.solids.size()); ++i) all.push_back(i);

  std::vector<Pass_case> cases;
  {  // (d1) the ball along x over the middle of the assembly, its box clear of the assembly's.
    Pass_case c;
    const double r = k_ball_radius * diagonal;
    char label[96];
    std::snprintf(label, sizeof label, "(d1) ball (r %.1f) over all solids", r);
    c.label = label;
    c.mover = make_sphere_body(r, "ball");
    const double z = box.zmax() + r + k_ball_clearance * diagonal;
    const double y = centre.y() + k_ball_offset * diagonal;
    const Vec3 from(box.xmin() - r, y, z), to(box.xmax() + r, y, z);
    Twist_3 v;
    v.linear = (to - from) / k_pass_seconds;
    v.angular = k_ball_spin;
    c.motion = Motion::twist(Rigid_pose_3(Mat3::Identity(), from), v, 0.0);
    c.solids = all;
    std::printf("\n### (d) a body moving over the as1 assembly: time per scene step\n\n");
    std::printf("%s: %zu solids, box %.1f x %.1f x %.1f mm, diagonal %.1f mm. (d1) ball r = %.2f mm "
                "from (%.2f, %.2f, %.2f) along x at %.1f mm/s, %.2f mm above the box (spinning "
                "%.1f rad/s).",
                file.c_str(), as.solids.size(), box.xmax() - box.xmin(), box.ymax() - box.ymin(),
                box.zmax() - box.zmin(), diagonal, r, from.x(), from.y(), from.z(), v.linear.norm(),
                k_ball_clearance * diagonal, k_ball_spin.norm());
    cases.push_back(std::move(c));
  }
  {  // (d2) the point over the highest solid (no other solid reaches above its box).
    std::size_t top = 0;
    for (std::size_t i = 1; i < as.solids.size(); ++i)
      if (box_of(as.solids[i]).zmax() > box_of(as.solids[top]).zmax()) top = i;
    const Bbox_3 part = box_of(as.solids[top]);
    const double size = box_diagonal(part);
    const Vec3 c_part = box_centre(part);
    const double z = part.zmax() + k_probe_clearance * size;
    const Vec3 from(part.xmin() - k_probe_run_out * size, c_part.y(), z),
        to(part.xmax() + k_probe_run_out * size, c_part.y(), z);
    Twist_3 v;
    v.linear = (to - from) / k_pass_seconds;
    Pass_case c;
    c.mover = make_point_body("probe");
    c.motion = Motion::twist(Rigid_pose_3(Mat3::Identity(), from), v, 0.0);
    c.solids = all;
    const std::string name = as.solids[top].name;
    std::printf(" (d2) point probe from (%.2f, %.2f, %.2f) along x at %.1f mm/s, %.2f mm above "
                "the box of %s (%zu faces, diagonal %.1f mm).\n",
                from.x(), from.y(), from.z(), v.linear.norm(), k_probe_clearance * size, name.c_str(),
                as.solids[top].faces.size(), size);
    c.label = "(d2) point over " + name;
    cases.push_back(c);
    c.label = "(d2) point over " + name + ", its pair only";
    c.solids = {static_cast<int>(top)};
    cases.push_back(std::move(c));
  }
  std::printf("\nTimes per scene step in us (all its pairs; the first step, which seeds them, is "
              "the start); motions: the bodies' poses and twists, timed apart; restricted "
              "solves: of candidate pairs without a tracker; solved: pair rows the certified "
              "solver answered; not apart: pair rows not Tracking or Boundary; pair by pair: one "
              "stepper per pair, each through all its steps in turn, as extremal report runs a "
              "scene. Errors at the "
              "checked frames against extremal_distance at %.0e: of the minimum over the pairs, "
              "and of any pair.\n\n",
              k_certified_tolerance);
  const auto t_certify = Clock::now();
  for (Pass_case& c : cases) certify(as, c, t_begin, t_end, frames);
  int uncertified = 0;
  for (const Pass_case& c : cases) uncertified += c.uncertified;
  std::printf("| case | pairs | rate | steps | start (ms) | mean | median | p99 | max | motions | "
              "restricted solves per step | solved | not apart | least distance (mm) | checked "
              "frames | max error of the minimum | max error of a pair |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  std::fflush(stdout);
  std::fprintf(stderr, "(d) certified references: %.1f s\n", micros_since(t_certify) * 1e-6);
  for (const Pass_case& c : cases)
    for (bool pair_by_pair : {false, true}) {
      if (pair_by_pair && c.solids.size() == 1) continue;
      for (double rate : {100.0, 1000.0}) {
        const auto t0 = Clock::now();
        run_case(as, c, rate, t_begin, t_end, pair_by_pair);
        std::fprintf(stderr, "(d) %s at %g Hz: %.1f s\n", c.label.c_str(), rate,
                     micros_since(t0) * 1e-6);
      }
    }
  if (uncertified)
    std::printf("\n%d certified references were not certified (budget or resolution).\n", uncertified);
  return 0;
}

}  // namespace extremal::bench
