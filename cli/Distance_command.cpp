// `extremal distance A B [--pose-a P] [--pose-b P] [--tolerance E] [--json] [--signed
// [--max-cells N]]`: one-shot certified extremal distance (../shared/CLI.md); with --signed, the
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

#include "algorithms/Global_distance.h"
#include "algorithms/Penetration_depth.h"
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

// The keys CLI.md specifies for `extremal distance --json`, shared by the plain and the signed
// result (same field names on both).
template <class Result>
nlohmann::json result_json(const Result& r, const std::string& name_a, const std::string& name_b,
                           double tolerance) {
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

// The certified solver's work counters (JSON "work").
nlohmann::json work_json(const Distance_result& r) {
  return {{"pairs", r.pairs_processed},
          {"nodes", r.nodes_created},
          {"newton_runs", r.newton_runs},
          {"intersection_attempts", r.intersection_attempts}};
}

// The first line of the readable answer: the distance and its certificate.
template <class Result>
void print_distance_line(const Result& r) {
  std::cout << std::setprecision(17);
  std::cout << "distance " << r.distance << "  (" << to_string(r.status) << ": " << r.lower_bound
            << " <= d <= " << r.upper_bound << ")\n";
}

struct Best {
  Distance_result result;
  std::size_t body_a = 0, body_b = 0;
  double lower = HUGE_VAL;  // smallest lower bound over all body pairs
  bool any = false;
  bool all_certified = true;
};

// --signed: the signed distance of every body pair; the smallest (the deepest penetration, or
// the closest pair when none overlaps) is reported, with the smallest lower bound of all.
int run_signed(const Distance_options& options, const std::vector<Body>& bodies_a,
               const std::vector<Body>& bodies_b, const std::vector<Distance_hierarchy>& ha,
               const std::vector<Distance_hierarchy>& hb, const std::vector<Rigid_pose_3>& poses_a,
               const std::vector<Rigid_pose_3>& poses_b) {
  Signed_distance_request request;
  request.absolute_tolerance = options.tolerance;
  request.relative_tolerance = 0.0;
  if (options.max_cells > 0) request.max_cells = options.max_cells;
  request.max_seconds = 60.0;
  request.apart.max_seconds = 60.0;
  Signed_distance_result best;
  std::size_t best_a = 0, best_b = 0;
  double lower = HUGE_VAL;
  bool any = false, all_certified = true;
  for (std::size_t i = 0; i < ha.size(); ++i)
    for (std::size_t j = 0; j < hb.size(); ++j) {
      const Signed_distance_result r =
          signed_distance(bodies_a[i], ha[i], poses_a[i], bodies_b[j], hb[j], poses_b[j], request);
      lower = std::min(lower, r.lower_bound);
      all_certified = all_certified && r.is_certified();
      if (!any || r.upper_bound < best.upper_bound) {
        best = r;
        best_a = i;
        best_b = j;
        any = true;
      }
    }
  Signed_distance_result& r = best;
  r.lower_bound = std::min(r.lower_bound, lower);
  // The sets' distance lies in [the smallest lower bound, the best upper bound]: a pair that ran
  // out of budget leaves it uncertified only when its lower bound opens that gap.
  if (!all_certified && r.is_certified() && r.upper_bound - r.lower_bound > r.tolerance_used)
    r.status = Signed_distance_status::Budget_exhausted;
  const bool overlapping = r.overlap != Overlap_kind::None;

  nlohmann::json j =
      result_json(r, bodies_a[best_a].name, bodies_b[best_b].name, options.tolerance);
  j["overlap"] = to_string(r.overlap);
  // What -distance measures while overlapping: the minimum translation distance (both bodies
  // certified convex) or the depth of the convex hulls (an upper bound on it).
  if (overlapping) j["depth"] = r.depth_is_translation_distance ? "translation" : "hull";
  j["closed_a"] = {{"closed", r.closed_a.closed}, {"reason", r.closed_a.reason}};
  j["closed_b"] = {{"closed", r.closed_b.closed}, {"reason", r.closed_b.reason}};
  j["work"] = work_json(r.apart);
  j["work"]["direction_cells"] = r.cells;
  j["work"]["supports"] = r.supports;
  j["work"]["winding_cells"] = r.winding_cells;
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
  std::cout << "point_a " << r.point_a.transpose() << "  on " << bodies_a[best_a].name << "\n";
  std::cout << "point_b " << r.point_b.transpose() << "  on " << bodies_b[best_b].name << "\n";
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
    // World pose of each body: the argument's pose after the body's placement in its file.
    std::vector<Rigid_pose_3> poses_a, poses_b;
    for (const Body& b : bodies_a) poses_a.push_back(X_WA * b.placement);
    for (const Body& b : bodies_b) poses_b.push_back(X_WB * b.placement);

    if (options.signed_distance)
      return run_signed(options, bodies_a, bodies_b, ha, hb, poses_a, poses_b);

    Distance_request request;
    request.absolute_tolerance = options.tolerance;  // CLI.md: d within the tolerance
    request.relative_tolerance = 0.0;
    request.max_seconds = 60.0;
    Distance_workspace ws;
    Best best;
    // Files of several bodies (assemblies): the body pairs nearest by their boxes first, each
    // query cut off at the best distance so far, and pairs whose boxes are already that far
    // apart not queried (their box distance is their lower bound). The distance is the one the
    // full loop gives; of pairs at exactly the same distance the one queried first is reported
    // (the cutoff prunes the others), which for bodies that meet (box distance 0, the sort
    // stable) is the first in file order.
    struct Body_pair {
      double box_gap;
      std::size_t a, b;
    };
    std::vector<Body_pair> order;
    for (std::size_t i = 0; i < ha.size(); ++i)
      for (std::size_t j = 0; j < hb.size(); ++j)
        order.push_back({box_distance(transformed(ha[i].box(), poses_a[i]),
                                      transformed(hb[j].box(), poses_b[j])),
                         i, j});
    std::stable_sort(order.begin(), order.end(),
                     [](const Body_pair& x, const Body_pair& y) { return x.box_gap < y.box_gap; });
    for (const Body_pair& pair : order) {
      const std::size_t i = pair.a, j = pair.b;
      if (best.any && pair.box_gap >= best.result.upper_bound) {
        best.lower = std::min(best.lower, pair.box_gap);
        continue;
      }
      Distance_request cut = request;
      if (best.any) cut.cutoff = best.result.upper_bound;
      const Distance_result r = extremal_distance(ha[i], poses_a[i], hb[j], poses_b[j], cut, ws);
      best.lower = std::min(best.lower, r.lower_bound);
      best.all_certified = best.all_certified && r.is_certified();
      if (r.element_a < 0) continue;  // nothing below the cutoff
      if (!best.any || r.upper_bound < best.result.upper_bound) {
        best.result = r;
        best.body_a = i;
        best.body_b = j;
        best.any = true;
      }
    }
    Distance_result r = best.result;
    r.lower_bound = std::min(r.lower_bound, best.lower);
    // As in run_signed: bodies that meet (upper bound 0) are certified whatever the other pairs.
    if (!best.all_certified && r.is_certified() && r.upper_bound - r.lower_bound > r.tolerance_used)
      r.status = Distance_status::Budget_exhausted;

    nlohmann::json j = result_json(r, bodies_a[best.body_a].name, bodies_b[best.body_b].name,
                                   options.tolerance);
    j["work"] = work_json(r);
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
    std::cout << "point_a " << r.point_a.transpose() << "  on " << bodies_a[best.body_a].name
              << " " << where(r.kind_a, r.element_a, r.params_a) << "\n";
    std::cout << "point_b " << r.point_b.transpose() << "  on " << bodies_b[best.body_b].name
              << " " << where(r.kind_b, r.element_b, r.params_b) << "\n";
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
