// `extremal distance A B [--pose-a P] [--pose-b P] [--tolerance E] [--json] [--signed
// [--max-cells N]]`: one-shot certified extremal distance (docs/cli.md); with --signed, the
// signed distance (negative penetration depth while the bodies overlap, Penetration_depth.h). A and B are shape specs or files (read_model: STEP, IGES,
// BREP, OBJ, meshes); a file that holds several bodies counts as the union of all its bodies (the
// JSON `body_a` / `body_b` names the body the witness lies on), each body placed by its file
// placement composed with --pose-a / --pose-b.
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "algorithms/distance/Global_distance.h"
#include "algorithms/distance/Penetration_depth.h"
#include "algorithms/distance/Set_distance.h"
#include "cli/Commands.h"
#include "io/Model_reader.h"
#include "io/Shape_spec.h"
#include "kernel/Error.h"

namespace extremal::cli {

namespace {

// The bodies an argument names.
std::vector<Body> load_bodies(const std::string& target, const char* which) {
  if (target.empty()) throw Invalid_input(std::string(which) + ": empty shape spec or file name");
  if (io::is_shape_spec(target)) {
    try {
      std::vector<Body> out;
      out.push_back(io::parse_shape_spec(target));
      return out;
    } catch (const Invalid_input& e) {
      throw Invalid_input(std::string(which) + " '" + target + "': " + e.what());
    }
  }
  io::Model model;
  try {
    // A tight trim band: points within the band count as on the face, and the trim boundary
    // edges only carry minima on the exact boundary, so the band bounds how far the certificate
    // can close near a boundary (1e-9 of each face's parameter extent).
    io::Read_options read;
    read.trim_tolerance = 1e-9;
    model = io::read_model(target, read);
  } catch (const Invalid_input& e) {
    throw Invalid_input(std::string(which) + " '" + target + "': " + e.what());
  } catch (const std::exception& e) {
    throw Invalid_input(std::string(which) + " '" + target + "': cannot read: " + e.what());
  }
  std::vector<Body> out;
  for (Body& b : model.bodies)
    if (!b.is_empty()) out.push_back(std::move(b));
  if (out.empty())
    throw Invalid_input(std::string(which) + " '" + target +
                        "': the file holds no body with a face, curve or triangle");
  return out;
}

Rigid_pose_3 load_pose(const std::string& text, const char* option) {
  if (text.empty()) return Rigid_pose_3();
  try {
    return io::parse_pose(text);
  } catch (const Invalid_input& e) {
    throw Invalid_input(std::string(option) + " '" + text + "': " + e.what());
  }
}

nlohmann::json vec_json(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

// The keys docs/cli.md specifies for `extremal distance --json`, shared by the plain and the
// signed result (same field names on both).
template <class Result>
nlohmann::json result_json(const Result& r, const nlohmann::json& name_a,
                           const nlohmann::json& name_b, double tolerance) {
  nlohmann::json j;
  j["distance"] = r.distance;
  j["lower_bound"] = r.lower_bound;
  j["upper_bound"] = r.upper_bound;
  j["point_a"] = vec_json(r.point_a);
  j["point_b"] = vec_json(r.point_b);
  j["normal"] = vec_json(r.normal);
  j["face_a"] = r.face_a;
  j["face_b"] = r.face_b;
  j["status"] = to_string(r.status);
  j["certified"] = r.is_certified();
  j["body_a"] = name_a;
  j["body_b"] = name_b;
  j["element_a"] = {{"kind", to_string(r.kind_a)}, {"index", r.element_a},
                    {"params", {r.params_a[0], r.params_a[1]}}};
  j["element_b"] = {{"kind", to_string(r.kind_b)}, {"index", r.element_b},
                    {"params", {r.params_b[0], r.params_b[1]}}};
  j["tolerance"] = tolerance;
  return j;
}

// The work of a query over the body pairs (JSON "work"): the certified solver's counters
// summed over the pairs queried, and how many pairs were queried or bounded by their boxes.
nlohmann::json work_json(const Set_work& w) {
  return {{"pairs", w.pairs_processed},
          {"nodes", w.nodes_created},
          {"newton_runs", w.newton_runs},
          {"intersection_attempts", w.intersection_attempts},
          {"body_pairs_queried", w.body_pairs_queried},
          {"body_pairs_bounded_by_boxes", w.body_pairs_bounded}};
}

// The name of the body at `index` of a set (null when no pair holds a witness).
nlohmann::json body_name(const std::vector<Placed_body>& set, int index) {
  if (index < 0) return nullptr;
  return set[static_cast<std::size_t>(index)].body->name;
}
std::string readable(const nlohmann::json& name) {
  return name.is_string() ? name.get<std::string>() : "no body (no witness)";
}

// The first line of the readable answer: the distance and its certificate.
template <class Result>
void print_distance_line(const Result& r) {
  std::cout << std::setprecision(17);
  std::cout << "distance " << r.distance << "  (" << to_string(r.status) << ": " << r.lower_bound
            << " <= d <= " << r.upper_bound << ")\n";
}

// The whole query's time: a file of many bodies gets this much in all, not per body pair.
constexpr double k_max_seconds = 60.0;

// --signed: the smallest signed distance over the body pairs (the deepest penetration, or the
// closest pair when none overlaps), with the smallest lower bound of all (Set_distance.h).
int run_signed(const Distance_options& options, const std::vector<Placed_body>& set_a,
               const std::vector<Placed_body>& set_b) {
  Signed_distance_request request;
  request.absolute_tolerance = options.tolerance;
  request.relative_tolerance = 0.0;
  if (options.max_cells > 0) request.max_cells = options.max_cells;
  const Signed_set_distance_result set = signed_set_distance(set_a, set_b, request, k_max_seconds);
  const Signed_distance_result& r = set.result;
  const nlohmann::json name_a = body_name(set_a, set.body_a), name_b = body_name(set_b, set.body_b);
  const bool overlapping = r.overlap != Overlap_kind::None;

  nlohmann::json j = result_json(r, name_a, name_b, options.tolerance);
  j["overlap"] = to_string(r.overlap);
  // What -distance measures while overlapping: the minimum translation distance (both bodies
  // certified convex) or the depth of the convex hulls (an upper bound on it).
  if (overlapping) j["depth"] = r.depth_is_translation_distance ? "translation" : "hull";
  j["closed_a"] = {{"closed", r.closed_a.closed}, {"reason", r.closed_a.reason}};
  j["closed_b"] = {{"closed", r.closed_b.closed}, {"reason", r.closed_b.reason}};
  j["work"] = work_json(set.work);
  j["work"]["direction_cells"] = set.work.cells;
  j["work"]["supports"] = set.work.supports;
  j["work"]["winding_cells"] = set.work.winding_cells;
  if (options.json) {
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  print_distance_line(r);
  if (overlapping)
    std::cout << "overlap " << to_string(r.overlap) << ", depth of the "
              << (r.depth_is_translation_distance ? "bodies (minimum translation distance)"
                                                  : "convex hulls")
              << "\n";
  std::cout << "point_a " << r.point_a.transpose() << "  on " << readable(name_a) << "\n";
  std::cout << "point_b " << r.point_b.transpose() << "  on " << readable(name_b) << "\n";
  std::cout << "normal  " << r.normal.transpose() << "\n";
  return 0;
}

}  // namespace

int run_distance(const Distance_options& options) {
  try {
    if (!(std::isfinite(options.tolerance) && options.tolerance > 0.0)) {
      std::ostringstream os;
      os << "--tolerance: must be finite and > 0, got " << options.tolerance;
      throw Invalid_input(os.str());
    }
    const std::vector<Body> bodies_a = load_bodies(options.a, "A");
    const std::vector<Body> bodies_b = load_bodies(options.b, "B");
    const Rigid_pose_3 X_WA = load_pose(options.pose_a, "--pose-a");
    const Rigid_pose_3 X_WB = load_pose(options.pose_b, "--pose-b");

    std::vector<Distance_hierarchy> ha, hb;
    auto build = [](const std::vector<Body>& bodies, std::vector<Distance_hierarchy>& h,
                    const std::string& target) {
      h.reserve(bodies.size());
      for (const Body& b : bodies) {
        try {
          h.emplace_back(b);
        } catch (const Invalid_input& e) {
          throw Invalid_input("'" + target + "': " + e.what());
        }
      }
    };
    build(bodies_a, ha, options.a);
    build(bodies_b, hb, options.b);
    // Each body placed by the argument's pose after its placement in its file.
    std::vector<Placed_body> set_a, set_b;
    for (std::size_t i = 0; i < bodies_a.size(); ++i)
      set_a.push_back({&bodies_a[i], &ha[i], X_WA * bodies_a[i].placement});
    for (std::size_t i = 0; i < bodies_b.size(); ++i)
      set_b.push_back({&bodies_b[i], &hb[i], X_WB * bodies_b[i].placement});

    if (options.signed_distance) return run_signed(options, set_a, set_b);

    Distance_request request;
    request.absolute_tolerance = options.tolerance;  // docs/cli.md: d within the tolerance
    request.relative_tolerance = 0.0;
    Distance_workspace ws;
    // Files of several bodies (assemblies): nearest body pairs first, each cut off at the best
    // so far (Set_distance.h).
    const Set_distance_result set = set_distance(set_a, set_b, request, ws, k_max_seconds);
    const Distance_result& r = set.result;
    const nlohmann::json name_a = body_name(set_a, set.body_a);
    const nlohmann::json name_b = body_name(set_b, set.body_b);

    nlohmann::json j = result_json(r, name_a, name_b, options.tolerance);
    j["work"] = work_json(set.work);
    if (options.json) {
      std::cout << j.dump(2) << "\n";
      return 0;
    }
    print_distance_line(r);
    auto where = [](Element_kind k, int index, const std::array<double, 2>& q) {
      std::ostringstream os;
      os << std::setprecision(17) << to_string(k);
      if (k != Element_kind::Point) os << " " << index << " at (" << q[0];
      if (k == Element_kind::Face) os << ", " << q[1];
      if (k != Element_kind::Point) os << ")";
      return os.str();
    };
    std::cout << "point_a " << r.point_a.transpose() << "  on " << readable(name_a) << " " << where(r.kind_a, r.element_a, r.params_a) << "\n";
    std::cout << "point_b " << r.point_b.transpose() << "  on " << readable(name_b) << " " << where(r.kind_b, r.element_b, r.params_b) << "\n";
    std::cout << "normal  " << r.normal.transpose() << "\n";
    return 0;
  } catch (const Invalid_input& e) {
    std::cerr << "extremal distance: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {  // Precondition_violation and anything unforeseen
    std::cerr << "extremal distance: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace extremal::cli
