// Malformed and hostile STEP and IGES files (docs/import.md, "Limits and containment"): each is
// refused with an Invalid_input naming the file and the entity, by io::read_model and by
// `extremal info` / `extremal distance` (exit code 1, the message on stderr), and nothing
// crashes. The files are generated here (a B-spline face whose size, knots and references each
// test sets); a well-formed one of each kind reads, so every refusal is the rule under test.
// Also: the limits are configurable (Read_options, the process defaults, the CLI options), and
// the child process that runs OpenCASCADE returns exactly the model an in-process reading makes.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "io/Model_reader.h"
#include "io/internal/Readers.h"
#include "kernel/Error.h"
#include "support/Cli_run.h"

namespace extremal {
namespace {

using io::Import_limits;
using io::Read_options;

// A STEP file holding one face on a B-spline surface of nu x nv control points (degree 3 x 3,
// the face bounded by the surface's own edges), in a product with a shape representation, as a
// CAD system writes a sheet. The surface is entity #20; its control points are #100 onwards.
// `edit` replaces one entity's text (to make references go wrong).
struct Step_face {
  int nu = 4, nv = 4;
  std::vector<double> u_knots{0, 1}, v_knots{0, 1};
  std::vector<int> u_mults{4, 4}, v_mults{4, 4};

  // Uniform knots for n control points of degree 3.
  static void uniform(int n, std::vector<double>& knots, std::vector<int>& mults) {
    knots = {0.0};
    mults = {4};
    for (int i = 1; i < n - 3; ++i) {
      knots.push_back(static_cast<double>(i) / (n - 3));
      mults.push_back(1);
    }
    knots.push_back(1.0);
    mults.push_back(4);
  }
  // An n x n grid of control points on uniform knots.
  static Step_face grid(int n) {
    Step_face f;
    f.nu = f.nv = n;
    uniform(n, f.u_knots, f.u_mults);
    uniform(n, f.v_knots, f.v_mults);
    return f;
  }

  std::string text(const std::string& from = "", const std::string& to = "") const {
    std::string s;
    s.reserve(static_cast<std::size_t>(nu) * nv * 48 + 4096);
    s += "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('hostile file test'),'2;1');\n"
         "FILE_NAME('face','2026-01-01T00:00:00',(''),(''),'','','');\n"
         "FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));\nENDSEC;\nDATA;\n";
    std::vector<std::string> lines = {
        "#1=APPLICATION_CONTEXT('core data for automotive mechanical design processes');",
        "#2=PRODUCT_CONTEXT('',#1,'mechanical');",
        "#3=PRODUCT('face','face','',(#2));",
        "#4=PRODUCT_DEFINITION_FORMATION('','',#3);",
        "#5=PRODUCT_DEFINITION_CONTEXT('part definition',#1,'design');",
        "#6=PRODUCT_DEFINITION('design','',#4,#5);",
        "#7=PRODUCT_DEFINITION_SHAPE('',$,#6);",
        "#10=(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.));",
        "#11=(NAMED_UNIT(*)PLANE_ANGLE_UNIT()SI_UNIT($,.RADIAN.));",
        "#12=(NAMED_UNIT(*)SI_UNIT($,.STERADIAN.)SOLID_ANGLE_UNIT());",
        "#13=UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-07),#10,'distance_accuracy_value','');",
        "#14=(GEOMETRIC_REPRESENTATION_CONTEXT(3)GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((#13))"
        "GLOBAL_UNIT_ASSIGNED_CONTEXT((#10,#11,#12))REPRESENTATION_CONTEXT('',''));",
        "#15=SHAPE_DEFINITION_REPRESENTATION(#7,#16);",
        "#16=MANIFOLD_SURFACE_SHAPE_REPRESENTATION('',(#17),#14);",
        "#17=SHELL_BASED_SURFACE_MODEL('',(#18));",
        "#18=OPEN_SHELL('',(#19));",
        "#19=ADVANCED_FACE('',(),#20,.T.);"};
    for (const std::string& l : lines) s += (!from.empty() && l == from ? to : l) + "\n";
    int id = 100;
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j) {
        s += "#" + std::to_string(id++) + "=CARTESIAN_POINT('',(" + std::to_string(i) + ".," +
             std::to_string(j) + ".," + std::to_string((i * j) % 7) + ".));\n";
      }
    s += "#20=B_SPLINE_SURFACE_WITH_KNOTS('',3,3,(";
    id = 100;
    for (int i = 0; i < nu; ++i) {
      s += i ? ",(" : "(";
      for (int j = 0; j < nv; ++j) s += (j ? ",#" : "#") + std::to_string(id++);
      s += ")";
    }
    s += "),.UNSPECIFIED.,.F.,.F.,.F.,";
    auto list = [&](const auto& v) {
      std::ostringstream os;
      os.precision(17);
      os << "(";
      for (std::size_t k = 0; k < v.size(); ++k) os << (k ? "," : "") << v[k];
      os << ")";
      return os.str();
    };
    // Reals need a decimal point in STEP.
    auto reals = [&](const std::vector<double>& v) {
      std::string r = "(";
      for (std::size_t k = 0; k < v.size(); ++k) {
        std::ostringstream os;
        os.precision(17);
        os << v[k];
        std::string x = os.str();
        if (x.find('.') == std::string::npos) x += ".";
        r += (k ? "," : "") + x;
      }
      return r + ")";
    };
    s += list(u_mults) + "," + list(v_mults) + "," + reals(u_knots) + "," + reals(v_knots) +
         ",.UNSPECIFIED.);\nENDSEC;\nEND-ISO-10303-21;\n";
    return s;
  }
};

// An IGES file holding one bare rational B-spline surface (entity 128, directory entry D1) of
// (k1 + 1) x (k2 + 1) control points and degree m1 x m2, with uniform clamped knots unless
// `u_knots` is given. `announce_k1` (if >= 0) is the upper index the entity claims instead of
// the one it holds data for.
struct Iges_surface {
  int k1 = 3, k2 = 3, m1 = 3, m2 = 3;
  std::vector<double> u_knots;
  long long announce_k1 = -1;

  static std::string field(const std::string& s, std::size_t width, bool right = true) {
    if (s.size() >= width) return s.substr(0, width);
    return right ? std::string(width - s.size(), ' ') + s : s + std::string(width - s.size(), ' ');
  }
  static std::string seq(char section, int n) { return section + field(std::to_string(n), 7); }

  static std::vector<double> clamped(int k, int m) {
    std::vector<double> t(m + 1, 0.0);
    const int inner = k - m;
    for (int i = 1; i <= inner; ++i) t.push_back(static_cast<double>(i) / (inner + 1));
    for (int i = 0; i <= m; ++i) t.push_back(1.0);
    return t;
  }

  std::string text(bool with_terminate = true) const {
    std::vector<std::string> params = {"128", std::to_string(announce_k1 >= 0 ? announce_k1 : k1),
                                       std::to_string(k2), std::to_string(m1), std::to_string(m2),
                                       "0", "0", "1", "0", "0"};
    auto num = [](double x) {
      std::ostringstream os;
      os.precision(17);
      os << x;
      std::string s = os.str();
      if (s.find_first_of(".eE") == std::string::npos) s += ".";
      return s;
    };
    for (double t : u_knots.empty() ? clamped(k1, m1) : u_knots) params.push_back(num(t));
    for (double t : clamped(k2, m2)) params.push_back(num(t));
    for (int i = 0; i < (k1 + 1) * (k2 + 1); ++i) params.push_back("1.");
    for (int j = 0; j <= k2; ++j)
      for (int i = 0; i <= k1; ++i) {
        params.push_back(num(i));
        params.push_back(num(j));
        params.push_back(num((i * j) % 5));
      }
    for (const char* p : {"0.", "1.", "0.", "1."}) params.push_back(p);
    // Parameter lines: columns 1-64 data, 66-72 the directory entry (1), 73-80 P and number.
    std::vector<std::string> plines;
    std::string cur;
    for (std::size_t i = 0; i < params.size(); ++i) {
      const std::string item = params[i] + (i + 1 == params.size() ? ";" : ",");
      if (cur.size() + item.size() > 64) {
        plines.push_back(cur);
        cur.clear();
      }
      cur += item;
    }
    plines.push_back(cur);
    std::string s;
    auto record = [&](const std::string& data, char section, int n) {
      s += field(data, 72, false) + seq(section, n) + "\n";
    };
    record("Extremal hostile file test", 'S', 1);
    const std::string global =
        "1H,,1H;,4Htest,8Htest.igs,8Hextremal,3H1.0,32,308,15,308,15,4Htest,1.,2,2HMM,1,1.,"
        "15H20260101.000000,1.E-07,1000.,4Htest,4Htest,11,0;";
    int g = 0;
    for (std::size_t i = 0; i < global.size(); i += 72) record(global.substr(i, 72), 'G', ++g);
    const std::string de1 = field("128", 8) + field("1", 8) + field("0", 8) + field("0", 8) +
                            field("0", 8) + field("0", 8) + field("0", 8) + field("0", 8) +
                            field("00000000", 8);
    const std::string de2 = field("128", 8) + field("0", 8) + field("0", 8) +
                            field(std::to_string(plines.size()), 8) + field("0", 8) +
                            field("", 8) + field("", 8) + field("", 8) + field("0", 8);
    record(de1, 'D', 1);
    record(de2, 'D', 2);
    for (std::size_t i = 0; i < plines.size(); ++i)
      record(field(plines[i], 64, false) + " " + field("1", 7), 'P', static_cast<int>(i + 1));
    if (with_terminate)
      record(seq('S', 1) + seq('G', g) + seq('D', 2) + seq('P', static_cast<int>(plines.size())),
             'T', 1);
    return s;
  }
};

std::string write_file(const std::string& name, const std::string& text) {
  const std::string path = (test::scratch_dir() / name).string();
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// read_model refuses `path` with a message holding every one of `parts` (and the path).
void expect_refused(const std::string& path, const std::vector<std::string>& parts,
                    const Read_options& options = {}) {
  try {
    const io::Model m = io::read_model(path, options);
    ADD_FAILURE() << path << " was read (" << m.bodies.size() << " bodies)";
  } catch (const Invalid_input& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path), std::string::npos) << what;
    for (const std::string& p : parts) EXPECT_NE(what.find(p), std::string::npos) << p << " in: " << what;
  }
}

// `extremal info` and `extremal distance` on the file: exit code 1, the path and every one of
// `parts` on stderr.
void expect_cli_refuses(const std::string& path, const std::vector<std::string>& parts,
                        const std::string& global_options = "") {
  for (const std::string& cmd : {"info " + path, "distance " + path + " point"}) {
    const test::Cli_run r = test::run_cli(global_options + cmd);
    EXPECT_EQ(r.exit_code, 1) << cmd << "\n" << r.err;
    EXPECT_NE(r.err.find(path), std::string::npos) << cmd << "\n" << r.err;
    for (const std::string& p : parts)
      EXPECT_NE(r.err.find(p), std::string::npos) << cmd << ": " << p << " in: " << r.err;
  }
}

TEST(HostileStep, WellFormedFaceReads) {
  const std::string path = write_file("face.stp", Step_face{}.text());
  const io::Model m = io::read_model(path);
  ASSERT_EQ(m.bodies.size(), 1u);
  ASSERT_EQ(m.bodies[0].faces.size(), 1u);
  EXPECT_EQ(m.bodies[0].faces[0].surface.number_of_poles_u(), 4);
  const test::Cli_run r = test::run_cli("info " + path);
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST(HostileStep, MillionPoleSurfaceIsRefusedByThePatchLimitBeforeOpenCascadeReadsIt) {
  const Step_face f = Step_face::grid(1000);
  const std::string path = write_file("million_poles.stp", f.text());
  const std::vector<std::string> parts = {"STEP #20 (B_SPLINE_SURFACE_WITH_KNOTS)",
                                          "1000000 control points",
                                          std::to_string(Import_limits{}.max_patch_poles),
                                          "max_patch_poles", "--max-patch-poles"};
  // The limit holds even with OpenCASCADE in this process: the scan refuses the text.
  Read_options in_process;
  in_process.limits.isolate = false;
  expect_refused(path, parts, in_process);
  expect_cli_refuses(path, parts);

  // With the pole limits off, the memory limit stops OpenCASCADE's reading in its process
  // (its STEP reader needs well over 256 MiB for a million entities), naming the file.
  Read_options no_pole_limits;
  no_pole_limits.limits.max_patch_poles = 0;
  no_pole_limits.limits.max_total_poles = 0;
  no_pole_limits.limits.max_memory_mb = 256;
  expect_refused(path, {"more than 256 MiB of memory", "max_memory_mb", "--import-memory-mb"},
                 no_pole_limits);
  std::filesystem::remove(path);
}

TEST(HostileStep, PatchAndTotalLimitsAreConfigurable) {
  const Step_face f = Step_face::grid(30);
  const std::string path = write_file("grid30.stp", f.text());
  Read_options options;
  options.limits.max_patch_poles = 899;
  expect_refused(path, {"STEP #20", "900 control points", "899"}, options);
  options.limits.max_patch_poles = 900;
  EXPECT_EQ(io::read_model(path, options).bodies.size(), 1u);
  options.limits.max_patch_poles = 0;  // off
  options.limits.max_total_poles = 899;
  expect_refused(path, {"900 control points in all", "899", "max_total_poles"}, options);

  // Process defaults (what the CLI options set) reach a default-constructed Read_options.
  const Import_limits saved = io::default_import_limits();
  Import_limits lowered;
  lowered.max_patch_poles = 899;
  io::set_default_import_limits(lowered);
  expect_refused(path, {"900 control points"});
  io::set_default_import_limits(saved);
  EXPECT_EQ(io::read_model(path).bodies.size(), 1u);

  // The CLI options, before or after the subcommand.
  expect_cli_refuses(path, {"900 control points", "899"}, "--max-patch-poles 899 ");
  EXPECT_EQ(test::run_cli("info " + path + " --max-total-poles 900").exit_code, 0);
  EXPECT_EQ(test::run_cli("info " + path + " --max-total-poles 899").exit_code, 1);
  EXPECT_EQ(test::run_cli("info " + path + " --max-total-poles -1").exit_code, 2);
}

TEST(HostileStep, ZeroLengthKnotSpanNamesTheSurfaceAndTheKnot) {
  Step_face f;
  f.nu = 5;
  f.u_knots = {0, 0, 1};  // the second distinct knot repeats the first
  f.u_mults = {4, 1, 4};
  const std::string path = write_file("zero_span.stp", f.text());
  const std::vector<std::string> parts = {"STEP #20", "u knots are not strictly increasing",
                                          "knot 2 (0) follows 0", "zero-length knot span"};
  expect_refused(path, parts);
  expect_cli_refuses(path, parts);
}

TEST(HostileStep, DecreasingKnotsNameTheSurfaceAndTheKnot) {
  Step_face f;
  f.nu = 5;
  f.u_knots = {0, 1, 0.5};
  f.u_mults = {4, 1, 4};
  const std::string path = write_file("decreasing.stp", f.text());
  const std::vector<std::string> parts = {"STEP #20", "knot 3 (0.5) follows 1"};
  expect_refused(path, parts);
  expect_cli_refuses(path, parts);
}

TEST(HostileStep, SelfReferencingEntityIsRefused) {
  const std::string path = write_file(
      "self_reference.stp",
      Step_face{}.text("#18=OPEN_SHELL('',(#19));", "#18=OPEN_SHELL('',(#18));"));
  const std::vector<std::string> parts = {"STEP #18 (OPEN_SHELL) refers to itself"};
  Read_options in_process;
  in_process.limits.isolate = false;
  expect_refused(path, parts, in_process);
  expect_cli_refuses(path, parts);
}

TEST(HostileStep, ReferenceCycleThroughOtherEntitiesIsRefused) {
  const std::string path = write_file(
      "cycle.stp", Step_face{}.text("#18=OPEN_SHELL('',(#19));", "#18=OPEN_SHELL('',(#16));"));
  expect_refused(path, {"STEP #16 (MANIFOLD_SURFACE_SHAPE_REPRESENTATION) refers back to itself",
                        "#16 -> #17 -> #18 -> #16", "reference cycle"});
}

TEST(HostileStep, TruncatedFileNamesTheEntityItEndsIn) {
  const std::string full = Step_face{}.text();
  const std::size_t cut = full.find("#20=B_SPLINE_SURFACE_WITH_KNOTS") + 60;
  const std::string path = write_file("truncated.stp", full.substr(0, cut));
  const std::vector<std::string> parts = {"ends inside entity #20", "truncated"};
  expect_refused(path, parts);
  expect_cli_refuses(path, parts);
  // Cut after the last entity: no ENDSEC, no END-ISO-10303-21.
  const std::string path2 = write_file("no_end.stp", full.substr(0, full.find("ENDSEC;\nEND-ISO")));
  expect_refused(path2, {"no ENDSEC", "truncated", "#20"});
  // Cut inside a string.
  const std::string path3 = write_file("in_string.stp", full.substr(0, full.find("'core data") + 5));
  expect_refused(path3, {"ends inside", "truncated"});
}

// The limit bounds what the reading adds to the process it forks from, so it is shown in a
// fresh process (the CLI): OpenCASCADE's STEP reader needs far more than 1 MiB to start.
TEST(HostileStep, TinyMemoryLimitStopsTheReaderProcess) {
  const std::string path = write_file("face_memory.stp", Step_face{}.text());
  expect_cli_refuses(path, {"more than 1 MiB of memory", "--import-memory-mb"},
                     "--import-memory-mb 1 ");
  EXPECT_EQ(test::run_cli("--import-memory-mb 64 info " + path).exit_code, 0);
}

TEST(HostileIges, WellFormedSurfaceReads) {
  const std::string path = write_file("surface.igs", Iges_surface{}.text());
  const io::Model m = io::read_model(path);
  ASSERT_EQ(m.bodies.size(), 1u);
  ASSERT_EQ(m.bodies[0].faces.size(), 1u);
  EXPECT_EQ(m.bodies[0].faces[0].surface.number_of_poles_u() *
                m.bodies[0].faces[0].surface.number_of_poles_v(),
            16);
}

TEST(HostileIges, PatchLimitNamesTheEntity) {
  Iges_surface s;
  s.k1 = s.k2 = 29;
  const std::string path = write_file("grid30.igs", s.text());
  Read_options options;
  options.limits.max_patch_poles = 899;
  expect_refused(path, {"IGES entity D1 (type 128)", "900 control points", "899"}, options);
  options.limits.max_patch_poles = 900;
  EXPECT_EQ(io::read_model(path, options).bodies.size(), 1u);
}

TEST(HostileIges, MillionPolesAnnouncedInATinyEntityAreRefused) {
  Iges_surface s;
  s.announce_k1 = 999'999;  // the data holds 4 x 4
  const std::string path = write_file("announces.igs", s.text());
  const std::vector<std::string> parts = {"IGES entity D1 (type 128)", "announces 1000000 control points"};
  Read_options in_process;
  in_process.limits.isolate = false;
  expect_refused(path, parts, in_process);
  expect_cli_refuses(path, parts);
}

TEST(HostileIges, DecreasingKnotsNameTheEntity) {
  Iges_surface s;
  s.u_knots = {0, 0, 0, 0, 1, 1, 0.5, 1};
  const std::string path = write_file("decreasing.igs", s.text());
  const std::vector<std::string> parts = {"IGES entity D1", "u knots decrease: knot 7 (0.5) follows 1"};
  expect_refused(path, parts);
  expect_cli_refuses(path, parts);
}

TEST(HostileIges, TruncatedFileIsRefused) {
  const std::string full = Iges_surface{}.text(false);
  const std::string path = write_file("truncated.igs", full);
  expect_refused(path, {"no Terminate (T) record", "truncated"});
  // Cut inside the parameter data: the directory entry points past the end.
  const std::string cut = full.substr(0, full.find("P      2"));
  const std::string path2 = write_file("truncated2.igs", cut);
  expect_refused(path2, {"truncated"});
  expect_cli_refuses(path2, {"truncated"});
}

// The child process returns the model an in-process reading makes, bit for bit.
void expect_same_model(const io::Model& a, const io::Model& b) {
  EXPECT_EQ(a.format_name, b.format_name);
  EXPECT_EQ(a.file_unit, b.file_unit);
  EXPECT_EQ(a.scale_to_unit, b.scale_to_unit);
  EXPECT_EQ(a.warnings, b.warnings);
  ASSERT_EQ(a.skipped.size(), b.skipped.size());
  for (std::size_t i = 0; i < a.skipped.size(); ++i) {
    EXPECT_EQ(a.skipped[i].entity, b.skipped[i].entity);
    EXPECT_EQ(a.skipped[i].reason, b.skipped[i].reason);
  }
  ASSERT_EQ(a.bodies.size(), b.bodies.size());
  for (std::size_t k = 0; k < a.bodies.size(); ++k) {
    const Body& x = a.bodies[k];
    const Body& y = b.bodies[k];
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.source_name, y.source_name);
    EXPECT_EQ(x.placement.rotation(), y.placement.rotation());
    EXPECT_EQ(x.placement.translation(), y.placement.translation());
    ASSERT_EQ(x.faces.size(), y.faces.size());
    for (std::size_t i = 0; i < x.faces.size(); ++i) {
      const Face& f = x.faces[i];
      const Face& g = y.faces[i];
      EXPECT_EQ(f.surface.poles(), g.surface.poles());
      EXPECT_EQ(f.surface.knots_u(), g.surface.knots_u());
      EXPECT_EQ(f.surface.knots_v(), g.surface.knots_v());
      EXPECT_EQ(f.surface.weights(), g.surface.weights());
      EXPECT_EQ(f.surface.outward_sign(), g.surface.outward_sign());
      EXPECT_EQ(f.surface.is_closed_u(), g.surface.is_closed_u());
      EXPECT_EQ(f.source, g.source);
      EXPECT_EQ(f.approximation_error, g.approximation_error);
      EXPECT_EQ(f.trim_region.tolerance(), g.trim_region.tolerance());
      EXPECT_EQ(f.trim_region.number_of_segments(), g.trim_region.number_of_segments());
      ASSERT_EQ(f.trims.size(), g.trims.size());
      for (std::size_t l = 0; l < f.trims.size(); ++l) {
        ASSERT_EQ(f.trims[l].curves.size(), g.trims[l].curves.size());
        EXPECT_EQ(f.trims[l].is_outer, g.trims[l].is_outer);
        for (std::size_t c = 0; c < f.trims[l].curves.size(); ++c) {
          EXPECT_EQ(f.trims[l].curves[c].uv.poles(), g.trims[l].curves[c].uv.poles());
          EXPECT_EQ(f.trims[l].curves[c].uv.knots(), g.trims[l].curves[c].uv.knots());
          EXPECT_EQ(f.trims[l].curves[c].edge, g.trims[l].curves[c].edge);
          EXPECT_EQ(f.trims[l].curves[c].reversed, g.trims[l].curves[c].reversed);
        }
      }
    }
    ASSERT_EQ(x.edges.size(), y.edges.size());
    for (std::size_t i = 0; i < x.edges.size(); ++i) {
      EXPECT_EQ(x.edges[i].curve.has_value(), y.edges[i].curve.has_value());
      if (x.edges[i].curve && y.edges[i].curve) {
        EXPECT_EQ(x.edges[i].curve->poles(), y.edges[i].curve->poles());
      }
      EXPECT_EQ(x.edges[i].tolerance, y.edges[i].tolerance);
      EXPECT_EQ(x.edges[i].t_min, y.edges[i].t_min);
      EXPECT_EQ(x.edges[i].same_parameter, y.edges[i].same_parameter);
      EXPECT_EQ(x.edges[i].uses.size(), y.edges[i].uses.size());
    }
    EXPECT_EQ(x.mesh.vertices, y.mesh.vertices);
  }
}

TEST(ReaderProcess, ReturnsTheModelAnInProcessReadingMakes) {
  const std::string shared = EXTREMAL_SHARED_DATA;
  for (const std::string file : {"/step/screw.step", "/step/bug28414_bug_toroidal_surface.stp",
                                 "/iges/OCC26138_Torus.igs"}) {
    const std::string path = shared + file;
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared data not found: " << path;
    Read_options in_process;
    in_process.limits.isolate = false;
    SCOPED_TRACE(path);
    expect_same_model(io::read_model(path), io::read_model(path, in_process));
  }
}

TEST(ReaderProcess, EncodingIsExactAndRefusesTruncation) {
  const io::Model m = io::read_model(write_file("face_codec.stp", Step_face{}.text()));
  const std::string bytes = io::internal::encode_model(m);
  expect_same_model(io::internal::decode_model(bytes), m);
  EXPECT_THROW(io::internal::decode_model(bytes.substr(0, bytes.size() - 1)), Invalid_input);
  EXPECT_THROW(io::internal::decode_model(bytes + "x"), Invalid_input);
}

}  // namespace
}  // namespace extremal
