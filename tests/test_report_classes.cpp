// End-to-end: the clearance classes of `extremal report` (docs/cli.md, "Clearance classes") in
// the JSON and readable summaries, --clearance and the scene's "clearance", the exit code of
// --fail-on, and the HTML report's page (its table, data and self-containedness; the page in a
// browser is tests/browser/test_html_report.py).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "support/Cli_run.h"

namespace extremal {
namespace {

using test::Cli_run;

Cli_run run(const std::string& args) { return test::run_cli(args); }

std::string scratch(const std::string& name) { return (test::scratch_dir() / name).string(); }

std::string write_scene(const std::string& name, const std::string& json) {
  const std::string path = scratch(name);
  std::ofstream(path) << json;
  return path;
}

std::string slurp(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

const std::string k_demo = std::string(EXTREMAL_SOURCE_DIR) + "/data/demo/demo.json";

// Two unit spheres `gap` apart (centres 2 + gap apart on x), standing still: a distance known
// exactly. `extra` adds top-level keys.
std::string spheres(const std::string& name, double gap, const std::string& extra = "") {
  return write_scene(name, R"({
    "time": {"start": 0, "end": 0.2, "step": 0.1},
    "bodies": [
      {"name": "A", "shape": {"type": "sphere", "radius": 1}},
      {"name": "B", "shape": {"type": "sphere", "radius": 1},
       "pose": {"position": [)" + std::to_string(2.0 + gap) + R"(, 0, 0]}}])" + extra + "}");
}

// The class of each pair of a JSON report: "A - B" -> class.
std::map<std::string, std::string> classes_of(const std::string& json_path) {
  std::map<std::string, std::string> out;
  const nlohmann::json report = nlohmann::json::parse(slurp(json_path));
  for (const auto& s : report["summary"])
    out[s["body_a"].get<std::string>() + " - " + s["body_b"].get<std::string>()] = s["class"];
  return out;
}

TEST(ReportClasses, DemoPairsAreAClashAndAClearanceInJsonAndSummary) {
  // The demo (clearance 2): the ellipsoids pass 1.66 mm apart, A dips 0.080 mm into the bracket.
  const std::string json = scratch("classes_demo.json");
  const Cli_run r = run("report " + k_demo + " -o " + json);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(slurp(json));
  EXPECT_EQ(j["clearance"], 2.0);
  EXPECT_EQ(j["contact_tolerance"], 1e-9);
  ASSERT_EQ(j["summary"].size(), 2u);
  EXPECT_EQ(j["summary"][0]["class"], "clearance");
  EXPECT_EQ(j["summary"][0]["class_range"], nlohmann::json({"clearance", "clearance"}));
  EXPECT_EQ(j["summary"][1]["class"], "clash");
  EXPECT_TRUE(j["summary"][1]["undecided"].empty());
  EXPECT_NE(r.out.find("  classes (contact within 1e-09, clearance below 2): 1 clash, 1 clearance\n"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("    class: clash\n"), std::string::npos) << r.out;
}

TEST(ReportClasses, ClearanceFlagOverridesTheScenesKey) {
  const std::string json = scratch("classes_flag.json");
  ASSERT_EQ(run("report " + k_demo + " -o " + json + " --clearance 1.6 --quiet").exit_code, 0);
  EXPECT_EQ(classes_of(json)["A - B"], "clear");  // 1.66 is not closer than 1.6
  ASSERT_EQ(run("report " + k_demo + " -o " + json + " --clearance 1.7 --quiet").exit_code, 0);
  EXPECT_EQ(classes_of(json)["A - B"], "clearance");
  const std::string none = spheres("classes_none.json", 1.5);
  ASSERT_EQ(run("report " + none + " -o " + json + " --quiet").exit_code, 0);
  EXPECT_EQ(classes_of(json)["A - B"], "clear");  // no clearance: clear when apart
  EXPECT_EQ(nlohmann::json::parse(slurp(json))["clearance"], nullptr);
}

TEST(ReportClasses, FailOnExitsThreeForPairsAtOrPastTheLevel) {
  const std::string apart = spheres("classes_gate.json", 1.5, R"(, "clearance": 2)");
  // 1.5 apart: clearance class under 2, so a clearance gate fails and a contact gate passes.
  const Cli_run fails = run("report " + apart + " --quiet --fail-on clearance");
  EXPECT_EQ(fails.exit_code, 3);
  EXPECT_EQ(fails.err, "extremal report: --fail-on clearance: 1 pair at or past it:\n  " + apart +
                           ": A - B (clearance)\n");
  EXPECT_EQ(run("report " + apart + " --quiet --fail-on contact").exit_code, 0);
  EXPECT_EQ(run("report " + apart + " --quiet --fail-on clearance --clearance 1").exit_code, 0);
  // The demo's clash fails every level.
  const Cli_run clash = run("report " + k_demo + " --quiet --fail-on clash");
  EXPECT_EQ(clash.exit_code, 3);
  EXPECT_NE(clash.err.find("demo.json: A - bracket (clash)\n"), std::string::npos) << clash.err;
  EXPECT_EQ(clash.err.find("A - B"), std::string::npos) << clash.err;
  // Touching spheres: a contact.
  const std::string touching = spheres("classes_touch.json", 0.0);
  const std::string json = scratch("classes_touch.out.json");
  EXPECT_EQ(run("report " + touching + " -o " + json + " --quiet --fail-on contact").exit_code, 3);
  EXPECT_EQ(classes_of(json)["A - B"], "contact");
  EXPECT_EQ(run("report " + touching + " --quiet --fail-on clash").exit_code, 0);
  // Usage and input errors.
  EXPECT_EQ(run("report " + apart + " --fail-on clear").exit_code, 2);
  EXPECT_EQ(run("report " + apart + " --fail-on bogus").exit_code, 2);
  EXPECT_EQ(run("report " + apart + " --clearance 0").exit_code, 2);
  const std::string unset = spheres("classes_unset.json", 1.5);
  const Cli_run no_clearance = run("report " + unset + " --fail-on clearance");
  EXPECT_EQ(no_clearance.exit_code, 1);
  EXPECT_EQ(no_clearance.err, "extremal report: " + unset +
                                  ": --fail-on clearance: no clearance to check against (give "
                                  "--clearance D, or the scene's \"clearance\")\n");
}

TEST(ReportClasses, AFartherBoxBoundShortOfTheClearanceIsUndecidedAndFailsItsGate) {
  // Centres 8 apart: distance 6, beyond the threshold 5, so only the boxes' bound (6) is known;
  // a clearance of 7 is neither proved nor ruled out.
  const std::string scene = spheres("classes_undecided.json", 6.0, R"(, "threshold": 5)");
  const std::string json = scratch("classes_undecided.out.json");
  const Cli_run r = run("report " + scene + " -o " + json + " --clearance 7 --fail-on clearance");
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find(": A - B (undecided: clearance not ruled out)\n"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("    class: undecided (clear to clearance)\n"), std::string::npos) << r.out;
  const nlohmann::json s = nlohmann::json::parse(slurp(json))["summary"][0];
  EXPECT_EQ(s["class"], "undecided");
  EXPECT_EQ(s["class_range"], nlohmann::json({"clear", "clearance"}));
  ASSERT_EQ(s["undecided"].size(), 1u);
  EXPECT_EQ(s["undecided"][0]["start"], 0.0);
  EXPECT_EQ(s["undecided"][0]["end"], 0.2);
  // Proved apart: a contact gate passes; with a clearance under the bound it is clear.
  EXPECT_EQ(run("report " + scene + " --quiet --clearance 7 --fail-on contact").exit_code, 0);
  ASSERT_EQ(run("report " + scene + " -o " + json + " --quiet --clearance 5.5").exit_code, 0);
  EXPECT_EQ(classes_of(json)["A - B"], "clear");
}

TEST(ReportClasses, SceneClearanceKeyIsCheckedWithItsPath) {
  for (const auto& [value, reason] :
       {std::pair<std::string, std::string>{"-1", "clearance: must be > 0"},
        {"0", "clearance: must be > 0"},
        {"\"2\"", "clearance: expected a number, got a string"}}) {
    const std::string scene = spheres("classes_bad.json", 1.0, R"(, "clearance": )" + value);
    const Cli_run r = run("report " + scene);
    EXPECT_EQ(r.exit_code, 1) << value;
    EXPECT_NE(r.err.find(scene + ": " + reason), std::string::npos) << r.err;
  }
}

// The JSON the page's script reads.
nlohmann::json page_data(const std::string& page) {
  const std::string open = "<script type=\"application/json\" id=\"report-data\">";
  const std::size_t at = page.find(open);
  if (at == std::string::npos) return nullptr;
  const std::size_t from = at + open.size();
  return nlohmann::json::parse(page.substr(from, page.find("</script>", from) - from));
}

TEST(ReportClasses, HtmlReportIsOneSelfContainedPageWithTheWorstMoment) {
  const std::string html = scratch("classes_demo.html");
  std::filesystem::remove(html);
  const Cli_run r = run("report " + k_demo + " -o " + html);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("-> " + html), std::string::npos) << r.out;
  const std::string page = slurp(html);
  EXPECT_EQ(page.rfind("<!DOCTYPE html>", 0), 0u);
  // Nothing is loaded from elsewhere: no script source, no style sheet, no import.
  for (const char* outside : {" src=", "<link", "@import", "url(http"})
    EXPECT_EQ(page.find(outside), std::string::npos) << outside;
  // Debian's three.js r111, its controls and loader, inlined.
  for (const char* script : {"REVISION=\"111\"", "var OrbitControls = function", "GLTFLoader"})
    EXPECT_NE(page.find(script), std::string::npos) << script;
  // The table: worst first.
  const std::regex row("<tr data-pair=\"(\\d)\"[^>]*><td>\\d</td><td>([^<]*)</td><td><span "
                       "class=\"cls (\\w+)\">");
  std::vector<std::string> rows;
  for (auto it = std::sregex_iterator(page.begin(), page.end(), row); it != std::sregex_iterator();
       ++it)
    rows.push_back((*it)[1].str() + " " + (*it)[2].str() + " " + (*it)[3].str());
  EXPECT_EQ(rows, (std::vector<std::string>{"1 A - bracket clash", "0 A - B clearance"}));
  // Each pair's plot, with the thresholds drawn.
  for (const char* plot : {"<template id=\"plot-0\">", "<template id=\"plot-1\">",
                           "clearance (d &lt; 2 mm)", "contact (|d| &lt;= 1e-09 mm)"})
    EXPECT_NE(page.find(plot), std::string::npos) << plot;
  // The 3D view's data: the worst pair at its minimum, the bracket where its keyframe puts it,
  // the witness segment as long as the depth.
  const nlohmann::json data = page_data(page);
  ASSERT_TRUE(data.is_object());
  EXPECT_EQ(data["worst"], 1);
  const nlohmann::json& worst = data["pairs"][1];
  EXPECT_EQ(worst["t"], 3.0);
  EXPECT_NEAR(worst["distance"].get<double>(), -0.080412, 1e-6);
  EXPECT_TRUE(worst["in_view"].get<bool>());
  EXPECT_NEAR(worst["pose_b"][12].get<double>(), -2.85, 1e-12);
  const auto& w = worst["witness"];
  const double length = std::hypot(w[1][0].get<double>() - w[0][0].get<double>(),
                                    w[1][1].get<double>() - w[0][1].get<double>(),
                                    w[1][2].get<double>() - w[0][2].get<double>());
  EXPECT_NEAR(length, 0.080412, 1e-6);
  // The bodies as binary glTF ("glTF" in base64 is "Z2xURg").
  EXPECT_NE(page.find("id=\"view-data\">Z2xURg"), std::string::npos);
}

TEST(ReportClasses, HtmlReportsOfABatchArePerScene) {
  const std::string a = spheres("classes_batch_a.json", 1.0);
  const std::string b = spheres("classes_batch_b.json", 0.5);
  const std::string out = scratch("classes_batch.html");
  ASSERT_EQ(run("report " + a + " " + b + " -o " + out + " --quiet").exit_code, 0);
  for (const char* tag : {"classes_batch_a", "classes_batch_b"}) {
    const std::string page = slurp(scratch(std::string("classes_batch.") + tag + ".html"));
    const nlohmann::json data = page_data(page);
    ASSERT_TRUE(data.is_object()) << tag;
    EXPECT_EQ(data["scene"], std::string(tag) + ".json");
  }
}

}  // namespace
}  // namespace extremal
