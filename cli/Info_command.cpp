// `extremal info TARGET [--json]`: what a file or shape spec holds.
#include <algorithm>
#include <iostream>
#include <map>

#include <nlohmann/json.hpp>

#include "cli/Commands.h"
#include "algorithms/mesh/Mesh_bvh.h"
#include "io/Model_reader.h"
#include "io/Shape_spec.h"
#include "kernel/Error.h"

namespace extremal::cli {

namespace {

nlohmann::json bbox_json(const Bbox_3& b) {
  return {b.xmin(), b.ymin(), b.zmin(), b.xmax(), b.ymax(), b.zmax()};
}

nlohmann::json pose_json(const Rigid_pose_3& X) {
  const Eigen::Quaterniond q = X.quaternion();
  const Vec3& t = X.translation();
  return {{"position", {t.x(), t.y(), t.z()}}, {"quaternion", {q.w(), q.x(), q.y(), q.z()}}};
}

nlohmann::json body_json(const Body& body, nlohmann::json& warnings) {
  nlohmann::json j;
  j["name"] = body.name;
  if (!body.source_name.empty()) j["source_name"] = body.source_name;
  j["faces"] = body.faces.size();
  j["curves"] = body.curves.size();
  j["is_point"] = body.is_point;
  // In the file frame: the body placed by its placement.
  j["bbox"] = bbox_json(body.trimmed_bbox(body.placement));
  j["placement"] = pose_json(body.placement);
  std::map<std::string, int> kinds;
  std::map<std::string, int> degrees;
  int loops = 0, holes = 0, trim_curves = 0, trimmed_faces = 0, rational = 0;
  double approx = 0.0;
  for (const auto& f : body.faces) {
    ++kinds[f.kind];
    ++degrees[std::to_string(f.surface.degree_u()) + "x" + std::to_string(f.surface.degree_v())];
    if (f.surface.is_rational()) ++rational;
    if (!f.trims.empty()) ++trimmed_faces;
    for (const auto& l : f.trims) {
      ++loops;
      if (!l.is_outer) ++holes;
      trim_curves += static_cast<int>(l.curves.size());
    }
    approx = std::max(approx, f.approximation_error);
  }
  j["surfaces"] = kinds;
  j["degrees"] = degrees;
  j["rational_faces"] = rational;
  j["approximation_error"] = approx;
  j["trims"] = {{"trimmed_faces", trimmed_faces},
                {"loops", loops},
                {"holes", holes},
                {"curves", trim_curves}};
  int manifold = 0, free_edges = 0, seams = 0, non_manifold = 0, degenerate = 0, same_param = 0;
  int no_curve = 0;
  for (const auto& e : body.edges) {
    if (e.degenerate) ++degenerate;
    if (!e.curve && !e.degenerate) ++no_curve;
    if (e.same_parameter) ++same_param;
    if (e.uses.size() == 1) ++free_edges;
    if (e.uses.size() > 2) ++non_manifold;
    if (e.uses.size() == 2) {
      if (e.uses[0].face == e.uses[1].face)
        ++seams;
      else
        ++manifold;
    }
  }
  j["adjacency"] = {{"edges", body.edges.size()},  {"shared", manifold},
                    {"seams", seams},              {"free", free_edges},
                    {"non_manifold", non_manifold}, {"degenerate", degenerate},
                    {"without_3d_curve", no_curve}, {"same_parameter", same_param}};
  if (!body.mesh.empty()) {
    // A mesh that does not enclose a volume (or whose triangles turn both ways) is a sheet:
    // its distances have no sign (docs/behaviour.md, "Meshes").
    const Mesh_bvh hierarchy(body.mesh, body.name);
    j["mesh"] = {{"vertices", body.mesh.vertices.size()},
                 {"triangles", body.mesh.triangles.size()},
                 {"closed", hierarchy.closed()}};
    if (!hierarchy.closed())
      warnings.push_back("mesh '" + body.name + "' is not closed: " + hierarchy.closedness_reason() +
                         "; treated as open (distances unsigned)");
  }
  nlohmann::json faces = nlohmann::json::array();
  for (std::size_t i = 0; i < body.faces.size(); ++i) {
    const Face& f = body.faces[i];
    const Nurbs_surface_3& s = f.surface;
    int nl = static_cast<int>(f.trims.size()), nc = 0;
    for (const auto& l : f.trims) nc += static_cast<int>(l.curves.size());
    nlohmann::json fj = {{"index", i},
                         {"kind", f.kind},
                         {"degree", {s.degree_u(), s.degree_v()}},
                         {"poles", {s.number_of_poles_u(), s.number_of_poles_v()}},
                         {"rational", s.is_rational()},
                         {"closed", {s.is_closed_u(), s.is_closed_v()}},
                         {"domain", {s.u_min(), s.u_max(), s.v_min(), s.v_max()}},
                         {"outward_sign", s.outward_sign()},
                         {"trim_loops", nl},
                         {"trim_curves", nc},
                         {"bbox", bbox_json(s.hull_bbox())}};
    if (f.approximation_error > 0.0) fj["approximation_error"] = f.approximation_error;
    if (!f.source.empty()) fj["source"] = f.source;
    faces.push_back(fj);
  }
  j["face_list"] = faces;
  return j;
}

void print_text(const nlohmann::json& info) {
  std::cout << info["file"].get<std::string>();
  if (info.contains("format")) std::cout << " [" << info["format"].get<std::string>() << "]";
  std::cout << " (units " << info["units"].get<std::string>();
  if (info.contains("file_unit"))
    std::cout << "; file: " << info["file_unit"].get<std::string>();
  std::cout << "): " << info["bodies"].size() << " bod"
            << (info["bodies"].size() == 1 ? "y" : "ies") << "\n";
  for (const auto& b : info["bodies"]) {
    std::cout << "  body '" << b["name"].get<std::string>() << "': " << b["faces"] << " faces";
    if (b["is_point"].get<bool>()) std::cout << " (a point)";
    if (b.contains("mesh"))
      std::cout << ", mesh " << b["mesh"]["triangles"] << " triangles"
                << (b["mesh"]["closed"].get<bool>() ? " (closed)" : " (open)");
    std::cout << ", bbox " << b["bbox"].dump() << "\n";
    if (b["faces"].get<int>() > 0) {
      std::cout << "    surfaces " << b["surfaces"].dump() << ", degrees " << b["degrees"].dump()
                << "\n    trims " << b["trims"].dump() << "\n    adjacency "
                << b["adjacency"].dump() << "\n";
      if (b["approximation_error"].get<double>() > 0.0)
        std::cout << "    approximated faces: largest deviation " << b["approximation_error"]
                  << "\n";
    }
    for (const auto& f : b["face_list"])
      std::cout << "    face " << f["index"] << ": " << f["kind"].get<std::string>()
                << ", degree " << f["degree"][0] << "x" << f["degree"][1] << ", poles "
                << f["poles"][0] << "x" << f["poles"][1]
                << (f["rational"].get<bool>() ? ", rational" : ", polynomial")
                << (f["closed"][0].get<bool>() ? ", closed in u" : "")
                << (f["closed"][1].get<bool>() ? ", closed in v" : "") << ", "
                << f["trim_loops"] << " trim loops\n";
  }
  for (const auto& w : info["warnings"]) std::cout << "  warning: " << w.get<std::string>() << "\n";
}

}  // namespace

int run_info(const Info_options& options) {
  try {
    nlohmann::json info;
    info["file"] = options.target;
    info["units"] = "mm";
    info["warnings"] = nlohmann::json::array();
    nlohmann::json bodies = nlohmann::json::array();
    if (io::is_shape_spec(options.target)) {
      bodies.push_back(body_json(io::parse_shape_spec(options.target), info["warnings"]));
    } else {
      const io::Model model = io::read_model(options.target);
      info["units"] = model.unit;
      info["format"] = model.format_name;
      info["file_unit"] = model.file_unit;
      for (const auto& b : model.bodies) bodies.push_back(body_json(b, info["warnings"]));
      nlohmann::json skipped = nlohmann::json::array();
      for (const auto& s : model.skipped) {
        skipped.push_back({{"entity", s.entity}, {"reason", s.reason}, {"action", s.action}});
        info["warnings"].push_back(s.entity + ": " + s.reason + " (" + s.action + ")");
      }
      for (const auto& w : model.warnings) info["warnings"].push_back(w);
      info["skipped"] = skipped;
    }
    info["bodies"] = bodies;
    if (options.json)
      std::cout << info.dump(2) << "\n";
    else
      print_text(info);
    return 0;
  } catch (const Invalid_input& e) {
    std::cerr << "extremal info: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {  // anything unforeseen still exits 1 with a message
    std::cerr << "extremal info: internal error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace extremal::cli
