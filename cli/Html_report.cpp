#include "cli/Html_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli/Embedded_text.h"
#include "io/Snapshot_writer.h"
#include "io/Svg_plot.h"
#include "kernel/Error.h"

namespace extremal::cli {

using namespace report;
using io::report_plot;

namespace {

// The embedded glTF of the watched bodies may weigh this much (before base64, which adds a
// third); past it the page embeds the worst pair's bodies only, and the 3D view of the other
// pairs says so. So a report stays under 20 MB (as1's 18 bodies weigh 1.3 MB: bench/RESULTS.md,
// "HTML report").
constexpr std::size_t k_view_bytes = std::size_t{12} << 20;
// Points each pair's curve keeps (Pair_series), so that a long run's plots stay small.
constexpr long k_plot_points = 2000;
// A plot of all pairs together is drawn for at most this many pairs (the palette's colours);
// every pair has its own plot in any case.
constexpr std::size_t k_combined_plot_pairs = 8;

class Null_writer final : public Report_writer {
 public:
  void row(double, const std::string&, const std::string&, const Pair_report&) override {}
  void finish(const std::vector<io::Pair_summary>&, const Report_timing&) override {}
};

std::string number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

std::string html(const std::string& text) { return io::xml_escape(text); }

// "0.5 to 0.7, 1.2": each run of rows from its first time to its last.
std::string intervals_text(const std::vector<io::Time_interval>& runs) {
  if (runs.empty()) return "none";
  std::string text;
  const std::size_t shown = std::min<std::size_t>(runs.size(), 4);
  for (std::size_t i = 0; i < shown; ++i) {
    text += (i ? ", " : "") + number(runs[i].start);
    if (runs[i].end > runs[i].start) text += " to " + number(runs[i].end);
  }
  if (runs.size() > shown) text += " and " + std::to_string(runs.size() - shown) + " more";
  return text;
}

std::string base64(const std::string& bytes) {
  static const char* const digits =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) |
                       (static_cast<unsigned char>(bytes[i + 1]) << 8) |
                       static_cast<unsigned char>(bytes[i + 2]);
    for (int s = 18; s >= 0; s -= 6) out += digits[(v >> s) & 63];
  }
  if (i < bytes.size()) {
    unsigned v = static_cast<unsigned char>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    out += digits[(v >> 18) & 63];
    out += digits[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? digits[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

// JSON inside a <script> element: '<' written as \u003c, so nothing in it can close the element.
std::string script_json(const nlohmann::json& j) {
  const std::string text = j.dump();
  std::string out;
  out.reserve(text.size());
  for (char c : text) out += c == '<' ? std::string("\\u003c") : std::string(1, c);
  return out;
}

// The 4x4 matrix of a pose, column by column (three.js's Matrix4.fromArray).
nlohmann::json matrix_json(const Rigid_pose_3& pose) {
  nlohmann::json m = nlohmann::json::array();
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      m.push_back(c < 3 ? (r < 3 ? pose.rotation()(r, c) : 0.0)
                        : (r < 3 ? pose.translation()[r] : 1.0));
  return m;
}

const std::string& embedded(const std::string& name) {
  for (const Embedded_text& t : embedded_texts())
    if (t.name == name) return t.text;
  EXTREMAL_PRECONDITION_MSG(false, "no embedded text " << name);
  static const std::string none;
  return none;
}

std::string pair_name(const io::Scene& scene, std::size_t k) {
  const auto& [a, b] = scene.pairs[k];
  return scene.bodies[a].name + " - " + scene.bodies[b].name;
}

std::string class_label(const io::Clearance_verdict& v) {
  std::string text = to_string(v.verdict);
  if (v.verdict == io::Clearance_class::Undecided)
    text += std::string(" (") + to_string(v.range.proven) + " to " + to_string(v.range.possible) + ")";
  return text;
}

// The classes' thresholds as the plot's rules: contact at 0, and the clearance when set.
void threshold_rules(io::Svg_plot& plot, const io::Clearance_thresholds& t, const std::string& units) {
  plot.rules.clear();
  plot.rules.push_back({0.0, "contact (|d| <= " + number(t.contact) + " " + units + ")"});
  if (t.clearance)
    plot.rules.push_back({*t.clearance, "clearance (d < " + number(*t.clearance) + " " + units + ")"});
}

// Records every uncaught error, rejected promise, failed resource and console.error of the page
// from the first script on: the count in <html data-errors>, the messages in #page-errors.
const char* const k_error_collector = R"js((function () {
  var errors = [];
  function show() {
    var box = document.getElementById('page-errors');
    if (box && errors.length) {
      box.hidden = false;
      box.textContent = 'This page hit an error: ' + errors.join(' | ');
    }
  }
  function record(message) {
    errors.push(String(message));
    document.documentElement.setAttribute('data-errors', String(errors.length));
    show();
  }
  document.documentElement.setAttribute('data-errors', '0');
  window.addEventListener('error', function (e) {
    record(e.message || ('failed to load ' + (e.target && (e.target.src || e.target.href))));
  }, true);
  window.addEventListener('unhandledrejection', function (e) {
    record('unhandled rejection: ' + (e.reason && e.reason.message ? e.reason.message : e.reason));
  });
  var original = console.error;
  console.error = function () {
    record(Array.prototype.join.call(arguments, ' '));
    original.apply(console, arguments);
  };
  document.addEventListener('DOMContentLoaded', show);
})();
)js";

// The rule of the classes, with this report's thresholds (docs/cli.md, "Clearance classes").
std::string classes_html(const io::Clearance_thresholds& t, const std::string& units) {
  const std::string c = number(t.contact) + " " + html(units);
  const std::string d = t.clearance ? number(*t.clearance) + " " + html(units) : std::string();
  std::ostringstream os;
  os << "<p>Each step bounds the bodies' true distance x: a <i>penetrating</i> step is a clash "
        "and a <i>contact</i> step a contact (the tracker's status); an apart step has its "
        "certified lower bound &le; x &le; its distance (a real pair of points); a step farther "
        "than the scene's threshold has its boxes' distance &le; x. The classes of x:</p>\n"
     << "<table class=\"kv\"><tr><th><span class=\"cls clash\">clash</span></th><td>x &lt; -"
     << c << "</td></tr>\n<tr><th><span class=\"cls contact\">contact</span></th><td>|x| &le; "
     << c << "</td></tr>\n";
  if (t.clearance)
    os << "<tr><th><span class=\"cls clearance\">clearance</span></th><td>" << c
       << " &lt; x &lt; " << d << "</td></tr>\n<tr><th><span class=\"cls clear\">clear</span>"
       << "</th><td>x &ge; " << d << "</td></tr>\n";
  else
    os << "<tr><th><span class=\"cls clear\">clear</span></th><td>x &gt; " << c
       << " (no clearance set)</td></tr>\n";
  os << "</table>\n<p>A pair's class is the most severe class one of its steps proves (the class "
        "of the upper end of its bounds); it is <span class=\"cls undecided\">undecided</span> "
        "when a step's lower bound leaves a more severe class open (the <i>undecided</i> column "
        "gives those steps' times). <code>--fail-on LEVEL</code> fails a pair whose class, or "
        "the most severe class left open, reaches LEVEL.</p>\n";
  return os.str();
}

}  // namespace

std::unique_ptr<Report_writer> make_null_writer() { return std::make_unique<Null_writer>(); }

Html_report::Html_report(const io::Scene& scene)
    : m_scene(scene),
      m_series(scene.pairs.size(), Pair_series(scene.step_count(), k_plot_points)),
      m_worst(scene.pairs.size()) {}

void Html_report::add(int step, double t, const std::vector<Pair_report>& reports) {
  EXTREMAL_PRECONDITION(reports.size() == m_series.size());
  for (std::size_t k = 0; k < reports.size(); ++k) {
    const Pair_report& r = reports[k];
    const bool farther = clearance_state(r.status) == io::Clearance_state::Farther;
    m_series[k].add(t, farther ? std::nan("") : r.distance);
    // The summary's minimum (io::Pair_summary): the first step of the smallest tracked distance.
    Worst& w = m_worst[k];
    const bool better = w.step < 0 || (!farther && !w.tracked) ||
                        (farther == !w.tracked && r.distance < w.report.distance);
    if (better) w = {step, !farther, r};
  }
}

void Html_report::write(const std::string& path, const std::vector<io::Pair_summary>& summaries,
                        const Report_timing& timing) const {
  const io::Scene& scene = m_scene;
  const std::size_t n = scene.pairs.size();
  EXTREMAL_PRECONDITION(summaries.size() == n && timing.pairs.size() == n);
  const io::Clearance_thresholds thresholds = clearance_thresholds(scene);
  const std::string scene_name = std::filesystem::path(scene.path).filename().string();

  // Worst first: the most severe proven class, then the smallest distance.
  std::vector<std::size_t> order(n);
  for (std::size_t k = 0; k < n; ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) {
    const io::Pair_summary &a = summaries[i], &b = summaries[j];
    if (a.clearance.range.proven != b.clearance.range.proven)
      return a.clearance.range.proven > b.clearance.range.proven;
    if (a.min_distance.has_value() != b.min_distance.has_value()) return a.min_distance.has_value();
    return a.min_distance && *a.min_distance < *b.min_distance;
  });
  std::vector<Pair_series> series = m_series;
  for (auto& s : series) s.finish();

  // The 3D view's bodies: every watched body in its body frame (the page poses them), or the
  // worst pair's only when they all weigh too much.
  io::Snapshot_options view_options;
  view_options.unit_in_metres = io::unit_in_mm(scene.units) / 1000.0;
  auto view_of = [&](const std::set<int>& ids) {
    std::vector<io::Snapshot_body> bodies;
    for (int i : ids) bodies.push_back({"body" + std::to_string(i), &scene.bodies[i].body, {}});
    return io::snapshot_glb(bodies, {}, view_options);
  };
  std::set<int> in_view;
  for (const auto& [a, b] : scene.pairs) in_view.insert({a, b});
  std::string glb = view_of(in_view);
  if (glb.size() > k_view_bytes && n > 1) {
    const auto& [a, b] = scene.pairs[order[0]];
    in_view = {a, b};
    glb = view_of(in_view);
  }

  // What the page's script needs per pair: its bodies, its worst moment, their poses there.
  nlohmann::json pairs = nlohmann::json::array();
  for (std::size_t k = 0; k < n; ++k) {
    const auto& [a, b] = scene.pairs[k];
    const Worst& w = m_worst[k];
    const double t = scene.time_of(w.step);
    auto pose = [&](int i) {
      return matrix_json(scene.bodies[i].motion.pose_at(t) * scene.bodies[i].body.placement);
    };
    nlohmann::json p = {{"name", pair_name(scene, k)},
                        {"class", class_label(summaries[k].clearance)},
                        {"verdict", to_string(summaries[k].clearance.verdict)},
                        {"a", a},
                        {"b", b},
                        {"t", t},
                        {"distance", w.report.distance},
                        {"status", to_string(w.report.status)},
                        {"pose_a", pose(a)},
                        {"pose_b", pose(b)},
                        {"in_view", in_view.count(a) && in_view.count(b)}};
    if (w.tracked) {
      const Vec3 &pa = w.report.point_a, &pb = w.report.point_b;
      p["witness"] = {{pa.x(), pa.y(), pa.z()}, {pb.x(), pb.y(), pb.z()}};
    } else {
      p["witness"] = nullptr;
    }
    pairs.push_back(p);
  }
  nlohmann::json bodies = nlohmann::json::array();
  for (const auto& body : scene.bodies) bodies.push_back(body.name);
  const nlohmann::json data = {{"scene", scene_name},
                               {"units", scene.units},
                               {"bodies", bodies},
                               {"pairs", pairs},
                               {"worst", order.empty() ? -1 : static_cast<long>(order[0])},
                               {"view_bytes", glb.size()}};

  std::ostringstream os;
  os << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
     << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
     << "<title>Clearance report: " << html(scene_name) << "</title>\n"
     << "<style>\n" << embedded("Html_report.css") << "</style>\n"
     // Errors are caught from the first script on, and shown on the page (and to its tests).
     << "<script>\n" << k_error_collector << "</script>\n"
     << "</head><body>\n";

  os << "<header><h1>Clearance report: " << html(scene_name) << "</h1>\n<p class=\"facts\">"
     << scene.bodies.size() << " bodies, " << n << " watched pair" << (n == 1 ? "" : "s") << ", "
     << scene.step_count() << " steps from t = " << number(scene.start) << " to "
     << number(scene.time_of(scene.step_count() - 1)) << " s, lengths in " << html(scene.units)
     << ". Classes: contact within " << number(thresholds.contact) << " " << html(scene.units)
     << "; "
     << (thresholds.clearance
             ? "clearance below " + number(*thresholds.clearance) + " " + html(scene.units)
             : std::string("no clearance set (--clearance D or the scene's \"clearance\")"))
     << ". Error budget: " << number(scene.tolerance.absolute) << " " << html(scene.units)
     << " or " << number(scene.tolerance.relative) << " of the distance.</p>\n"
     << "<p class=\"counts\">";
  for (io::Clearance_class c : {io::Clearance_class::Clash, io::Clearance_class::Contact,
                                io::Clearance_class::Clearance, io::Clearance_class::Undecided,
                                io::Clearance_class::Clear}) {
    long count = 0;
    for (const auto& s : summaries) count += s.clearance.verdict == c;
    if (count)
      os << "<span class=\"cls " << to_string(c) << "\">" << count << " " << to_string(c)
         << "</span> ";
  }
  os << "</p></header>\n<div id=\"page-errors\" hidden></div>\n";

  os << "<section id=\"detail\"><div id=\"view-box\"><canvas id=\"view\"></canvas>"
     << "<div id=\"view-caption\"></div><div id=\"view-note\" hidden></div></div>\n"
     << "<div id=\"side\"><h2 id=\"pair-title\"></h2><table id=\"pair-row\" class=\"kv\"></table>"
     << "<div id=\"pair-plot\"></div></div></section>\n";

  os << "<section><h2>Pairs</h2><p class=\"hint\">Worst first. Select a row to see the pair at "
        "its worst moment (its smallest distance) in 3D: drag to turn, wheel to zoom, right "
        "drag to pan.</p>\n<table id=\"summary\"><thead><tr><th>#</th><th>pair</th>"
        "<th>class</th><th>minimum distance</th><th>at t (s)</th><th>deepest penetration</th>"
        "<th>at t (s)</th><th>contact</th><th>uncertified</th><th>undecided</th>"
        "<th>step time</th></tr></thead>\n<tbody>\n";
  for (std::size_t k : order) {
    const io::Pair_summary& s = summaries[k];
    const std::string cls = to_string(s.clearance.verdict);
    os << "<tr data-pair=\"" << k << "\" tabindex=\"0\"><td>" << k + 1 << "</td><td>"
       << html(pair_name(scene, k)) << "</td><td><span class=\"cls " << cls << "\">"
       << html(class_label(s.clearance)) << "</span></td>";
    if (s.min_distance)
      os << "<td>" << number(*s.min_distance) << "</td><td>" << number(s.min_time) << "</td>";
    else
      os << "<td>farther than " << number(scene.threshold.value_or(0.0)) << "</td><td></td>";
    if (s.deepest_penetration)
      os << "<td>" << number(*s.deepest_penetration) << "</td><td>" << number(s.deepest_time)
         << "</td>";
    else
      os << "<td>none</td><td></td>";
    os << "<td>" << intervals_text(s.contact) << "</td><td>" << intervals_text(s.uncertified)
       << "</td><td>" << intervals_text(s.clearance.undecided) << "</td><td>median "
       << number(timing.pairs[k].median) << " &micro;s, p99 " << number(timing.pairs[k].p99)
       << " &micro;s</td></tr>\n";
  }
  os << "</tbody></table></section>\n";

  if (n > 1 && n <= k_combined_plot_pairs) {
    io::Svg_plot all = report_plot(scene, series, summaries);
    all.clip_id = "plot-area-all";
    threshold_rules(all, thresholds, scene.units);
    os << "<section id=\"all-plot\"><h2>All pairs</h2>\n" << all.to_svg() << "</section>\n";
  }

  os << "<section><h2>Classes</h2>\n" << classes_html(thresholds, scene.units) << "</section>\n";

  // Each pair's plot, put beside the 3D view when its pair is selected.
  const double half = 0.5 * scene.step;
  for (std::size_t k = 0; k < n; ++k) {
    io::Svg_plot plot = report_plot(scene, series, summaries, {k});
    plot.width = 720;
    plot.height = 340;
    plot.clip_id = "plot-area-" + std::to_string(k);
    threshold_rules(plot, thresholds, scene.units);
    for (const auto& r : summaries[k].clearance.undecided)
      plot.bands.push_back({std::max(scene.start, r.start - half),
                            std::min(scene.time_of(scene.step_count() - 1), r.end + half),
                            "#9467bd", "undecided", 0.25});
    os << "<template id=\"plot-" << k << "\">" << plot.to_svg() << "</template>\n";
  }

  os << "<script type=\"application/json\" id=\"report-data\">" << script_json(data)
     << "</script>\n<script type=\"application/octet-stream\" id=\"view-data\">" << base64(glb)
     << "</script>\n";
  for (const char* name : {"three.min.js", "OrbitControls.js", "GLTFLoader.js", "Html_report.js"})
    os << "<script>\n" << embedded(name) << "\n</script>\n";
  os << "</body></html>\n";

  std::ofstream file(path, std::ios::binary);
  if (!file) throw Invalid_input(path + ": cannot open for writing");
  file << os.str();
  if (!file) throw Invalid_input(path + ": write failed");
}

}  // namespace extremal::cli
