// verify_report: runs a scene as `extremal report` does and checks its rows against the
// certified one-shot signed distance (`extremal distance --signed`) at the same poses, so that a
// claim about a scene's accuracy is one command anyone can rerun.
//
//   ./build/bench/verify_report SCENE.json... [--every N] [--tolerance E] [--seconds S]
//
// Every Nth step of every watched pair (and the last) is checked. Per row, against the
// reference s (certified, lower <= s <= upper):
//   - apart (the reference finds the bodies apart): error = |reported - s|, counted wrong when
//     it exceeds the tolerance plus the reference's own bound width plus the bodies' largest
//     edge tolerances (a file whose edges lie off their faces by that much is read on either);
//     Between two open sheets only the size is compared (their sign is A's normal's);
//   - overlapping: a row reading the bodies apart is a wrong sign. The depth is compared only
//     where the reference's is the bodies' own (both certified convex: the minimum translation
//     distance); otherwise it is the hulls' depth, a bound, and the row is only counted;
//   - a `farther` row's distance is a lower bound: wrong when above the reference's upper bound;
//   - a NaN or infinite distance is always wrong; uncertified references are counted, not judged.
// Prints one line per pair and, with --rows, one per wrong row. Exit code 0 when no row is wrong,
// 3 when some is, 1 on bad input.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "algorithms/distance/Distance_hierarchy.h"
#include "algorithms/distance/Penetration_depth.h"
#include "cli/Scene_run.h"
#include "io/Model_reader.h"
#include "io/Scene.h"
#include "kernel/Error.h"

namespace {

using namespace extremal;
using io::Scene_body;

struct Pair_tally {
  int rows = 0, apart = 0, overlapping = 0, hull_depth_rows = 0, farther = 0, unjudged = 0;
  int wrong = 0, wrong_sign = 0, not_finite = 0;
  double max_apart_error = 0.0, t_max_apart_error = 0.0;
  double max_depth_error = 0.0;  // convex bodies only
  double reference_seconds = 0.0;
};

struct Options {
  std::vector<std::string> scenes;
  int every = 10;
  double tolerance = 1e-6;
  double seconds = 30.0;
  bool rows = false;
};

// The largest edge tolerance of a body (the file's, raised to the measured gap between an
// edge's curve and its faces): its faces and edges disagree by up to this, and a minimum on a
// face's side may be read on either.
double edge_tolerance(const Body& body) {
  double t = 0.0;
  for (const Edge& e : body.edges) t = std::max(t, e.tolerance);
  return t;
}

void judge_row(const Options& o, const io::Scene& scene, int k, double t, const Pair_report& r,
               const Signed_distance_result& ref, double model_tolerance, bool sheets,
               Pair_tally& tally) {
  const auto& [ia, ib] = scene.pairs[k];
  const std::string who = scene.bodies[ia].name + " - " + scene.bodies[ib].name;
  auto wrong = [&](const char* what, double expected) {
    ++tally.wrong;
    if (o.rows)
      std::printf(
          "  t = %.9g %s: %s: reported %.12g (%s, faces %d %d), reference %.12g in [%.12g, "
          "%.12g] (%s, %s, %s %d, %s %d)\n",
          t, who.c_str(), what, r.distance, to_string(r.status), r.feature_a, r.feature_b,
          expected, ref.lower_bound, ref.upper_bound, to_string(ref.status),
          to_string(ref.overlap), to_string(ref.kind_a), ref.element_a, to_string(ref.kind_b),
          ref.element_b);
  };
  ++tally.rows;
  if (!std::isfinite(r.distance)) {
    ++tally.not_finite;
    wrong("not finite", ref.distance);
    return;
  }
  if (r.status == Pair_status::Farther) {  // beyond the threshold: a bound
    ++tally.farther;
    if (ref.is_certified() && r.distance > ref.upper_bound + o.tolerance)
      wrong("farther bound above the distance", ref.distance);
    return;
  }
  if (!ref.is_certified()) {
    ++tally.unjudged;
    return;
  }
  const double width = ref.upper_bound - ref.lower_bound;
  const double allowed =
      o.tolerance * std::max(1.0, std::abs(ref.distance)) + width + model_tolerance;
  if (ref.overlap == Overlap_kind::None) {
    ++tally.apart;
    // Two open sheets read their sign from A's normal (README: a plane passed through another
    // stays behind it), which the reference, with no inside to either, does not.
    const double reported = sheets ? std::abs(r.distance) : r.distance;
    const double e = std::abs(reported - ref.distance);
    if (e > tally.max_apart_error) {
      tally.max_apart_error = e;
      tally.t_max_apart_error = t;
    }
    if (e > allowed) wrong("apart, off", ref.distance);
    return;
  }
  ++tally.overlapping;
  if (r.distance > allowed) {
    ++tally.wrong_sign;
    wrong("overlapping, read apart", ref.distance);
    return;
  }
  if (!ref.depth_is_translation_distance) {
    ++tally.hull_depth_rows;
    return;
  }
  const double e = std::abs(r.distance - ref.distance);
  tally.max_depth_error = std::max(tally.max_depth_error, e);
  if (e > allowed) wrong("convex depth, off", ref.distance);
}

int verify(const Options& o, const std::string& path) {
  const io::Scene scene = io::read_scene(path, io::load_bodies);
  std::vector<std::unique_ptr<Distance_hierarchy>> hierarchies(scene.bodies.size());
  auto hierarchy = [&](int i) -> const Distance_hierarchy& {
    if (!hierarchies[i]) hierarchies[i] = std::make_unique<Distance_hierarchy>(scene.bodies[i].body);
    return *hierarchies[i];
  };
  std::vector<double> edge_tolerances;
  for (const Scene_body& b : scene.bodies) edge_tolerances.push_back(edge_tolerance(b.body));
  Signed_distance_request request;
  request.total_seconds = o.seconds;

  std::vector<Pair_tally> tallies(scene.pairs.size());
  const int steps = scene.step_count();
  double stepping = 0.0;
  cli::Scene_run run(scene, cli::Scene_run_options{});
  auto clock = std::chrono::steady_clock::now();
  run.run([&](int step, double t, const std::vector<Pair_report>& reports) {
    stepping += std::chrono::duration<double>(std::chrono::steady_clock::now() - clock).count();
    if (step % o.every == 0 || step == steps - 1) {
      for (std::size_t k = 0; k < reports.size(); ++k) {
        const auto& [ia, ib] = scene.pairs[k];
        const auto t0 = std::chrono::steady_clock::now();
        // The body frame sits at the entry's pose times the body's placement in its file.
        const Scene_body& A = scene.bodies[ia];
        const Scene_body& B = scene.bodies[ib];
        const Signed_distance_result ref = signed_distance(
            A.body, hierarchy(ia), A.motion.pose_at(t) * A.body.placement, B.body, hierarchy(ib),
            B.motion.pose_at(t) * B.body.placement, request);
        tallies[k].reference_seconds +=
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        judge_row(o, scene, static_cast<int>(k), t, reports[k], ref,
                  edge_tolerances[ia] + edge_tolerances[ib],
                  !ref.closed_a.closed && !ref.closed_b.closed, tallies[k]);
      }
    }
    clock = std::chrono::steady_clock::now();
  });

  int wrong = 0;
  std::printf("%s: %d steps, stepping %.3g s (%.3g ms per step, all pairs)\n", path.c_str(), steps,
              stepping, 1e3 * stepping / std::max(1, steps));
  for (std::size_t k = 0; k < tallies.size(); ++k) {
    const Pair_tally& p = tallies[k];
    const auto& [ia, ib] = scene.pairs[k];
    std::printf(
        "  %s - %s: %d rows checked (%d apart, %d overlapping of which %d hull depth, %d farther, "
        "%d reference uncertified): %d wrong (%d wrong sign, %d not finite); max apart error "
        "%.3g at t = %.9g; max convex depth error %.3g; reference %.3g s\n",
        scene.bodies[ia].name.c_str(), scene.bodies[ib].name.c_str(), p.rows, p.apart,
        p.overlapping, p.hull_depth_rows, p.farther, p.unjudged, p.wrong, p.wrong_sign,
        p.not_finite, p.max_apart_error, p.t_max_apart_error, p.max_depth_error,
        p.reference_seconds);
    wrong += p.wrong;
  }
  return wrong;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"Checks a scene's report rows against the certified signed distance"};
  app.add_option("scenes", o.scenes, "Scene file(s)")->required();
  app.add_option("--every", o.every, "Check every Nth step (and the last)")
      ->check(CLI::PositiveNumber);
  app.add_option("--tolerance", o.tolerance,
                 "Allowed error, relative to max(1, |distance|), beyond the reference's width")
      ->check(CLI::PositiveNumber);
  app.add_option("--seconds", o.seconds, "Time limit of each reference query")
      ->check(CLI::PositiveNumber);
  app.add_flag("--rows", o.rows, "Print every wrong row");
  CLI11_PARSE(app, argc, argv);
  int wrong = 0;
  for (const std::string& path : o.scenes) {
    try {
      wrong += verify(o, path);
    } catch (const Invalid_input& e) {
      std::cerr << "verify_report: " << e.what() << '\n';
      return 1;
    }
  }
  return wrong == 0 ? 0 : 3;
}
