// `extremal report SCENE -o REPORT.html` (docs/cli.md, "HTML report"): one self-contained page
// that opens offline from a file: URL. It holds the summary table (a row per watched pair, worst
// first, with its clearance class), each pair's distance-against-time plot with the classes'
// thresholds, and a 3D view of the selected pair at its worst moment: the bodies (a binary glTF
// of every watched body, embedded), the witness segment, orbit controls, the pair's row beside
// it. The page's scripts are Debian's libjs-three and the project's own (cli/Html_report.js),
// embedded by the build (cli/Embedded_text.h) and inlined in the page.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "algorithms/body_pair/Pair_report.h"
#include "io/Report_plot.h"
#include "algorithms/scene/Report_writer.h"
#include "algorithms/scene/Step_times.h"
#include "io/Pair_summary.h"
#include "io/Scene.h"

namespace extremal::cli {

using report::Report_timing;
using report::Report_writer;
using io::Pair_series;

// A writer that keeps no rows: the HTML report holds the summaries, not the rows (those go to
// -o OUT.csv or OUT.json).
std::unique_ptr<Report_writer> make_null_writer();

class Html_report {
 public:
  // The scene must outlive this.
  explicit Html_report(const io::Scene& scene);
  // Every step, in order, one report per scene pair (in the order of scene.pairs).
  void add(int step, double t, const std::vector<Pair_report>& reports);
  // After the last step: writes the page. Throws Invalid_input naming the path when it cannot
  // be written.
  void write(const std::string& path, const std::vector<io::Pair_summary>& summaries,
             const Report_timing& timing) const;

 private:
  const io::Scene& m_scene;
  std::vector<Pair_series> m_series;  // per pair; NaN where farther (a gap)
  // Per pair, its worst moment: the step of its smallest distance (the first such step), among
  // the tracked steps, or among the farther ones when it never was tracked.
  struct Worst {
    int step = -1;
    bool tracked = false;
    Pair_report report;
  };
  std::vector<Worst> m_worst;
};

}  // namespace extremal::cli
