// Scene reports as `extremal report` makes them, through the command's own code (cli/Scene_run,
// cli/Report_rows, cli/Report_writer): extremal.report's JSON.
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "Convert.h"
#include "cli/Report_rows.h"
#include "cli/Report_writer.h"
#include "cli/Scene_run.h"

namespace extremal::python {

namespace {

std::string report_json(const std::string& path, int threads) {
  if (threads < 1) throw Invalid_input("threads: must be at least 1, got " + std::to_string(threads));
  py::gil_scoped_release release;
  const io::Scene scene = io::read_scene(path, io::load_bodies);
  cli::Scene_run_options options;
  options.threads = threads;
  cli::Scene_run run(scene, options);
  std::ostringstream out;
  const std::unique_ptr<cli::Report_writer> writer = cli::make_json_writer(out, scene);
  cli::Report_rows rows(scene, *writer);
  run.run([&](int, double t, const std::vector<Pair_report>& reports) { rows.add(t, reports); });
  rows.finish();
  return out.str();
}

}  // namespace

void bind_report(py::module_& m) {
  m.def("_report_json", &report_json, py::arg("scene"), py::arg("threads") = 1,
        "The JSON report `extremal report SCENE -o OUT.json` writes, as text.");
}

}  // namespace extremal::python
