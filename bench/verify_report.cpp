// verify_report: runs a scene as `extremal report` does and checks its rows against the
// certified one-shot signed distance (`extremal distance --signed`) at the same poses, so that a
// claim about a scene's accuracy is one command anyone can rerun.
//
//   ./build/bench/verify_report SCENE.json... [--every N] [--tolerance E] [--seconds S]
//
// Every Nth step of every watched pair (and the last) is checked. Per row, against the
// reference s (certified, lower <= s <= upper):
//   - apart (the reference finds the bodies apart): error = |reported - s|, counted wrong when
//     it exceeds the tolerance plus the reference's own bound width plus the bodies' largest
//     edge tolerances (a file whose edges lie off their faces by that much is read on either);
//     a row reading them overlapping (below minus that allowance) is a wrong sign. Open sheets
//     too: apart, an open sheet has no inside, and its row is the distance, positive;
//   - overlapping: a row reading the bodies apart is a wrong sign. The depth is checked where a
//     reference depth is known, first that applies (README, "Distances, contact and
//     penetration"):
//       closed form: two balls (`sphere` shapes), |c_A - c_B| - r_A - r_B; a `sphere` or
//         `ellipsoid` shape through a `plane` shape (an open sheet): the depth of the side it
//         entered by, c - h or -(c + h), c its centre's height over the plane, h its support
//         along the plane's normal;
//       convex: both bodies certified convex (is_certified_convex): the reference is the
//         minimum translation distance, and the row must lie within its certified bounds; the
//         same for two closed meshes, whose rows read their hulls' depth by definition;
//       a sheet's plane: any other solid through a `plane` shape: the entry side's depth, the
//         solid's support along the plane's normal (certified support bounds);
//     the entry side is the side the solid was on (clear of the plane) when last apart, followed
//     at every step. Otherwise only the sign is checked, counted by why: the hulls' depth (non-
//     convex bodies, or a sheet that is no `plane` shape), the solid across the plane sheet's
//     border (its box not within the sheet), or no entry side (overlapping since the start);
//   - a `farther` row's distance is a lower bound: wrong when above the reference's upper bound;
//   - a NaN or infinite distance is always wrong; uncertified references are counted, not judged.
// A depth is off when it is farther from the reference depth than the tolerance (relative to
// the depth above 1) plus the reference's bound width plus the edge tolerances.
// Prints one line per pair and, with --rows, one per wrong row. Exit code 0 when no row is wrong,
// 3 when some is, 1 on bad input.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "algorithms/distance/Distance_hierarchy.h"
#include "algorithms/distance/Penetration_depth.h"
#include "algorithms/distance/Solid_classification.h"
#include "algorithms/mesh/Mesh_bvh.h"
#include "algorithms/scene/Scene_setup.h"
#include "io/Model_reader.h"
#include "io/Scene.h"
#include "kernel/Error.h"

namespace {

using namespace extremal;
using io::Scene_body;

struct Pair_tally {
  int rows = 0, apart = 0, overlapping = 0, farther = 0, unjudged = 0;
  // Overlapping rows checked against a depth, by its source, and the ones checked only for
  // their sign, by why.
  int closed_form_rows = 0, convex_rows = 0, sheet_plane_rows = 0;
  int hull_depth_rows = 0, other_sheet_rows = 0, sheet_border_rows = 0, no_entry_side_rows = 0;
  int wrong = 0, wrong_sign = 0, wrong_depth = 0, not_finite = 0;
  double max_apart_error = 0.0, t_max_apart_error = 0.0;
  double max_depth_error = 0.0, t_max_depth_error = 0.0;  // over the rows checked for a depth
  double reference_seconds = 0.0;
  int depth_rows() const { return closed_form_rows + convex_rows + sheet_plane_rows; }
  int sign_rows() const {
    return hull_depth_rows + other_sheet_rows + sheet_border_rows + no_entry_side_rows;
  }
};

// What a scene entry's shape spec says (Scene_body::source is its JSON for shapes).
struct Shape {
  enum Kind { Other, Sphere, Ellipsoid, Plane } kind = Other;
  Vec3 axes = Vec3::Zero();   // sphere: the radius thrice; ellipsoid: its semi-axes
  double w = 0.0, h = 0.0;    // plane: z = 0 in its frame, [-w/2, w/2] x [-h/2, h/2], normal +z
};

Shape shape_of(const io::Scene_body& b) {
  Shape s;
  if (!nlohmann::json::accept(b.source)) return s;
  const nlohmann::json j = nlohmann::json::parse(b.source);
  if (!j.is_object() || !j.contains("type")) return s;
  const std::string type = j["type"].get<std::string>();
  if (type == "sphere") {
    s.kind = Shape::Sphere;
    s.axes = Vec3::Constant(j["radius"].get<double>());
  } else if (type == "ellipsoid") {
    s.kind = Shape::Ellipsoid;
    s.axes = Vec3(j["axes"][0].get<double>(), j["axes"][1].get<double>(), j["axes"][2].get<double>());
  } else if (type == "plane") {
    s.kind = Shape::Plane;
    s.w = j["size"][0].get<double>();
    s.h = j["size"][1].get<double>();
  }
  return s;
}

// A solid (body `solid`) against a `plane` shape (body `plane`): where the solid lies along the
// plane's normal, followed at every step for the side it entered by.
struct Sheet_pair {
  int plane = -1, solid = -1;
  int side = 0;  // +1 above the plane (its normal's side), -1 below, 0 not known
};

// The solid's extent along the plane's normal n (heights over the plane: low <= high), with
// certified bounds [low_lo, low_hi], [high_lo, high_hi]; closed form for a sphere or ellipsoid
// (its bounds exact).
struct Extent {
  double low_lo = 0, low_hi = 0, high_lo = 0, high_hi = 0;
};
struct Options {
  std::vector<std::string> scenes;
  int every = 10;
  double tolerance = 1e-6;
  double seconds = 30.0;
  bool rows = false;
};

// The largest edge tolerance of a body (the file's, raised to the measured gap between an
// edge's curve and its faces): its faces and edges disagree by up to this, and a minimum on a
// face's side may be read on either.
double edge_tolerance(const Body& body) {
  double t = 0.0;
  for (const Edge& e : body.edges) t = std::max(t, e.tolerance);
  return t;
}

// The reference depth of an overlapping row where one is known (see the top), and where it
// comes from; `kind` Depth::None with `why` the reason otherwise.
struct Depth {
  enum Kind { None, Closed_form, Convex, Sheet_plane } kind = None;
  enum Why { Hull, Other_sheet, Border, No_side } why = Hull;
  double value = 0.0, lower = 0.0, upper = 0.0;  // certified: lower <= value <= upper
};

// The world pose of a scene body at t (its entry's pose times its placement in its file).
Rigid_pose_3 pose_of(const io::Scene_body& b, double t) { return b.motion.pose_at(t) * b.body.placement; }

// The extent of `solid` along unit world n over the plane through p0 (normal n).
Extent extent_along(const Shape& shape, const Distance_hierarchy& H, const Rigid_pose_3& X,
                    const Vec3& n, const Vec3& p0) {
  Extent e;
  const double c = n.dot(X.translation() - p0);
  if (shape.kind == Shape::Sphere || shape.kind == Shape::Ellipsoid) {
    // h(n) = |D R^T n| about the centre.
    const double h = (shape.axes.asDiagonal() * (X.rotation().transpose() * n)).norm();
    e.low_lo = e.low_hi = c - h;
    e.high_lo = e.high_hi = c + h;
    return e;
  }
  const Support_bound up = support_bound(H, X, n), down = support_bound(H, X, -n);
  const double o = n.dot(p0);
  e.high_lo = up.lower - o;
  e.high_hi = up.upper - o;
  e.low_lo = -down.upper - o;
  e.low_hi = -down.lower - o;
  return e;
}

// Whether the solid's world box, projected on the plane (frame X_P), lies within the sheet.
bool within_sheet(const Shape& plane, const Rigid_pose_3& X_P, const Bbox_3& world_box) {
  for (int k = 0; k < 8; ++k) {
    const Vec3 corner((k & 1) ? world_box.xmax() : world_box.xmin(),
                      (k & 2) ? world_box.ymax() : world_box.ymin(),
                      (k & 4) ? world_box.zmax() : world_box.zmin());
    const Vec3 q = X_P.inverse().apply_point(corner);
    if (std::abs(q.x()) > 0.5 * plane.w || std::abs(q.y()) > 0.5 * plane.h) return false;
  }
  return true;
}

void judge_row(const Options& o, const io::Scene& scene, int k, double t, const Pair_report& r,
               const Signed_distance_result& ref, const Depth& depth, double model_tolerance,
               Pair_tally& tally) {
  const auto& [ia, ib] = scene.pairs[k];
  const std::string who = scene.bodies[ia].name + " - " + scene.bodies[ib].name;
  auto wrong = [&](const char* what, double expected, double lower, double upper) {
    ++tally.wrong;
    if (o.rows)
      std::printf(
          "  t = %.9g %s: %s: reported %.12g (%s, faces %d %d), reference %.12g in [%.12g, "
          "%.12g] (%s, %s, %s %d, %s %d)\n",
          t, who.c_str(), what, r.distance, to_string(r.status), r.feature_a, r.feature_b,
          expected, lower, upper, to_string(ref.status), to_string(ref.overlap),
          to_string(ref.kind_a), ref.element_a, to_string(ref.kind_b), ref.element_b);
  };
  ++tally.rows;
  if (!std::isfinite(r.distance)) {
    ++tally.not_finite;
    wrong("not finite", ref.distance, ref.lower_bound, ref.upper_bound);
    return;
  }
  if (r.status == Pair_status::Farther) {  // beyond the threshold: a bound
    ++tally.farther;
    if (ref.is_certified() && r.distance > ref.upper_bound + o.tolerance)
      wrong("farther bound above the distance", ref.distance, ref.lower_bound, ref.upper_bound);
    return;
  }
  if (!ref.is_certified()) {
    ++tally.unjudged;
    return;
  }
  const double width = ref.upper_bound - ref.lower_bound;
  const double allowed =
      o.tolerance * std::max(1.0, std::abs(ref.distance)) + width + model_tolerance;
  if (ref.overlap == Overlap_kind::None) {
    ++tally.apart;
    const double e = std::abs(r.distance - ref.distance);
    if (e > tally.max_apart_error) {
      tally.max_apart_error = e;
      tally.t_max_apart_error = t;
    }
    if (r.distance < -allowed) {
      ++tally.wrong_sign;
      wrong("apart, read overlapping", ref.distance, ref.lower_bound, ref.upper_bound);
    } else if (e > allowed) {
      wrong("apart, off", ref.distance, ref.lower_bound, ref.upper_bound);
    }
    return;
  }
  ++tally.overlapping;
  if (r.distance > allowed) {
    ++tally.wrong_sign;
    wrong("overlapping, read apart", ref.distance, ref.lower_bound, ref.upper_bound);
    return;
  }
  if (depth.kind == Depth::None) {
    ++(depth.why == Depth::Border        ? tally.sheet_border_rows
       : depth.why == Depth::No_side     ? tally.no_entry_side_rows
       : depth.why == Depth::Other_sheet ? tally.other_sheet_rows
                                         : tally.hull_depth_rows);
    return;
  }
  static const char* const what[] = {"", "closed-form depth, off", "convex depth, off",
                                     "entry-side depth (sheet's plane), off"};
  ++(depth.kind == Depth::Closed_form ? tally.closed_form_rows
     : depth.kind == Depth::Convex    ? tally.convex_rows
                                      : tally.sheet_plane_rows);
  // Outside [lower, upper] by more than the tolerance (and the edge tolerances).
  const double slack = o.tolerance * std::max(1.0, std::abs(depth.value)) + model_tolerance;
  const double e = std::max({0.0, depth.lower - r.distance, r.distance - depth.upper});
  const double off = std::abs(r.distance - depth.value);
  if (off > tally.max_depth_error) {
    tally.max_depth_error = off;
    tally.t_max_depth_error = t;
  }
  if (e > slack) {
    ++tally.wrong_depth;
    wrong(what[depth.kind], depth.value, depth.lower, depth.upper);
  }
}

int verify(const Options& o, const std::string& path) {
  const io::Scene scene = io::read_scene(path, io::load_bodies);
  std::vector<std::unique_ptr<Distance_hierarchy>> hierarchies(scene.bodies.size());
  auto hierarchy = [&](int i) -> const Distance_hierarchy& {
    if (!hierarchies[i]) hierarchies[i] = std::make_unique<Distance_hierarchy>(scene.bodies[i].body);
    return *hierarchies[i];
  };
  std::vector<double> edge_tolerances;
  std::vector<Shape> shapes;
  std::vector<bool> convex, closed, closed_mesh;
  for (const Scene_body& b : scene.bodies) {
    closed_mesh.push_back(!b.body.mesh.empty() && b.body.faces.empty() && b.body.curves.empty() &&
                          Mesh_bvh(b.body.mesh, b.body.name).closed());
    edge_tolerances.push_back(edge_tolerance(b.body));
    shapes.push_back(shape_of(b));
    convex.push_back(is_certified_convex(b.body));
    closed.push_back(body_closedness(b.body).closed);
  }
  Signed_distance_request request;
  request.total_seconds = o.seconds;

  // Solids against `plane` shapes, by pair.
  std::vector<Sheet_pair> sheet_pairs(scene.pairs.size());
  for (std::size_t k = 0; k < scene.pairs.size(); ++k) {
    const auto& [ia, ib] = scene.pairs[k];
    for (const auto& [p, q] : {std::make_pair(ia, ib), std::make_pair(ib, ia)})
      if (shapes[p].kind == Shape::Plane && closed[q]) sheet_pairs[k] = {p, q, 0};
  }
  // A sheet pair's extent at t, and whether the solid is within the sheet.
  auto sheet_extent = [&](const Sheet_pair& sp, double t, bool& within) {
    const Rigid_pose_3 X_P = pose_of(scene.bodies[sp.plane], t);
    const Rigid_pose_3 X_S = pose_of(scene.bodies[sp.solid], t);
    const Vec3 n = X_P.rotation().col(2);
    within = within_sheet(shapes[sp.plane], X_P, transformed(hierarchy(sp.solid).box(), X_S));
    return extent_along(shapes[sp.solid], hierarchy(sp.solid), X_S, n, X_P.translation());
  };
  // The reference depth of pair k at t (overlapping rows), see the top.
  auto reference_depth = [&](int k, double t, const Signed_distance_result& ref) {
    Depth d;
    const auto& [ia, ib] = scene.pairs[k];
    const Shape& sa = shapes[ia];
    const Shape& sb = shapes[ib];
    if (sa.kind == Shape::Sphere && sb.kind == Shape::Sphere) {
      d.kind = Depth::Closed_form;
      d.value = d.lower = d.upper =
          (pose_of(scene.bodies[ia], t).translation() - pose_of(scene.bodies[ib], t).translation())
              .norm() -
          sa.axes[0] - sb.axes[0];
      return d;
    }
    // Two closed meshes read their hulls' depth by definition (docs/behaviour.md, "Meshes"):
    // the reference itself.
    if (ref.depth_is_translation_distance || (closed_mesh[ia] && closed_mesh[ib])) {
      d.kind = Depth::Convex;
      d.value = ref.distance;
      d.lower = ref.lower_bound;
      d.upper = ref.upper_bound;
      return d;
    }
    const Sheet_pair& sp = sheet_pairs[k];
    if (sp.plane < 0) {
      // A sheet that is no `plane` shape: its entry side's depth is not known here.
      if (closed[ia] != closed[ib]) d.why = Depth::Other_sheet;
      return d;
    }
    bool within = false;
    const Extent e = sheet_extent(sp, t, within);
    if (!within) {
      d.why = Depth::Border;
      return d;
    }
    if (sp.side == 0) {
      d.why = Depth::No_side;
      return d;
    }
    const Shape::Kind solid = shapes[sp.solid].kind;
    d.kind = solid == Shape::Sphere || solid == Shape::Ellipsoid ? Depth::Closed_form
                                                                 : Depth::Sheet_plane;
    // Entered from above: its lowest point's height (below 0); from below: minus its highest's.
    d.lower = sp.side > 0 ? e.low_lo : -e.high_hi;
    d.upper = sp.side > 0 ? e.low_hi : -e.high_lo;
    d.value = 0.5 * (d.lower + d.upper);
    return d;
  };

  std::vector<Pair_tally> tallies(scene.pairs.size());
  const int steps = scene.step_count();
  double stepping = 0.0;
  const std::unique_ptr<Scene_stepper> run = scene_stepper(scene);
  auto clock = std::chrono::steady_clock::now();
  run_scene(scene, *run, [&](int step, double t, const std::vector<Pair_report>& reports) {
    stepping += std::chrono::duration<double>(std::chrono::steady_clock::now() - clock).count();
    const bool check = step % o.every == 0 || step == steps - 1;
    for (std::size_t k = 0; k < reports.size(); ++k) {
      const auto& [ia, ib] = scene.pairs[k];
      Sheet_pair& sp = sheet_pairs[k];
      const auto t0 = std::chrono::steady_clock::now();
      Depth depth;
      Signed_distance_result ref;
      if (check) {
        // The body frame sits at the entry's pose times the body's placement in its file.
        const Scene_body& A = scene.bodies[ia];
        const Scene_body& B = scene.bodies[ib];
        ref = signed_distance(A.body, hierarchy(ia), pose_of(A, t), B.body, hierarchy(ib),
                              pose_of(B, t), request);
        if (ref.is_certified() && ref.overlap != Overlap_kind::None)
          depth = reference_depth(static_cast<int>(k), t, ref);
      }
      // The side the solid entered a plane sheet by: the one it was on when last clear of the
      // plane (at every step); unknown once it straddles the plane off the sheet.
      if (sp.plane >= 0) {
        bool within = false;
        const Extent e = sheet_extent(sp, t, within);
        if (e.low_lo > 0.0) sp.side = 1;
        else if (e.high_hi < 0.0) sp.side = -1;
        else if (!within) sp.side = 0;
      }
      tallies[k].reference_seconds +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (check)
        judge_row(o, scene, static_cast<int>(k), t, reports[k], ref, depth,
                  edge_tolerances[ia] + edge_tolerances[ib], tallies[k]);
    }
    clock = std::chrono::steady_clock::now();
  });

  int wrong = 0;
  std::printf("%s: %d steps, stepping %.3g s (%.3g ms per step, all pairs)\n", path.c_str(), steps,
              stepping, 1e3 * stepping / std::max(1, steps));
  for (std::size_t k = 0; k < tallies.size(); ++k) {
    const Pair_tally& p = tallies[k];
    const auto& [ia, ib] = scene.pairs[k];
    std::printf(
        "  %s - %s: %d rows checked (%d apart, %d overlapping, %d farther, %d reference "
        "uncertified): %d wrong (%d wrong sign, %d wrong depth, %d not finite); overlapping rows "
        "checked against a depth %d (closed form %d, convex %d, sheet's plane %d), by sign only "
        "%d (hull depth %d, sheet no plane %d, across a sheet's border %d, no entry side %d); max "
        "apart error %.3g "
        "at t = %.9g; max depth error %.3g at t = %.9g; reference %.3g s\n",
        scene.bodies[ia].name.c_str(), scene.bodies[ib].name.c_str(), p.rows, p.apart,
        p.overlapping, p.farther, p.unjudged, p.wrong, p.wrong_sign, p.wrong_depth, p.not_finite,
        p.depth_rows(), p.closed_form_rows, p.convex_rows, p.sheet_plane_rows, p.sign_rows(),
        p.hull_depth_rows, p.other_sheet_rows, p.sheet_border_rows, p.no_entry_side_rows, p.max_apart_error,
        p.t_max_apart_error, p.max_depth_error, p.t_max_depth_error, p.reference_seconds);
    wrong += p.wrong;
  }
  return wrong;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"Checks a scene's report rows against the certified signed distance"};
  app.add_option("scenes", o.scenes, "Scene file(s)")->required();
  app.add_option("--every", o.every, "Check every Nth step (and the last)")
      ->check(CLI::PositiveNumber);
  app.add_option("--tolerance", o.tolerance,
                 "Allowed error, relative to max(1, |distance|), beyond the reference's width")
      ->check(CLI::PositiveNumber);
  app.add_option("--seconds", o.seconds, "Time limit of each reference query")
      ->check(CLI::PositiveNumber);
  app.add_flag("--rows", o.rows, "Print every wrong row");
  app.footer(
      "Rows are checked against the certified signed distance at the same poses. Apart: the\n"
      "distance, positive (open sheets too; a row read overlapping is a wrong sign). Overlapping: the sign, and the depth where one is known: a closed form (two\n"
      "`sphere` shapes; a `sphere` or `ellipsoid` shape through a `plane` shape, the depth of\n"
      "the side it entered by), the certified bounds of two certified convex bodies, or, for\n"
      "any other solid through a `plane` shape, the entry side's depth from the solid's support\n"
      "along the plane's normal. The entry side is the side the solid was on when last clear of\n"
      "the plane. Other overlapping rows (non-convex bodies: the hulls' depth; a sheet that is no\n"
      "`plane` shape; a solid across a plane sheet's border; overlapping since the start) are\n"
      "checked for their sign only and counted per pair. Exit code 3 when a row is wrong.");
  CLI11_PARSE(app, argc, argv);
  int wrong = 0;
  for (const std::string& path : o.scenes) {
    try {
      wrong += verify(o, path);
    } catch (const Invalid_input& e) {
      std::cerr << "verify_report: " << e.what() << '\n';
      return 1;
    }
  }
  return wrong == 0 ? 0 : 3;
}
