// Scene reports as `extremal report` makes them, through the same code (the scene runner and
// its report: algorithms/scene): extremal.report's JSON, and the three halves of
// extremal.batch: a scene read and checked on the client (an outline, the geometry dropped),
// its pairs run on a worker (their rows as arrays), and the report written on the client.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "Convert.h"
#include "algorithms/scene/Report_rows.h"
#include "algorithms/scene/Report_writer.h"
#include "algorithms/scene/Scene_setup.h"

namespace extremal::python {

namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// Files a shipped scene names, by the path the scene resolves them to -> where the worker put
// them. The scene's entries read the local copies; anything not listed is read where it is.
using File_map = std::map<std::string, std::string>;

io::File_loader loader(const File_map& files) {
  return [files](const std::string& path, const std::string& file_units,
                 const std::string& scene_units) {
    const auto it = files.find(path);
    return io::load_bodies(it == files.end() ? path : it->second, file_units, scene_units);
  };
}

// A scene as `extremal report` reads it: from its file, or (shipped) from its text, with the
// scene's own path kept for its messages and its report.
io::Scene read(const std::string& path, const std::optional<std::string>& text,
               const File_map& files) {
  if (text) return io::parse_scene(*text, path, loader(files));
  return io::read_scene(path, loader(files));
}

std::string report_json(const std::string& path, int threads, int every) {
  if (threads < 1) throw Invalid_input("threads: must be at least 1, got " + std::to_string(threads));
  if (every < 1) throw Invalid_input("every: must be at least 1, got " + std::to_string(every));
  py::gil_scoped_release release;
  const io::Scene scene = io::read_scene(path, io::load_bodies);
  const std::unique_ptr<Scene_stepper> run = scene_stepper(scene, threads);
  std::ostringstream out;
  const std::unique_ptr<report::Report_writer> writer = report::make_json_writer(out, scene);
  report::Report_rows rows(scene, *writer, every);
  run_scene(scene, *run, [&](int, double t, const std::vector<Pair_report>& reports) {
    rows.add(t, reports);
  });
  rows.finish(report::report_timing(run->step_times_us(), run->audit_times_us()));
  return out.str();
}

// A scene read and checked, its bodies' geometry dropped: what writing its report needs.
struct Py_scene_outline {
  std::shared_ptr<const io::Scene> scene;
};

Py_scene_outline read_outline(const std::string& path, const std::optional<std::string>& text,
                              const File_map& files) {
  auto scene = std::make_shared<io::Scene>();
  {
    py::gil_scoped_release release;
    *scene = read(path, text, files);
    for (io::Scene_body& b : scene->bodies) b.body = Body();
  }
  return {scene};
}

// Fields of the rows of the pairs one task ran, pair-major: [pair][step] (and [component]).
struct Pair_rows {
  std::vector<double> distance, point_a, point_b, normal, params;
  std::vector<double> lower_bound;  // where `bounded`; 0 elsewhere
  // Each pair's step times and its audits' times, microseconds (Scene_stepper::run).
  std::vector<float> step_time_us, audit_time_us;
  std::vector<std::int32_t> face_a, face_b;
  std::vector<std::int8_t> status, degeneracy, solved, bounded;
};

py::dict run_scene(const std::string& path, const std::optional<std::vector<int>>& pairs,
                   int threads, const std::optional<std::string>& text, const File_map& files) {
  if (threads < 1) throw Invalid_input("threads: must be at least 1, got " + std::to_string(threads));
  std::vector<int> selected;
  Pair_rows rows;
  int steps = 0;
  {
    py::gil_scoped_release release;
    io::Scene scene = read(path, text, files);
    const int n_pairs = static_cast<int>(scene.pairs.size());
    if (pairs) {
      std::set<int> seen;
      std::vector<std::pair<int, int>> restricted;
      for (int k : *pairs) {
        if (k < 0 || k >= n_pairs)
          throw Invalid_input(path + ": pair index " + std::to_string(k) + " out of range (" +
                              std::to_string(n_pairs) + " pairs)");
        if (!seen.insert(k).second)
          throw Invalid_input(path + ": pair index " + std::to_string(k) + " given twice");
        restricted.push_back(scene.pairs[static_cast<std::size_t>(k)]);
      }
      selected = *pairs;
      // Each pair has a tracker of its own (Scene_stepper), so a subset runs as it does in the
      // whole.
      scene.pairs = restricted;
    } else {
      for (int k = 0; k < n_pairs; ++k) selected.push_back(k);
    }
    const std::unique_ptr<Scene_stepper> run = scene_stepper(scene, threads);
    steps = scene.step_count();
    const std::size_t n = selected.size() * static_cast<std::size_t>(steps);
    rows.distance.resize(n);
    rows.point_a.resize(3 * n);
    rows.point_b.resize(3 * n);
    rows.normal.resize(3 * n);
    rows.params.resize(4 * n);
    rows.face_a.resize(n);
    rows.face_b.resize(n);
    rows.status.resize(n);
    rows.degeneracy.resize(n);
    rows.solved.resize(n);
    rows.lower_bound.resize(n);
    rows.bounded.resize(n);
    const auto m = static_cast<std::size_t>(steps);
    run_scene(scene, *run, [&](int step, double, const std::vector<Pair_report>& reports) {
      for (std::size_t k = 0; k < reports.size(); ++k) {
        const Pair_report& r = reports[k];
        const std::size_t at = k * m + static_cast<std::size_t>(step);
        rows.distance[at] = r.distance;
        for (int c = 0; c < 3; ++c) {
          rows.point_a[3 * at + c] = r.point_a[c];
          rows.point_b[3 * at + c] = r.point_b[c];
          rows.normal[3 * at + c] = r.normal[c];
        }
        for (int c = 0; c < 4; ++c) rows.params[4 * at + c] = r.params[c];
        rows.face_a[at] = r.feature_a;
        rows.face_b[at] = r.feature_b;
        rows.status[at] = static_cast<std::int8_t>(r.status);
        rows.degeneracy[at] = static_cast<std::int8_t>(r.degeneracy);
        rows.solved[at] = r.solved ? 1 : 0;
        rows.bounded[at] = r.lower_bound ? 1 : 0;
        rows.lower_bound[at] = r.lower_bound.value_or(0.0);
      }
    });
    // Pair-major as the rows: the client rebuilds the summaries' step times from them.
    for (const std::vector<float>& times : run->step_times_us())
      rows.step_time_us.insert(rows.step_time_us.end(), times.begin(), times.end());
    for (const std::vector<float>& times : run->audit_times_us())
      rows.audit_time_us.insert(rows.audit_time_us.end(), times.begin(), times.end());
  }
  const auto P = static_cast<py::ssize_t>(selected.size()), M = static_cast<py::ssize_t>(steps);
  py::dict out;
  out["scene"] = path;
  out["pairs"] = selected;
  out["steps"] = steps;
  out["distance"] = take_array(std::move(rows.distance), {P, M});
  out["point_a"] = take_array(std::move(rows.point_a), {P, M, 3});
  out["point_b"] = take_array(std::move(rows.point_b), {P, M, 3});
  out["normal"] = take_array(std::move(rows.normal), {P, M, 3});
  out["params"] = take_array(std::move(rows.params), {P, M, 4});
  out["face_a"] = take_array(std::move(rows.face_a), {P, M});
  out["face_b"] = take_array(std::move(rows.face_b), {P, M});
  out["status"] = take_array(std::move(rows.status), {P, M});
  out["degeneracy"] = take_array(std::move(rows.degeneracy), {P, M});
  out["solved"] = take_array(std::move(rows.solved), {P, M});
  out["lower_bound"] = take_array(std::move(rows.lower_bound), {P, M});
  out["bounded"] = take_array(std::move(rows.bounded), {P, M});
  out["step_time_us"] = take_array(std::move(rows.step_time_us), {P, M});
  out["audit_time_us"] = take_array(std::move(rows.audit_time_us), {P, M});
  return out;
}

// A part's array `key`, checked to hold `per_row` values for each of its pairs' `steps` rows.
template <class T>
py::array_t<T, py::array::c_style> part_array(const py::dict& part, const char* key,
                                              std::size_t pairs, std::size_t steps,
                                              std::size_t per_row) {
  if (!part.contains(key)) throw Invalid_input(std::string("rows: a part has no '") + key + "'");
  auto a = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(part[key]);
  if (!a || static_cast<std::size_t>(a.size()) != pairs * steps * per_row)
    throw Invalid_input(std::string("rows: a part's '") + key + "' does not hold its rows");
  return a;
}

struct Part_view {
  std::size_t steps = 0;
  py::array_t<double, py::array::c_style> distance, point_a, point_b, normal, params, lower_bound;
  py::array_t<float, py::array::c_style> step_time_us, audit_time_us;
  py::array_t<std::int32_t, py::array::c_style> face_a, face_b;
  py::array_t<std::int8_t, py::array::c_style> status, degeneracy, solved, bounded;
};

// Writes a scene's report from the rows its tasks ran (every pair once, in any split), as
// `extremal report SCENE -o output` writes it; returns the readable summary it prints.
std::string write_report(const Py_scene_outline& outline, const std::string& output,
                         const py::list& parts) {
  const io::Scene& scene = *outline.scene;
  if (!ends_with(output, ".csv") && !ends_with(output, ".json"))
    throw Invalid_input("-o " + output + ": expected a file name ending in .csv or .json");
  const std::size_t n_pairs = scene.pairs.size(), steps = static_cast<std::size_t>(scene.step_count());
  std::vector<Part_view> views;
  // Where each scene pair's rows are: (part, index in the part).
  std::vector<std::pair<int, std::size_t>> where(n_pairs, {-1, 0});
  for (const py::handle h : parts) {
    if (!py::isinstance<py::dict>(h)) throw Invalid_input("rows: expected a list of the tasks' dicts");
    const py::dict part = h.cast<py::dict>();
    const std::vector<int> pairs = part["pairs"].cast<std::vector<int>>();
    const std::size_t part_steps = part["steps"].cast<std::size_t>();
    if (part_steps != steps)
      throw Invalid_input(scene.path + ": a part has " + std::to_string(part_steps) +
                          " steps, the scene " + std::to_string(steps));
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      const int k = pairs[i];
      if (k < 0 || static_cast<std::size_t>(k) >= n_pairs || where[static_cast<std::size_t>(k)].first >= 0)
        throw Invalid_input(scene.path + ": pair " + std::to_string(k) +
                            " is out of range or in two parts");
      where[static_cast<std::size_t>(k)] = {static_cast<int>(views.size()), i};
    }
    Part_view v;
    v.steps = steps;
    const std::size_t p = pairs.size();
    v.distance = part_array<double>(part, "distance", p, steps, 1);
    v.point_a = part_array<double>(part, "point_a", p, steps, 3);
    v.point_b = part_array<double>(part, "point_b", p, steps, 3);
    v.normal = part_array<double>(part, "normal", p, steps, 3);
    v.params = part_array<double>(part, "params", p, steps, 4);
    v.face_a = part_array<std::int32_t>(part, "face_a", p, steps, 1);
    v.face_b = part_array<std::int32_t>(part, "face_b", p, steps, 1);
    v.status = part_array<std::int8_t>(part, "status", p, steps, 1);
    v.degeneracy = part_array<std::int8_t>(part, "degeneracy", p, steps, 1);
    v.solved = part_array<std::int8_t>(part, "solved", p, steps, 1);
    v.lower_bound = part_array<double>(part, "lower_bound", p, steps, 1);
    v.bounded = part_array<std::int8_t>(part, "bounded", p, steps, 1);
    v.step_time_us = part_array<float>(part, "step_time_us", p, steps, 1);
    v.audit_time_us = part_array<float>(part, "audit_time_us", p, steps, 1);
    views.push_back(std::move(v));
  }
  for (std::size_t k = 0; k < n_pairs; ++k)
    if (where[k].first < 0)
      throw Invalid_input(scene.path + ": no rows for pair " + std::to_string(k));

  std::ostringstream summary;
  {
    py::gil_scoped_release release;
    std::ofstream file(output);
    if (!file) throw Invalid_input(output + ": cannot open for writing");
    const std::unique_ptr<report::Report_writer> writer =
        ends_with(output, ".json") ? report::make_json_writer(file, scene)
                                   : report::make_csv_writer(file, true, std::string());
    report::Report_rows rows(scene, *writer);
    std::vector<Pair_report> reports(n_pairs);
    for (std::size_t i = 0; i < steps; ++i) {
      const double t = scene.time_of(static_cast<int>(i));
      for (std::size_t k = 0; k < n_pairs; ++k) {
        const Part_view& v = views[static_cast<std::size_t>(where[k].first)];
        const std::size_t at = where[k].second * steps + i;
        Pair_report& r = reports[k];
        r.time = t;
        r.distance = v.distance.data()[at];
        for (int c = 0; c < 3; ++c) {
          r.point_a[c] = v.point_a.data()[3 * at + c];
          r.point_b[c] = v.point_b.data()[3 * at + c];
          r.normal[c] = v.normal.data()[3 * at + c];
        }
        for (int c = 0; c < 4; ++c) r.params[c] = v.params.data()[4 * at + c];
        r.feature_a = v.face_a.data()[at];
        r.feature_b = v.face_b.data()[at];
        r.status = static_cast<Pair_status>(v.status.data()[at]);
        r.degeneracy = static_cast<Degeneracy>(v.degeneracy.data()[at]);
        r.solved = v.solved.data()[at] != 0;
        r.lower_bound.reset();
        if (v.bounded.data()[at] != 0) r.lower_bound = v.lower_bound.data()[at];
      }
      rows.add(t, reports);
    }
    // The step and audit times the workers measured, pair by pair in scene order.
    std::vector<std::vector<float>> step_times(n_pairs), audit_times(n_pairs);
    for (std::size_t k = 0; k < n_pairs; ++k) {
      const Part_view& v = views[static_cast<std::size_t>(where[k].first)];
      const std::size_t first = where[k].second * steps;
      step_times[k].assign(v.step_time_us.data() + first, v.step_time_us.data() + first + steps);
      audit_times[k].assign(v.audit_time_us.data() + first, v.audit_time_us.data() + first + steps);
    }
    const report::Report_timing timing = report::report_timing(step_times, audit_times);
    const std::vector<io::Pair_summary> summaries = rows.finish(timing);
    if (!file) throw Invalid_input(output + ": write failed");
    report::print_summary(summary, scene, output, summaries, timing);
  }
  return summary.str();
}

}  // namespace

void bind_report(py::module_& m) {
  m.def("_report_json", &report_json, py::arg("scene"), py::arg("threads") = 1,
        py::arg("every") = 1,
        "The JSON report `extremal report SCENE -o OUT.json [--every N]` writes, as text.");

  py::class_<Py_scene_outline>(m, "SceneOutline", R"doc(
A scene file read and checked as `extremal report` reads it (every key, body, file and pair),
its bodies' geometry dropped: what extremal.batch needs to plan its tasks and write the report.
)doc")
      .def_property_readonly("path", [](const Py_scene_outline& o) { return o.scene->path; })
      .def_property_readonly("units", [](const Py_scene_outline& o) { return o.scene->units; })
      .def_property_readonly("start", [](const Py_scene_outline& o) { return o.scene->start; })
      .def_property_readonly("end", [](const Py_scene_outline& o) { return o.scene->end; })
      .def_property_readonly("step", [](const Py_scene_outline& o) { return o.scene->step; })
      .def_property_readonly("steps", [](const Py_scene_outline& o) { return o.scene->step_count(); })
      .def_property_readonly("bodies",
                             [](const Py_scene_outline& o) {
                               std::vector<std::string> names;
                               for (const auto& b : o.scene->bodies) names.push_back(b.name);
                               return names;
                             })
      .def_property_readonly("pairs",
                             [](const Py_scene_outline& o) {
                               std::vector<std::pair<std::string, std::string>> out;
                               for (const auto& [a, b] : o.scene->pairs)
                                 out.emplace_back(o.scene->bodies[a].name, o.scene->bodies[b].name);
                               return out;
                             })
      .def_property_readonly("threshold", [](const Py_scene_outline& o) { return o.scene->threshold; });

  m.def("_read_outline", &read_outline, py::arg("path"), py::arg("text") = py::none(),
        py::arg("files") = File_map());
  m.def("_run_scene", &run_scene, py::arg("path"), py::arg("pairs") = py::none(),
        py::arg("threads") = 1, py::arg("text") = py::none(), py::arg("files") = File_map());
  m.def("_write_report", &write_report, py::arg("outline"), py::arg("output"), py::arg("parts"));
  m.def(
      "_output_names",
      [](const std::vector<std::string>& scenes, const std::string& output) {
        const std::vector<std::string> tags = report::scene_tags(scenes);
        std::vector<std::string> out;
        for (const std::string& tag : tags) out.push_back(report::batch_path(output, tag, scenes.size() > 1));
        return out;
      },
      py::arg("scenes"), py::arg("output"),
      "The report files `extremal report SCENES... -o OUTPUT` writes, one per scene.");
  m.def(
      "_resolve_scene_file",
      [](const std::string& scene, const std::string& file) {
        // As io::parse_scene resolves a scene entry's file: from the scene file's folder.
        return (std::filesystem::path(std::filesystem::path(scene).parent_path()) / file).string();
      },
      py::arg("scene"), py::arg("file"));
}

}  // namespace extremal::python
