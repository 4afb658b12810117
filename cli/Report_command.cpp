// `extremal report SCENE.json`: batch distance report over time (../shared/CLI.md).
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "algorithms/Scene_stepper.h"
#include "cli/Commands.h"
#include "io/Model_reader.h"
#include "io/Scene.h"
#include "kernel/Error.h"

namespace extremal::cli {

namespace {

std::string format_number(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

// Per-pair summary: minimum distance and when.
struct Summary {
  double min_distance = std::numeric_limits<double>::infinity();
  double min_time = 0.0;
};

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

int run_scene(const std::string& scene_path, const Report_options& options, std::ostream& csv,
              nlohmann::json* json_rows, bool write_header) {
  const io::Scene scene = io::read_scene(scene_path, io::load_bodies);
  std::vector<Scene_stepper_body> bodies;
  for (const auto& b : scene.bodies) bodies.push_back({&b.body, &b.motion});
  Body_pair_options pair_options;
  pair_options.tracker.gain.setConstant(scene.tracker.gain);
  pair_options.tracker.substeps = scene.tracker.substeps;
  pair_options.tracker.integrator = scene.tracker.rk4 ? Integrator::Rk4 : Integrator::Euler;
  pair_options.threshold = scene.threshold.value_or(0.0);
  pair_options.audit_every = scene.tracker.audit_every;
  Scene_stepper stepper(bodies, scene.pairs, pair_options);

  if (write_header) csv << "t,body_a,body_b,distance,ax,ay,az,bx,by,bz,nx,ny,nz,face_a,face_b,status,detail,ua,va,ub,vb\n";
  std::vector<Summary> summaries(scene.pairs.size());
  const int steps = scene.step_count();
  for (int i = 0; i < steps; ++i) {
    const double t = scene.time_of(i);
    const auto& reports = stepper.step(t, scene.step);
    for (std::size_t k = 0; k < reports.size(); ++k) {
      const Pair_report& r = reports[k];
      const std::string& na = scene.bodies[scene.pairs[k].first].name;
      const std::string& nb = scene.bodies[scene.pairs[k].second].name;
      if (r.distance < summaries[k].min_distance) {
        summaries[k].min_distance = r.distance;
        summaries[k].min_time = t;
      }
      if (json_rows) {
        json_rows->push_back({{"t", t}, {"body_a", na}, {"body_b", nb}, {"distance", r.distance},
                              {"point_a", {r.point_a.x(), r.point_a.y(), r.point_a.z()}},
                              {"point_b", {r.point_b.x(), r.point_b.y(), r.point_b.z()}},
                              {"normal", {r.normal.x(), r.normal.y(), r.normal.z()}},
                              {"face_a", r.feature_a}, {"face_b", r.feature_b},
                              {"params", {r.params[0], r.params[1], r.params[2], r.params[3]}},
                              {"status", to_string(r.status)},
                              {"detail", to_string(r.degeneracy)}});
        continue;
      }
      csv << format_number(t) << ',' << na << ',' << nb << ',' << format_number(r.distance);
      for (const Vec3* v : {&r.point_a, &r.point_b, &r.normal})
        for (int c = 0; c < 3; ++c) csv << ',' << format_number((*v)[c]);
      csv << ',' << r.feature_a << ',' << r.feature_b << ',' << to_string(r.status) << ','
          << to_string(r.degeneracy);
      for (int c = 0; c < 4; ++c) csv << ',' << format_number(r.params[c]);
      csv << '\n';
    }
  }
  if (!options.quiet && !options.output.empty()) {
    std::cout << scene_path << ": " << scene.bodies.size() << " bodies, " << scene.pairs.size()
              << " watched pairs, " << steps << " steps\n";
    for (std::size_t k = 0; k < scene.pairs.size(); ++k)
      std::cout << "  " << scene.bodies[scene.pairs[k].first].name << " - "
                << scene.bodies[scene.pairs[k].second].name << ": minimum distance "
                << summaries[k].min_distance << " at t = " << summaries[k].min_time << "\n";
  }
  return 0;
}

}  // namespace

int run_report(const Report_options& options) {
  try {
    std::unique_ptr<std::ofstream> file;
    std::ostream* out = &std::cout;
    const bool json = ends_with(options.output, ".json");
    if (!options.output.empty()) {
      if (!json && !ends_with(options.output, ".csv"))
        throw Invalid_input(options.output + ": -o takes a .csv or .json file");
      file = std::make_unique<std::ofstream>(options.output);
      if (!*file) throw Invalid_input(options.output + ": cannot open for writing");
      out = file.get();
    }
    nlohmann::json report = nlohmann::json::array();
    for (std::size_t i = 0; i < options.scenes.size(); ++i) {
      nlohmann::json rows = nlohmann::json::array();
      run_scene(options.scenes[i], options, *out, json ? &rows : nullptr, i == 0);
      if (json) report.push_back({{"scene", options.scenes[i]}, {"rows", rows}});
    }
    if (json) *out << (report.size() == 1 ? report[0] : report).dump(1) << "\n";
    return 0;
  } catch (const Invalid_input& e) {
    std::cerr << "extremal report: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace extremal::cli
