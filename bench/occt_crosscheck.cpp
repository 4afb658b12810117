// occt_crosscheck: apart rows of a scene checked against OpenCASCADE's BRepExtrema_DistShapeShape,
// an implementation independent of ours (docs/checking.md, "The certificate hunt").
//
//   ./build/bench/occt_crosscheck SCENE.json ROWS.json [--tolerance E] [--json OUT] [--rows]
//
// ROWS.json: {"rows": [[t, pair, distance, lower_bound, certified], ...]}, `pair` the index of
// a watched pair of the scene (as `verify_report --json` writes its apart rows; lower_bound
// null when the row has none, certified false for an `uncertified` row, true when left out).
// At each row's t both bodies are built as OpenCASCADE shapes at their poses and BRepExtrema's
// distance D, the distance of a real pair of points (an upper bound on the true distance, to
// its own precision), is compared with the row: wrong when the row's lower bound, or a
// certified row's distance, is above D + E x max(1, D) + the bodies' edge tolerances (a
// certified distance is the minimum to the budget: a row above a pair OpenCASCADE found is
// not the minimum; a lower bound above it is false), and when BRepExtrema finds one solid
// holding the other (its inner solution) where the row reads them apart. An uncertified row
// above D is counted, not wrong (it promises its lower bound only); D above the row counts as
// OpenCASCADE missing the minimum (reported, not wrong).
//
// The shapes: a file that OpenCASCADE reads (STEP, IGES, BREP) is read again by it, and each
// scene body matched with the file's solid, shell or face whose box is the body's (a body not
// matched is skipped); other bodies (shape specs, OBJ free-form, meshes) are built from our
// geometry: each untrimmed face's NURBS over its domain, curves as edges, a point as a vertex,
// mesh triangles as plane faces (meshes of more than --max-triangles are skipped: BRepExtrema
// takes too long on them). Exit code 0 when no row is wrong, 3 when some is, 1 on bad input.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "support/Occt_bridge.h"  // CGAL before OpenCASCADE

#include "io/Model_reader.h"
#include "io/Scene.h"
#include "kernel/Error.h"

#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepBuilderAPI_Transform.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <Bnd_Box.hxx>
#include <Geom_BSplineCurve.hxx>
#include <IGESControl_Reader.hxx>
#include <STEPControl_Reader.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array1OfPnt.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopExp.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <gp_Trsf.hxx>

namespace {

using namespace extremal;

// A scene body matched with a file's sub-shape when their boxes' centres lie within this
// fraction of the body's box diagonal (and their diagonals agree as closely): the file's
// solids of an assembly lie far further apart than that.
constexpr double k_box_match = 0.02;
// BRepExtrema's deflection (the precision of its extrema), as bench/compare uses it.
constexpr double k_occt_deflection = 1e-7;

struct Options {
  std::string scene, rows_file, json;
  double tolerance = 1e-6;
  int max_triangles = 2000;
  bool rows = false;
};

// Our body's geometry as a shape in its body frame, or why not.
std::optional<TopoDS_Shape> from_geometry(const Body& b, int max_triangles, std::string& why) {
  BRep_Builder builder;
  TopoDS_Compound c;
  builder.MakeCompound(c);
  if (b.is_point) builder.Add(c, BRepBuilderAPI_MakeVertex(gp_Pnt(0, 0, 0)).Vertex());
  for (const Face& f : b.faces) {
    if (!f.trims.empty()) {
      why = "trimmed faces not read by OpenCASCADE";
      return std::nullopt;
    }
    const Nurbs_surface_3& s = f.surface;
    BRepBuilderAPI_MakeFace face(bench::to_occt(s, Rigid_pose_3()), s.u_min(), s.u_max(),
                                 s.v_min(), s.v_max(), 1e-7);
    if (!face.IsDone()) {
      why = "a face OpenCASCADE cannot build";
      return std::nullopt;
    }
    builder.Add(c, face.Face());
  }
  for (const Nurbs_curve_3& k : b.curves)
    builder.Add(c, BRepBuilderAPI_MakeEdge(bench::to_occt(k), k.domain_min(), k.domain_max()).Edge());
  if (static_cast<int>(b.mesh.triangles.size()) > max_triangles) {
    why = "mesh over --max-triangles";
    return std::nullopt;
  }
  for (const auto& t : b.mesh.triangles) {
    gp_Pnt p[3];
    for (int i = 0; i < 3; ++i) {
      const Point_3& v = b.mesh.vertices[t[i]];
      p[i] = gp_Pnt(CGAL::to_double(v.x()), CGAL::to_double(v.y()), CGAL::to_double(v.z()));
    }
    if (p[0].Distance(p[1]) <= 0 || p[1].Distance(p[2]) <= 0 || p[0].Distance(p[2]) <= 0 ||
        gp_Vec(p[0], p[1]).Crossed(gp_Vec(p[0], p[2])).Magnitude() <= 0) {
      // A degenerate triangle: its vertices as points (they lie on its neighbours' edges).
      for (const gp_Pnt& q : p) builder.Add(c, BRepBuilderAPI_MakeVertex(q).Vertex());
      continue;
    }
    BRepBuilderAPI_MakePolygon poly(p[0], p[1], p[2], true);
    BRepBuilderAPI_MakeFace face(poly.Wire(), true);
    if (!face.IsDone()) {
      why = "a mesh triangle OpenCASCADE cannot build";
      return std::nullopt;
    }
    builder.Add(c, face.Face());
  }
  return c;
}

// The file as OpenCASCADE reads it (null when it is no STEP, IGES or BREP file).
TopoDS_Shape read_file(const std::string& path) {
  std::string lower = path;
  std::transform(lower.begin(), lower.end(), lower.begin(), ::tolower);
  auto ends = [&](const char* e) {
    const std::string s(e);
    return lower.size() >= s.size() && lower.compare(lower.size() - s.size(), s.size(), s) == 0;
  };
  if (ends(".step") || ends(".stp")) {
    STEPControl_Reader r;
    if (r.ReadFile(path.c_str()) != IFSelect_RetDone) return {};
    r.TransferRoots();
    return r.OneShape();
  }
  if (ends(".igs") || ends(".iges")) {
    IGESControl_Reader r;
    if (r.ReadFile(path.c_str()) != IFSelect_RetDone) return {};
    r.TransferRoots();
    return r.OneShape();
  }
  if (ends(".brep")) {
    TopoDS_Shape s;
    BRep_Builder b;
    if (!BRepTools::Read(s, path.c_str(), b)) return {};
    return s;
  }
  return {};
}

struct Box {
  Vec3 centre = Vec3::Zero();
  double diagonal = 0.0;
};
Box box_of(const TopoDS_Shape& s) {
  Bnd_Box b;
  BRepBndLib::AddOptimal(s, b, false, false);
  Box out;
  if (b.IsVoid()) return out;
  double x0, y0, z0, x1, y1, z1;
  b.Get(x0, y0, z0, x1, y1, z1);
  out.centre = 0.5 * Vec3(x0 + x1, y0 + y1, z0 + z1);
  out.diagonal = (Vec3(x1, y1, z1) - Vec3(x0, y0, z0)).norm();
  return out;
}
Box box_of(const Bbox_3& b) {
  Box out;
  out.centre = 0.5 * Vec3(b.xmin() + b.xmax(), b.ymin() + b.ymax(), b.zmin() + b.zmax());
  out.diagonal = Vec3(b.xmax() - b.xmin(), b.ymax() - b.ymin(), b.zmax() - b.zmin()).norm();
  return out;
}

// The sub-shapes of `file` of one kind, each instance once.
std::vector<TopoDS_Shape> parts_of(const TopoDS_Shape& file, TopAbs_ShapeEnum kind,
                                   TopAbs_ShapeEnum not_in) {
  std::vector<TopoDS_Shape> out;
  TopTools_IndexedMapOfShape seen;
  for (TopExp_Explorer e(file, kind, not_in); e.More(); e.Next())
    if (seen.Add(e.Current())) out.push_back(e.Current());
  return out;
}

// A shape per scene body, in the frame the body's entry motion places (a file's frame for a
// file's sub-shape, the body frame for our geometry), or why there is none.
struct Occt_body {
  TopoDS_Shape shape;
  bool file_frame = false;
  bool solid = false;
  std::string why;  // not empty: no shape
};

std::vector<Occt_body> occt_bodies(const io::Scene& scene, int max_triangles) {
  std::vector<Occt_body> out(scene.bodies.size());
  std::map<std::string, std::vector<int>> by_file;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) by_file[scene.bodies[i].source].push_back(static_cast<int>(i));
  for (const auto& [source, members] : by_file) {
    const TopoDS_Shape file = read_file(source);
    if (file.IsNull()) {
      for (int i : members) {
        const std::optional<TopoDS_Shape> s = from_geometry(scene.bodies[i].body, max_triangles, out[i].why);
        if (s) out[i].shape = *s;
      }
      continue;
    }
    // The level whose count is the file's body count: solids, free shells, free faces.
    std::vector<TopoDS_Shape> parts;
    TopAbs_ShapeEnum level = TopAbs_SOLID;
    for (const auto& [kind, not_in] : {std::make_pair(TopAbs_SOLID, TopAbs_SHAPE),
                                       std::make_pair(TopAbs_SHELL, TopAbs_SOLID),
                                       std::make_pair(TopAbs_FACE, TopAbs_SHELL)}) {
      parts = parts_of(file, kind, not_in);
      level = kind;
      if (parts.size() == members.size()) break;
    }
    if (parts.size() != members.size() && members.size() == 1) {
      // One body: all of the file's faces (free edges and vertices are no body of ours).
      BRep_Builder b;
      TopoDS_Compound c;
      b.MakeCompound(c);
      for (const TopoDS_Shape& f : parts_of(file, TopAbs_FACE, TopAbs_SHAPE)) b.Add(c, f);
      parts = {c};
      level = TopAbs_COMPOUND;
    }
    std::vector<Box> boxes;
    for (const TopoDS_Shape& p : parts) boxes.push_back(box_of(p));
    for (int i : members) {
      const Body& body = scene.bodies[i].body;
      const Box ours = box_of(body.trimmed_bbox(body.placement));
      int best = -1;
      double best_d = HUGE_VAL;
      for (std::size_t k = 0; k < parts.size(); ++k) {
        const double d = (boxes[k].centre - ours.centre).norm() +
                         std::abs(boxes[k].diagonal - ours.diagonal);
        if (d < best_d) {
          best_d = d;
          best = static_cast<int>(k);
        }
      }
      if (best < 0 || best_d > k_box_match * ours.diagonal + 1e-6) {
        out[i].why = "no sub-shape of the file matches the body's box";
        continue;
      }
      out[i].shape = parts[best];
      out[i].file_frame = true;
      out[i].solid = level == TopAbs_SOLID;
    }
  }
  return out;
}

double edge_tolerance(const Body& body) {
  double t = 0.0;
  for (const Edge& e : body.edges) t = std::max(t, e.tolerance);
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"Checks a scene's apart rows against OpenCASCADE's BRepExtrema_DistShapeShape"};
  app.add_option("scene", o.scene, "Scene file")->required();
  app.add_option("rows", o.rows_file, "Rows: {\"rows\": [[t, pair, distance, lower_bound], ...]}")
      ->required();
  app.add_option("--tolerance", o.tolerance, "Allowed excess over OpenCASCADE's distance, relative to max(1, D)")
      ->check(CLI::PositiveNumber);
  app.add_option("--max-triangles", o.max_triangles, "Skip meshes of more triangles")
      ->check(CLI::PositiveNumber);
  app.add_option("--json", o.json, "Write the results as JSON");
  app.add_flag("--rows", o.rows, "Print every row");
  CLI11_PARSE(app, argc, argv);
  try {
    const io::Scene scene = io::read_scene(o.scene, io::load_bodies);
    nlohmann::json input;
    {
      std::ifstream f(o.rows_file);
      if (!f) throw Invalid_input(o.rows_file + ": cannot be read");
      input = nlohmann::json::parse(f, nullptr, false);
      if (input.is_discarded() || !input.contains("rows") || !input["rows"].is_array())
        throw Invalid_input(o.rows_file + ": expected {\"rows\": [[t, pair, distance, lower_bound], ...]}");
    }
    const std::vector<Occt_body> bodies = occt_bodies(scene, o.max_triangles);
    int checked = 0, wrong = 0, occt_above = 0, uncertified_above = 0;
    std::map<std::string, int> skipped;
    double max_row_above = -HUGE_VAL, max_occt_above = 0.0;
    nlohmann::json rows = nlohmann::json::array();
    for (const nlohmann::json& row : input["rows"]) {
      const double t = row.at(0).get<double>();
      const int k = row.at(1).get<int>();
      const double d = row.at(2).get<double>();
      const double lower = row.at(3).is_null() ? -HUGE_VAL : row.at(3).get<double>();
      const bool certified = row.size() < 5 || row.at(4).get<bool>();
      if (k < 0 || k >= static_cast<int>(scene.pairs.size()))
        throw Invalid_input(o.rows_file + ": pair " + std::to_string(k) + " out of range");
      const auto& [ia, ib] = scene.pairs[k];
      const io::Scene_body& A = scene.bodies[ia];
      const io::Scene_body& B = scene.bodies[ib];
      nlohmann::json r = {{"t", t}, {"pair", k}, {"body_a", A.name}, {"body_b", B.name},
                          {"distance", d}, {"lower_bound", row.at(3)}, {"certified", certified}};
      const Occt_body& oa = bodies[ia];
      const Occt_body& ob = bodies[ib];
      if (!oa.why.empty() || !ob.why.empty()) {
        ++skipped[!oa.why.empty() ? oa.why : ob.why];
        continue;
      }
      auto place = [&](const Occt_body& b, const io::Scene_body& s) {
        const Rigid_pose_3 entry = s.motion.pose_at(t);
        return bench::moved(b.shape, b.file_frame ? entry : entry * s.body.placement);
      };
      double occt = HUGE_VAL;
      bool inner = false;
      try {
        BRepExtrema_DistShapeShape ext(place(oa, A), place(ob, B), k_occt_deflection);
        if (ext.IsDone()) {
          occt = ext.Value();
          inner = ext.InnerSolution();
        }
      } catch (const Standard_Failure&) {
      }
      if (!std::isfinite(occt)) {
        ++skipped["BRepExtrema failed"];
        continue;
      }
      ++checked;
      const double allowed = o.tolerance * std::max(1.0, occt) +
                             edge_tolerance(A.body) + edge_tolerance(B.body);
      std::string verdict = "ok";
      if (lower > occt + allowed) verdict = "lower bound above OpenCASCADE's distance";
      else if (certified && d > occt + allowed) verdict = "distance above OpenCASCADE's";
      else if (inner && d > allowed) verdict = "apart, but OpenCASCADE finds one solid holding the other";
      if (certified) max_row_above = std::max(max_row_above, d - occt);
      if (occt - d > allowed) ++occt_above;
      if (!certified && d > occt + allowed) ++uncertified_above;
      max_occt_above = std::max(max_occt_above, occt - d);
      r["occt"] = occt;
      r["inner"] = inner;
      r["verdict"] = verdict;
      rows.push_back(r);
      if (verdict != "ok") ++wrong;
      if (o.rows || verdict != "ok")
        std::printf("  %s t = %.17g %s - %s: row %.12g%s (lower bound %.12g), BRepExtrema %.12g%s: %s\n",
                    verdict == "ok" ? "ok" : "WRONG", t, A.name.c_str(), B.name.c_str(), d,
                    certified ? "" : " uncertified", lower, occt, inner ? " (inner)" : "",
                    verdict.c_str());
    }
    int skipped_total = 0;
    for (const auto& [why, n] : skipped) skipped_total += n;
    std::printf("%s: %d apart rows against BRepExtrema: %d wrong; %d where BRepExtrema is above the "
                "row by more than the tolerance (it missed the minimum); row - BRepExtrema at most "
                "%.3g (certified rows); %d uncertified rows above it; %d skipped",
                o.scene.c_str(), checked, wrong, occt_above,
                max_row_above > -HUGE_VAL ? max_row_above : 0.0, uncertified_above, skipped_total);
    for (const auto& [why, n] : skipped) std::printf(" (%d: %s)", n, why.c_str());
    std::printf("\n");
    if (!o.json.empty()) {
      nlohmann::json s = nlohmann::json::object();
      for (const auto& [why, n] : skipped) s[why] = n;
      std::ofstream f(o.json);
      f << nlohmann::json{{"scene", o.scene}, {"checked", checked}, {"wrong", wrong},
                          {"occt_above", occt_above}, {"max_occt_above", max_occt_above},
                          {"max_row_above", max_row_above > -HUGE_VAL ? max_row_above : 0.0},
                          {"uncertified_above", uncertified_above},
                          {"skipped", s}, {"rows", rows}}
               .dump()
        << '\n';
    }
    return wrong == 0 ? 0 : 3;
  } catch (const Invalid_input& e) {
    std::cerr << "occt_crosscheck: " << e.what() << '\n';
    return 1;
  }
}
