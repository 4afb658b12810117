// `extremal info TARGET [--json]`: what a file or shape spec holds.
#include <iostream>
#include <map>

#include <nlohmann/json.hpp>

#include "cli/Commands.h"
#include "io/Shape_spec.h"
#include "kernel/Error.h"

namespace extremal::cli {

namespace {

nlohmann::json bbox_json(const Bbox_3& b) {
  return {b.xmin(), b.ymin(), b.zmin(), b.xmax(), b.ymax(), b.zmax()};
}

nlohmann::json body_json(const Body& body) {
  nlohmann::json j;
  j["name"] = body.name;
  j["faces"] = body.faces.size();
  j["curves"] = body.curves.size();
  j["is_point"] = body.is_point;
  j["bbox"] = bbox_json(body.hull_bbox());
  std::map<std::string, int> kinds;
  for (const auto& f : body.faces) ++kinds[f.kind];
  j["surfaces"] = kinds;
  nlohmann::json faces = nlohmann::json::array();
  for (std::size_t i = 0; i < body.faces.size(); ++i) {
    const Nurbs_surface_3& s = body.faces[i].surface;
    faces.push_back({{"index", i},
                     {"kind", body.faces[i].kind},
                     {"degree", {s.degree_u(), s.degree_v()}},
                     {"poles", {s.number_of_poles_u(), s.number_of_poles_v()}},
                     {"rational", s.is_rational()},
                     {"closed", {s.is_closed_u(), s.is_closed_v()}},
                     {"domain", {s.u_min(), s.u_max(), s.v_min(), s.v_max()}},
                     {"bbox", bbox_json(s.hull_bbox())}});
  }
  j["face_list"] = faces;
  return j;
}

void print_text(const nlohmann::json& info) {
  std::cout << info["file"].get<std::string>() << " (units " << info["units"].get<std::string>()
            << "): " << info["bodies"].size() << " bod" << (info["bodies"].size() == 1 ? "y" : "ies")
            << "\n";
  for (const auto& b : info["bodies"]) {
    std::cout << "  body '" << b["name"].get<std::string>() << "': " << b["faces"] << " faces";
    if (b["is_point"].get<bool>()) std::cout << " (a point)";
    std::cout << ", bbox " << b["bbox"].dump() << "\n";
    for (const auto& f : b["face_list"])
      std::cout << "    face " << f["index"] << ": " << f["kind"].get<std::string>()
                << ", degree " << f["degree"][0] << "x" << f["degree"][1] << ", poles "
                << f["poles"][0] << "x" << f["poles"][1]
                << (f["rational"].get<bool>() ? ", rational" : ", polynomial")
                << (f["closed"][0].get<bool>() ? ", closed in u" : "")
                << (f["closed"][1].get<bool>() ? ", closed in v" : "") << "\n";
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
    if (!io::is_shape_spec(options.target))
      throw Invalid_input(options.target + ": cannot open file (CAD import is not built yet)");
    info["bodies"] = nlohmann::json::array({body_json(io::parse_shape_spec(options.target))});
    if (options.json)
      std::cout << info.dump(2) << "\n";
    else
      print_text(info);
    return 0;
  } catch (const Invalid_input& e) {
    std::cerr << "extremal info: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace extremal::cli
