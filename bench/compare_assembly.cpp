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
// --budget-sweep (run_assembly_budget_sweep, compare_budget.h): (d1) and (d2) over all solids at
// 1 kHz at each swept budget, and FCL (BVHModel<OBBRSS>) on our tessellations
// (kernel/Tessellation.h) of the ball and the solids at the checked frames' poses, against the
// same certified distances.
#include "compare_assembly.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <iterator>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "algorithms/distance/Global_distance.h"
#include "algorithms/scene/Scene_stepper.h"
#include "compare_budget.h"
#include "io/Model_reader.h"
#include "kernel/Motion.h"
#include "kernel/Shapes.h"
#include "kernel/Tessellation.h"
#include "support/Fcl_bridge.h"

#include <fcl/narrowphase/distance.h>

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
// --budget-sweep: the trackers' rate, and FCL's tessellations of the ball and the solids, their
// deflections of the assembly's box diagonal (--quick: the first two).
constexpr double k_sweep_rate = 1000.0;
constexpr double k_fcl_deflections[] = {1e-3, 1e-4, 1e-5};

volatile double g_sink = 0.0;

double micros_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
}

// Nearest rank, as the CLI's step-time summary (algorithms/scene/Step_times): the ceil(p n / 100)-th smallest.
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

// A case stepped at one rate: every step's reports (distance, solved, status) and time, in
// either order, and each pair's statistics.
struct Stepped_case {
  double dt = 0.0;
  long steps = 0;
  std::vector<Scene_stepper_body> bodies;  // the solids, then the mover
  std::vector<std::pair<int, int>> pairs;
  std::vector<long> checked;  // the checked times' steps
  std::vector<std::vector<Pair_report>> reports;  // [step][pair]
  std::vector<double> times;
  std::vector<Pair_statistics> statistics;
};

Stepped_case step_case(const Assembly& as, const Pass_case& c, double rate, double t_begin,
                       double t_end, bool pair_by_pair, const Body_pair_options& options) {
  Stepped_case s;
  auto& [dt, steps, bodies, pairs, checked, reports, times, statistics] = s;
  dt = 1.0 / rate;
  steps = std::lround((t_end - t_begin) * rate);
  for (const Body& b : as.solids) bodies.push_back({&b, &as.still});
  const int mover = static_cast<int>(bodies.size());
  bodies.push_back({&c.mover, &c.motion});
  for (int i : c.solids) pairs.emplace_back(i, mover);
  // (The checked times lie on every rate's grid.)
  for (double t : c.check_times) checked.push_back(std::lround((t - t_begin) * rate));

  const std::size_t n = static_cast<std::size_t>(steps) + 1;
  reports.assign(n, std::vector<Pair_report>(pairs.size()));
  times.assign(n, 0.0);
  if (!pair_by_pair) {
    Scene_stepper stepper(bodies, pairs, options);
    for (std::size_t i = 0; i < n; ++i) {
      const auto t0 = Clock::now();
      const std::vector<Pair_report>& r = stepper.step(t_begin + static_cast<double>(i) * dt, dt);
      times[i] = micros_since(t0);
      reports[i] = r;
    }
    for (std::size_t k = 0; k < pairs.size(); ++k) statistics.push_back(stepper.statistics(k));
  } else {
    // As `extremal report` runs a scene (Scene_stepper::run): each pair, each pair
    // through all its steps in turn, a scene step's time the sum of its pairs' times there.
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      Scene_stepper stepper({bodies[static_cast<std::size_t>(pairs[k].first)], bodies.back()},
                            {{0, 1}}, options);
      for (std::size_t i = 0; i < n; ++i) {
        const auto t0 = Clock::now();
        reports[i][k] = stepper.step(t_begin + static_cast<double>(i) * dt, dt).front();
        times[i] += micros_since(t0);
      }
      statistics.push_back(stepper.statistics(0));
    }
  }
  return s;
}

void run_case(const Assembly& as, const Pass_case& c, double rate, double t_begin, double t_end,
              bool pair_by_pair) {
  const Stepped_case stepped =
      step_case(as, c, rate, t_begin, t_end, pair_by_pair, Body_pair_options{});
  const long steps = stepped.steps;
  const std::vector<Scene_stepper_body>& bodies = stepped.bodies;
  const std::vector<std::pair<int, int>>& pairs = stepped.pairs;
  const std::vector<long>& checked = stepped.checked;
  const std::vector<std::vector<Pair_report>>& reports = stepped.reports;
  const std::vector<double>& times = stepped.times;
  const std::vector<Pair_statistics>& statistics = stepped.statistics;
  const std::size_t n = static_cast<std::size_t>(steps) + 1;
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
      const double t = t_begin + static_cast<double>(i) * stepped.dt;
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

// The assembly, the cases passing over it, and the stretch of their motion that is run.
struct Assembly_scene {
  Assembly as;
  double diagonal = 0.0;  // of the assembly's box
  double t_begin = 0.0, t_end = 0.0;
  int frames = 0;  // checked frames
  std::vector<Pass_case> cases;
  std::string description;  // of the assembly and the cases, for the tables' preamble
};

// printf's formatting, into a string.
__attribute__((format(printf, 1, 2))) std::string formatted(const char* format, ...) {
  va_list args, sizing;
  va_start(args, format);
  va_copy(sizing, args);
  std::string text(static_cast<std::size_t>(std::vsnprintf(nullptr, 0, format, sizing)), '\0');
  va_end(sizing);
  std::vsnprintf(text.data(), text.size() + 1, format, args);
  va_end(args);
  return text;
}

// False (noted as skipped) when the file cannot be read.
bool set_up_scene(bool quick, const std::string& data, Assembly_scene& scene) {
  const std::string file = data + "/step/as1-oc-214-mat.stp";
  Assembly& as = scene.as;
  try {
    as.solids = io::load_bodies(file, "mm", "mm");
  } catch (const std::exception& e) {
    std::printf("\n(d) skipped: %s\n", e.what());
    return false;
  }
  for (const Body& b : as.solids) as.hierarchies.emplace_back(b);
  Bbox_3 box;
  for (const Body& b : as.solids) box += box_of(b);
  const double diagonal = box_diagonal(box);
  const Vec3 centre = box_centre(box);
  scene.diagonal = diagonal;
  scene.t_begin = quick ? k_quick_from * k_pass_seconds : 0.0;
  scene.t_end = quick ? k_quick_to * k_pass_seconds : k_pass_seconds;
  scene.frames = quick ? k_quick_checked_frames : k_checked_frames;
  std::vector<int> all;
  for (int i = 0; i < static_cast<int>(as.solids.size()); ++i) all.push_back(i);

  std::vector<Pass_case>& cases = scene.cases;
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
    scene.description = formatted(
        "%s: %zu solids, box %.1f x %.1f x %.1f mm, diagonal %.1f mm. (d1) ball r = %.2f mm "
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
    scene.description += formatted(
        " (d2) point probe from (%.2f, %.2f, %.2f) along x at %.1f mm/s, %.2f mm above the box "
        "of %s (%zu faces, diagonal %.1f mm).\n",
        from.x(), from.y(), from.z(), v.linear.norm(), k_probe_clearance * size, name.c_str(),
        as.solids[top].faces.size(), size);
    c.label = "(d2) point over " + name;
    cases.push_back(c);
    c.label = "(d2) point over " + name + ", its pair only";
    c.solids = {static_cast<int>(top)};
    cases.push_back(std::move(c));
  }
  return true;
}

// The tracker over a case's pairs at one budget (Body_pair_options' defaults otherwise), its
// steps' median time and its errors at the checked frames: a row of the budget sweep.
Budget_sweep_row budget_sweep_row(const Assembly_scene& scene, const Pass_case& c, double budget) {
  Body_pair_options options;
  options.tolerance = {budget, budget};
  const Stepped_case stepped =
      step_case(scene.as, c, k_sweep_rate, scene.t_begin, scene.t_end, false, options);
  Budget_sweep_row row;
  row.method = "Scene_stepper";
  row.mover = c.mover.name;
  row.series = formatted("Scene_stepper, %s, %g Hz", c.mover.name.c_str(), k_sweep_rate);
  row.point_label = formatted("%.0e", budget);
  row.setting = formatted("%s, %g Hz (start %.1f ms)", c.label.c_str(), k_sweep_rate,
                          stepped.times[0] * 1e-3);
  row.frames = stepped.steps;
  row.median_us = percentile({stepped.times.begin() + 1, stepped.times.end()}, 50);
  row.max_error = 0.0;
  Budget_check check{options.tolerance};
  for (std::size_t j = 0; j < stepped.checked.size(); ++j) {
    const std::vector<Pair_report>& got = stepped.reports[static_cast<std::size_t>(stepped.checked[j])];
    for (std::size_t k = 0; k < got.size(); ++k) {
      if (!std::isfinite(got[k].distance)) {
        ++row.failures;
        continue;
      }
      const double error = std::abs(got[k].distance - c.certified[j][k]);
      row.max_error = std::max(row.max_error, error);
      check.add_error(error, c.certified[j][k]);
    }
  }
  for (const std::vector<Pair_report>& step : stepped.reports)
    for (const Pair_report& r : step) check.add_report(r);
  row.check = check;
  return row;
}

// FCL's distances between a moving body and each of its solids at the checked times, on our
// tessellations (kernel/Tessellation.h) of both at `deflection`, the queries of a frame timed
// together: a row of FCL's ladder in the budget sweep.
Budget_sweep_row fcl_ladder_row(const Assembly& as, const Pass_case& c, double deflection) {
  const auto t_build = Clock::now();
  Tessellation_options options;
  options.deflection = deflection;
  auto model_of = [&](const Body& body, const Rigid_pose_3& placement, std::size_t& triangles) {
    Tessellation t;
    tessellate(body, placement, 0, options, t);
    triangles += t.mesh.triangles.size();
    return fcl_model(t.mesh);
  };
  std::size_t solid_triangles = 0, mover_triangles = 0;
  std::vector<std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>>> solids;
  for (int i : c.solids) {
    const Body& solid = as.solids[static_cast<std::size_t>(i)];
    solids.push_back(model_of(solid, solid.placement, solid_triangles));
  }
  const auto mover = model_of(c.mover, Rigid_pose_3(), mover_triangles);  // placed by the motion
  Budget_sweep_row row;
  row.method = "FCL distance (OBBRSS)";
  row.mover = c.mover.name;
  row.series = "FCL distance, OBBRSS, " + c.mover.name;
  row.setting = formatted("deflection %.3g mm: %zu + %zu triangles (build %.2f s)", deflection,
                          solid_triangles, mover_triangles, micros_since(t_build) * 1e-6);
  row.point_label = formatted("%.2gM tri", static_cast<double>(solid_triangles + mover_triangles) * 1e-6);
  row.frames = static_cast<long>(c.check_times.size());
  row.max_error = 0.0;
  const fcl::DistanceRequestd request;
  std::vector<double> times;
  for (std::size_t j = 0; j < c.check_times.size(); ++j) {
    const fcl::Transform3d X = fcl_pose(c.motion.pose_at(c.check_times[j]) * c.mover.placement);
    std::vector<double> distance(solids.size());
    const auto t0 = Clock::now();
    for (std::size_t k = 0; k < solids.size(); ++k) {
      fcl::DistanceResultd result;
      fcl::distance(solids[k].get(), fcl::Transform3d::Identity(), mover.get(), X, request, result);
      distance[k] = result.min_distance;
    }
    times.push_back(micros_since(t0));
    for (std::size_t k = 0; k < solids.size(); ++k) {
      if (std::isfinite(distance[k]))
        row.max_error = std::max(row.max_error, std::abs(distance[k] - c.certified[j][k]));
      else
        ++row.failures;
    }
  }
  row.median_us = percentile(times, 50);
  return row;
}

}  // namespace

int run_assembly_scenario(bool quick, const std::string& data) {
  Assembly_scene scene;
  if (!set_up_scene(quick, data, scene)) return 0;
  const Assembly& as = scene.as;
  std::vector<Pass_case>& cases = scene.cases;
  const double t_begin = scene.t_begin, t_end = scene.t_end;
  std::printf("\n### (d) a body moving over the as1 assembly: time per scene step\n\n%s",
              scene.description.c_str());
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
  for (Pass_case& c : cases) certify(as, c, t_begin, t_end, scene.frames);
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

int run_assembly_budget_sweep(bool quick, const std::string& data, const std::string& out_dir) {
  Assembly_scene scene;
  if (!set_up_scene(quick, data, scene)) return 0;
  // The ball's and the probe's passes over all solids (not the probe's one pair alone).
  std::vector<Pass_case>& cases = scene.cases;
  cases.erase(std::remove_if(cases.begin(), cases.end(),
                             [](const Pass_case& c) { return c.solids.size() == 1; }),
              cases.end());
  const auto t_start = Clock::now();
  for (Pass_case& c : cases) certify(scene.as, c, scene.t_begin, scene.t_end, scene.frames);
  std::fprintf(stderr, "(d) certified references: %.1f s\n", micros_since(t_start) * 1e-6);
  Budget_sweep sweep;
  sweep.key = "d";
  sweep.title = "a ball and a probe over the as1 assembly";
  for (const Pass_case& c : cases)
    for (double budget : k_swept_budgets) {
      sweep.rows.push_back(budget_sweep_row(scene, c, budget));
      std::fprintf(stderr, "(d) %s, budget %g: %.0f s\n", c.label.c_str(), budget,
                   micros_since(t_start) * 1e-6);
    }
  // FCL's ladder for the ball (the probe is a point: no mesh), in the assembly's scale.
  const Pass_case& ball = cases.front();
  for (std::size_t i = 0; i < (quick ? 2 : std::size(k_fcl_deflections)); ++i) {
    sweep.rows.push_back(fcl_ladder_row(scene.as, ball, k_fcl_deflections[i] * scene.diagonal));
    std::fprintf(stderr, "(d) FCL %s: %.0f s\n", sweep.rows.back().setting.c_str(),
                 micros_since(t_start) * 1e-6);
  }
  sweep.notes = scene.description + formatted(
      "\nReference: extremal_distance at %.0e of each pair at %d checked frames. Tracker rows: "
      "Scene_stepper over all the moving body's pairs at %g Hz, Body_pair_options' defaults but "
      "the budget; time the median step (the first, which seeds the pairs, apart as the start); "
      "errors over the checked frames and the pairs. FCL rows: the ball's pairs (a point has no "
      "mesh: the probe's rows have no speed-up), BVHModel<OBBRSS> on our tessellations of the "
      "ball and of each solid at one deflection (1e-3, 1e-4 and 1e-5 of the assembly's "
      "diagonal; --quick: the first two), a frame's queries timed together, the median over the "
      "checked frames.",
      k_certified_tolerance, scene.frames, k_sweep_rate);
  report_budget_sweep(sweep, out_dir);
  return 0;
}

}  // namespace extremal::bench
