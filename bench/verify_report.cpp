// verify_report: runs a scene as `extremal report` does and checks its rows against the
// certified one-shot signed distance (`extremal distance --signed`) at the same poses, and
// against evidence and references computed apart from it, so that a claim about a scene's
// accuracy is one command anyone can rerun (docs/checking.md).
//
//   ./build/bench/verify_report SCENE.json... [--every N | --at T] [--tolerance E] [--seconds S]
//                               [--rows] [--json OUT] [--doctor lower_bound|value|sign]
//
// Every Nth step of every watched pair (and the last) is checked, or the step nearest T. Each
// row goes through every check that applies to it; a row failing one is wrong, and each check
// counts the rows it judged and the ones it found wrong. With s the reference (certified,
// lower <= s <= upper), E the tolerance relative to max(1, |value|), w the reference's bound
// width, m the bodies' largest edge tolerances (a file whose edges lie off their faces by that
// much is read on either) and r a rounding slack (k_rounding_ulps epsilons of the scene's size
// and largest coordinate):
//   finite             the distance, lower bound, witnesses and normal are finite numbers;
//   lower_bound        a row's lower bound (apart and `farther` rows) is at most the
//                      reference's upper bound + m + r (overlapping, the upper bound of the
//                      surfaces' distance, 0 where they meet: a row read apart there is a
//                      wrong sign, below): no false certificate;
//   support_plane      the row is at least the separating-plane bound along its own normal n,
//                      s(n) = -(h_A(n) + h_B(-n)) from certified upper bounds on the support
//                      functions, - m - r (its witnesses on the bodies and point_b - point_a =
//                      d n give d >= s(n), apart or not); for apart rows also along the
//                      reference's normal (the true distance is at least s(n) for every n);
//   apart_sign, overlap_sign   the row's sign against evidence found here, not the
//                      reference's overlap flag: the surfaces meet (the reference's apart query
//                      found a common point) or a closed body contains a point of the other (the
//                      winding number of its surface about the other's witness of the apart
//                      query); a row reading them overlapping (below -(E + m)) with the surfaces
//                      certified apart and no containment is wrong, and so is one reading them
//                      apart (above E + m) against evidence of overlap;
//   reference_evidence that evidence and the reference's overlap flag agree (a disagreement is a
//                      defect of the one-shot solver or of the evidence, reported all the same);
//   apart_value        apart: |row - s| <= E + w + m (open sheets too: apart, a sheet has no
//                      inside, and its row is the distance, positive); a row reading
//                      `uncertified` promises a real pair of points only, row >= s - E - w - m
//                      (how far above it reads is counted per pair, not judged);
//   convex_value       two convex bodies (certified convex, or `sphere`, `ellipsoid`,
//                      `cylinder`, `point` shapes): apart, the row within the bounds of the
//                      support-function distance (hull_signed_distance, independent of the
//                      branch and bound of the apart query) +- E + m; overlapping, within the
//                      reference's, the minimum translation distance; also two closed meshes
//                      overlapping, whose rows read their hulls' depth by definition;
//   closed_form_depth  two balls (certified balls): |c_A - c_B| - r_A - r_B; a `sphere` or
//                      `ellipsoid` shape through a `plane` shape: the depth of the side it
//                      entered by, c - h or -(c + h), c its centre's height over the plane, h its
//                      support along the plane's normal;
//   ball_depth         a ball against a closed body or a point, overlapping: its centre's
//                      certified signed distance to the other body (minus its distance to the
//                      surface when inside), less the radius;
//   point_depth        a point inside a closed body: minus its certified distance to the
//                      surface;
//   sheet_plane_depth  another solid through a `plane` shape: the entry side's depth, the
//                      solid's certified support along the plane's normal;
//   (the entry side is the side the solid was on, clear of the plane, when last apart, followed
//   at every step.) A depth is off when outside its reference's bounds by more than E + m.
//   Other overlapping rows are checked for their sign only, counted by why: the hulls' depth
//   (non-convex bodies), a sheet that is no `plane` shape, a solid across a plane sheet's
//   border, or no entry side (overlapping since the start).
//   A `farther` row's distance, a lower bound, goes through lower_bound only. References that
//   are not certified are counted; their bounds still judge lower_bound and support_plane.
// Prints one line per pair and, with --rows, one per wrong row with a command that replays it.
// --json writes the counts, the wrong rows and the apart rows (for bench/occt_crosscheck).
// --doctor makes rows wrong before they are judged (the checks' self-test, see doctored()).
// Exit code 0 when no row is wrong, 3 when some is, 1 on bad input, 4 when a scene's run
// threw (a crash of the tracker, reported with the scene and step).
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
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
#include "kernel/Shapes.h"

namespace {

using namespace extremal;
using io::Scene_body;

constexpr double k_eps = std::numeric_limits<double>::epsilon();
// Rounding slack between two certified bounds computed in doubles from the same geometry placed
// in the world (a row's lower bound against the reference's upper bound, a row against a
// support bound): each places control points to half an ulp of the largest coordinate and
// sums a few products of them. The stress ladder measured excesses of up to 2 epsilons of the
// size and 0.6 of the largest coordinate (bench/experiments/Stress_ladder.cpp); 64 leaves room
// for longer chains of operations, and is still 1e-14 of the scene.
constexpr double k_rounding_ulps = 64.0;
// Sub-nets per support search of the separating-plane check: a search stopped short still
// gives a certified upper bound (a weaker check), and keeps the check's cost below the
// reference's on large parts.
constexpr int k_support_nets = 20000;

// ---- checks -------------------------------------------------------------------------------------

enum Check {
  Finite,
  Lower_bound,
  Support_plane,
  Apart_sign,
  Overlap_sign,
  Reference_evidence,
  Apart_value,
  Convex_value,
  Closed_form_depth,
  Ball_depth,
  Point_depth,
  Sheet_plane_depth,
  k_check_count
};
const char* const k_check_name[k_check_count] = {
    "finite",       "lower_bound",      "support_plane",     "apart_sign",
    "overlap_sign", "reference_evidence", "apart_value",     "convex_value",
    "closed_form_depth", "ball_depth",  "point_depth",       "sheet_plane_depth"};
// The kind of defect a failed check shows.
const char* const k_check_class[k_check_count] = {
    "NaN",         "false lower bound", "wrong value", "wrong sign",
    "wrong sign",  "reference disagrees with evidence", "wrong value", "wrong value",
    "wrong value", "wrong value",       "wrong value", "wrong value"};

struct Pair_tally {
  int rows = 0, apart = 0, overlapping = 0, farther = 0, unjudged = 0, wrong = 0;
  std::array<int, k_check_count> checked{}, failed{};
  // Overlapping rows checked for their sign only, by why; rows whose sign no evidence decided.
  int hull_depth_rows = 0, other_sheet_rows = 0, sheet_border_rows = 0, no_entry_side_rows = 0;
  int sign_undecided = 0;
  double max_apart_error = 0.0, t_max_apart_error = 0.0;
  // Apart rows reading `uncertified` (their distance a real pair's, its bound short of the
  // budget or none): judged for their value from below only; how far above the truth they read.
  int uncertified_rows = 0;
  double max_uncertified_excess = 0.0, t_max_uncertified_excess = 0.0;
  double max_depth_error = 0.0, t_max_depth_error = 0.0;  // over the rows checked for a depth
  // The largest amount a lower bound exceeds the reference's upper bound by (0 when none).
  double max_lower_bound_excess = 0.0;
  double reference_seconds = 0.0;
  int depth_rows() const {
    return checked[Closed_form_depth] + checked[Ball_depth] + checked[Point_depth] +
           checked[Sheet_plane_depth];
  }
  int sign_rows() const {
    return hull_depth_rows + other_sheet_rows + sheet_border_rows + no_entry_side_rows;
  }
};

// What a scene entry's shape spec says (Scene_body::source is its JSON for shapes).
struct Shape {
  enum Kind { Other, Sphere, Ellipsoid, Plane, Cylinder, Point } kind = Other;
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
  } else if (type == "cylinder") {
    s.kind = Shape::Cylinder;
  } else if (type == "point") {
    s.kind = Shape::Point;
  }
  return s;
}

// What the checks need to know of a scene body.
struct Body_info {
  Shape shape;
  bool closed = false, closed_mesh = false;
  // Convex: certified (a point, one untrimmed sphere or ellipsoid face) or a convex shape spec.
  bool convex = false;
  std::optional<Ball> ball;  // a certified ball
  double edge_tolerance = 0.0;
};

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
  std::optional<double> at;
  double tolerance = 1e-6;
  double seconds = 30.0;
  bool rows = false;
  std::string json;
  std::string doctor;  // empty: rows as read
};

// The largest edge tolerance of a body (the file's, raised to the measured gap between an
// edge's curve and its faces): its faces and edges disagree by up to this, and a minimum on a
// face's side may be read on either.
double edge_tolerance(const Body& body) {
  double t = 0.0;
  for (const Edge& e : body.edges) t = std::max(t, e.tolerance);
  return t;
}

// The reference depth of an overlapping row where one is known (see the top), the check that
// judges it; `check` k_check_count with `why` the reason otherwise.
struct Depth {
  Check check = k_check_count;
  enum Why { Hull, Other_sheet, Border, No_side } why = Hull;
  double value = 0.0, lower = 0.0, upper = 0.0;  // certified: lower <= value <= upper
};

// Whether the bodies overlap, from evidence: the surfaces meet (a common point), or a closed
// body contains a point of the other (a witness of the apart query, by the winding number).
enum class Evidence { Apart, Meet, Contains, Unknown };
const char* to_string(Evidence e) {
  switch (e) {
    case Evidence::Apart: return "apart";
    case Evidence::Meet: return "surfaces meet";
    case Evidence::Contains: return "contains";
    default: return "unknown";
  }
}

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

// The scene's size and largest coordinate at these poses (of the two bodies' world boxes),
// for the rounding slack.
double rounding_scale(const Bbox_3& a, const Bbox_3& b) {
  double c = 0.0;
  for (const Bbox_3* box : {&a, &b})
    for (int i = 0; i < 3; ++i)
      c = std::max({c, std::abs(box->min(i)), std::abs(box->max(i))});
  double size = 0.0;
  for (const Bbox_3* box : {&a, &b})
    size = std::max(size, std::sqrt(CGAL::square(box->xmax() - box->xmin()) +
                                    CGAL::square(box->ymax() - box->ymin()) +
                                    CGAL::square(box->zmax() - box->zmin())));
  return k_rounding_ulps * k_eps * (c + size);
}

std::string detail_of(const Pair_report& r) {
  if (!r.solved) return to_string(r.degeneracy);
  if (r.rejected_by == Reading_rule::None) return "solved";
  return std::string("solved: ") + to_string(r.rejected_by);
}

bool finite_row(const Pair_report& r) {
  return std::isfinite(r.distance) && (!r.lower_bound || std::isfinite(*r.lower_bound)) &&
         r.point_a.allFinite() && r.point_b.allFinite() && r.normal.allFinite();
}

// The checks' self-test (--doctor): a row made wrong on purpose, so that a test can show each
// kind of wrong row is caught (tests/hunt/check_hunt.py). `lower_bound`: an apart row's lower
// bound (a `farther` row's distance) raised by k_doctor_offset above its distance; `value`:
// every row's distance moved by that much farther; `sign`: every row's distance and lower
// bound negated.
constexpr double k_doctor_offset = 1e-2;  // relative to max(1, |distance|): far above E
Pair_report doctored(const std::string& how, Pair_report r) {
  const double delta = k_doctor_offset * std::max(1.0, std::abs(r.distance));
  if (how == "lower_bound") {
    if (r.status == Pair_status::Farther) r.distance += delta;
    else if (r.lower_bound && r.distance > 0.0) r.lower_bound = r.distance + delta;
  } else if (how == "value") {
    r.distance += delta;
  } else if (how == "sign") {
    r.distance = -r.distance;
    if (r.lower_bound) r.lower_bound = -*r.lower_bound;
  }
  return r;
}

// The reference and evidence a row is judged against, computed at its step.
struct Row_reference {
  Signed_distance_result ref;
  Evidence evidence = Evidence::Unknown;
  Depth depth;                                    // overlapping rows
  std::optional<Signed_distance_result> convex;   // apart rows of two convex bodies
  // Certified lower bounds on s(n) along the row's normal and (apart) the reference's.
  std::optional<double> support_row, support_ref;
  double rounding = 0.0;
};

struct Scene_result {
  std::vector<Pair_tally> tallies;
  std::vector<std::pair<std::string, std::string>> names;  // of each pair's bodies
  nlohmann::json wrong_rows = nlohmann::json::array();
  // [t, pair, distance, lower_bound or null, certified]
  nlohmann::json apart_rows = nlohmann::json::array();
};

void judge_row(const Options& o, const io::Scene& scene, int k, double t, const Pair_report& r,
               const Row_reference& R, double model_tolerance, Pair_tally& tally,
               Scene_result& out) {
  const auto& [ia, ib] = scene.pairs[k];
  const Signed_distance_result& ref = R.ref;
  const std::string a = scene.bodies[ia].name, b = scene.bodies[ib].name;
  bool row_wrong = false;
  auto judge = [&](Check c, bool ok, double expected, double lower, double upper) {
    ++tally.checked[c];
    if (ok) return;
    ++tally.failed[c];
    row_wrong = true;
    nlohmann::json w = {{"scene", scene.path}, {"t", t}, {"pair", k}, {"body_a", a},
                        {"body_b", b}, {"check", k_check_name[c]}, {"class", k_check_class[c]},
                        {"got", r.distance}, {"status", to_string(r.status)},
                        {"detail", detail_of(r)}, {"expected", expected}, {"lower", lower},
                        {"upper", upper}, {"reference_status", to_string(ref.status)},
                        {"overlap", to_string(ref.overlap)},
                        {"evidence", to_string(R.evidence)},
                        {"apart_query", to_string(ref.apart.status)},
                        {"apart_distance", ref.apart.distance}};
    if (r.lower_bound) w["lower_bound"] = *r.lower_bound;
    if (!std::isfinite(r.distance)) w["got"] = nullptr;
    for (const char* key : {"expected", "lower", "upper"})
      if (!std::isfinite(w[key].get<double>())) w[key] = nullptr;
    out.wrong_rows.push_back(w);
    char lower_text[64] = "";
    if (r.lower_bound) std::snprintf(lower_text, sizeof lower_text, ", lower bound %.12g", *r.lower_bound);
    if (o.rows)
      std::printf(
          "  WRONG (%s) %s: %s t = %.17g %s - %s: got %.12g%s (%s%s%s, faces %d %d), expected "
          "%.12g in [%.12g, %.12g] (reference %s, %s, %s %d, %s %d; apart query %s, %.12g; "
          "evidence: %s)\n"
          "    replay: verify_report %s --at %.17g --rows%s%s\n",
          k_check_class[c], k_check_name[c], scene.path.c_str(), t, a.c_str(), b.c_str(),
          r.distance, lower_text,
          to_string(r.status), detail_of(r).empty() ? "" : ", ", detail_of(r).c_str(), r.feature_a,
          r.feature_b, expected, lower, upper, to_string(ref.status), to_string(ref.overlap),
          to_string(ref.kind_a), ref.element_a, to_string(ref.kind_b), ref.element_b,
          to_string(ref.apart.status), ref.apart.distance, to_string(R.evidence), scene.path.c_str(), t,
          o.doctor.empty() ? "" : " --doctor ", o.doctor.c_str());
  };
  ++tally.rows;
  judge(Finite, finite_row(r), ref.distance, ref.lower_bound, ref.upper_bound);
  if (row_wrong) {
    ++tally.wrong;
    return;
  }
  // No certified lower bound above the truth.
  const double bound_slack = model_tolerance + R.rounding;
  const std::optional<double> lower =
      r.status == Pair_status::Farther ? std::optional<double>(r.distance) : r.lower_bound;
  // Overlapping, a row's lower bound is judged against the surfaces' distance (0 where they
  // meet), its sign by the sign checks below: one wrong reading, one wrong check.
  const double truth_upper =
      ref.overlap == Overlap_kind::None ? ref.upper_bound : ref.apart.upper_bound;
  if (lower && std::isfinite(truth_upper)) {
    const double excess = *lower - truth_upper;
    tally.max_lower_bound_excess = std::max(tally.max_lower_bound_excess, excess);
    judge(Lower_bound, excess <= bound_slack, truth_upper, -HUGE_VAL, truth_upper);
  }
  if (r.status == Pair_status::Farther) {
    ++tally.farther;
    if (row_wrong) ++tally.wrong;
    return;
  }
  // The separating-plane bounds.
  if (R.support_row)
    judge(Support_plane, r.distance >= *R.support_row - bound_slack, *R.support_row,
          *R.support_row, HUGE_VAL);
  if (R.support_ref)
    judge(Support_plane, r.distance >= *R.support_ref - bound_slack, *R.support_ref,
          *R.support_ref, HUGE_VAL);

  // The sign against evidence.
  const double sign_allowed = o.tolerance * std::max(1.0, std::abs(r.distance)) + model_tolerance;
  if (R.evidence == Evidence::Apart) {
    judge(Apart_sign, r.distance >= -sign_allowed, ref.distance, ref.lower_bound, ref.upper_bound);
  } else if (R.evidence == Evidence::Meet || R.evidence == Evidence::Contains) {
    judge(Overlap_sign, r.distance <= sign_allowed, ref.distance, ref.lower_bound, ref.upper_bound);
  } else {
    ++tally.sign_undecided;
  }
  if (R.evidence != Evidence::Unknown && ref.is_certified())
    judge(Reference_evidence, (ref.overlap != Overlap_kind::None) == (R.evidence != Evidence::Apart),
          ref.distance, ref.lower_bound, ref.upper_bound);

  if (!ref.is_certified()) {
    ++tally.unjudged;
    if (row_wrong) ++tally.wrong;
    return;
  }
  const double width = ref.upper_bound - ref.lower_bound;
  if (ref.overlap == Overlap_kind::None) {
    ++tally.apart;
    const double allowed =
        o.tolerance * std::max(1.0, std::abs(ref.distance)) + width + model_tolerance;
    // An `uncertified` row promises only its lower bound (judged above) and a real pair of
    // points: at least the truth, however far above it (Pair_report::lower_bound).
    const bool uncertified = r.status == Pair_status::Uncertified;
    const double e = std::abs(r.distance - ref.distance);
    if (uncertified) {
      ++tally.uncertified_rows;
      if (r.distance - ref.distance > tally.max_uncertified_excess) {
        tally.max_uncertified_excess = r.distance - ref.distance;
        tally.t_max_uncertified_excess = t;
      }
      judge(Apart_value, r.distance >= ref.lower_bound - allowed, ref.distance, ref.lower_bound,
            HUGE_VAL);
    } else {
      if (e > tally.max_apart_error) {
        tally.max_apart_error = e;
        tally.t_max_apart_error = t;
      }
      judge(Apart_value, e <= allowed, ref.distance, ref.lower_bound, ref.upper_bound);
    }
    out.apart_rows.push_back({t, k, r.distance, r.lower_bound ? nlohmann::json(*r.lower_bound)
                                                               : nlohmann::json(nullptr),
                              !uncertified});
    if (R.convex && R.convex->status == Signed_distance_status::Penetrating) {
      const Signed_distance_result& c = *R.convex;
      const double slack = o.tolerance * std::max(1.0, std::abs(c.distance)) + model_tolerance;
      judge(Convex_value,
            r.distance >= c.lower_bound - slack &&
                (uncertified || r.distance <= c.upper_bound + slack),
            c.distance, c.lower_bound, c.upper_bound);
    }
    if (row_wrong) ++tally.wrong;
    return;
  }
  ++tally.overlapping;
  const Depth& depth = R.depth;
  if (depth.check == k_check_count) {
    ++(depth.why == Depth::Border        ? tally.sheet_border_rows
       : depth.why == Depth::No_side     ? tally.no_entry_side_rows
       : depth.why == Depth::Other_sheet ? tally.other_sheet_rows
                                         : tally.hull_depth_rows);
    if (row_wrong) ++tally.wrong;
    return;
  }
  // Outside [lower, upper] by more than the tolerance (and the edge tolerances).
  const double slack = o.tolerance * std::max(1.0, std::abs(depth.value)) + model_tolerance;
  const double e = std::max({0.0, depth.lower - r.distance, r.distance - depth.upper});
  const double off = std::abs(r.distance - depth.value);
  if (off > tally.max_depth_error) {
    tally.max_depth_error = off;
    tally.t_max_depth_error = t;
  }
  judge(depth.check, e <= slack, depth.value, depth.lower, depth.upper);
  if (row_wrong) ++tally.wrong;
}

Scene_result verify(const Options& o, const std::string& path) {
  const io::Scene scene = io::read_scene(path, io::load_bodies);
  std::vector<std::unique_ptr<Distance_hierarchy>> hierarchies(scene.bodies.size());
  auto hierarchy = [&](int i) -> const Distance_hierarchy& {
    if (!hierarchies[i]) hierarchies[i] = std::make_unique<Distance_hierarchy>(scene.bodies[i].body);
    return *hierarchies[i];
  };
  std::vector<Body_info> info;
  for (const Scene_body& b : scene.bodies) {
    Body_info bi;
    bi.closed_mesh = !b.body.mesh.empty() && b.body.faces.empty() && b.body.curves.empty() &&
                     Mesh_bvh(b.body.mesh, b.body.name).closed();
    bi.edge_tolerance = edge_tolerance(b.body);
    bi.shape = shape_of(b);
    bi.convex = is_certified_convex(b.body) || bi.shape.kind == Shape::Sphere ||
                bi.shape.kind == Shape::Ellipsoid || bi.shape.kind == Shape::Cylinder ||
                bi.shape.kind == Shape::Point;
    bi.closed = body_closedness(b.body).closed;
    bi.ball = certified_ball(b.body);
    info.push_back(bi);
  }
  Signed_distance_request request;
  request.total_seconds = o.seconds;
  // A point at a ball's centre, for its centre's signed distance.
  static const Body point_body = make_point_body();
  static const Distance_hierarchy point_hierarchy(point_body);

  // Solids against `plane` shapes, by pair.
  std::vector<Sheet_pair> sheet_pairs(scene.pairs.size());
  for (std::size_t k = 0; k < scene.pairs.size(); ++k) {
    const auto& [ia, ib] = scene.pairs[k];
    for (const auto& [p, q] : {std::make_pair(ia, ib), std::make_pair(ib, ia)})
      if (info[p].shape.kind == Shape::Plane && info[q].closed) sheet_pairs[k] = {p, q, 0};
  }
  // A sheet pair's extent at t, and whether the solid is within the sheet.
  auto sheet_extent = [&](const Sheet_pair& sp, double t, bool& within) {
    const Rigid_pose_3 X_P = pose_of(scene.bodies[sp.plane], t);
    const Rigid_pose_3 X_S = pose_of(scene.bodies[sp.solid], t);
    const Vec3 n = X_P.rotation().col(2);
    within = within_sheet(info[sp.plane].shape, X_P, transformed(hierarchy(sp.solid).box(), X_S));
    return extent_along(info[sp.solid].shape, hierarchy(sp.solid), X_S, n, X_P.translation());
  };
  // The reference depth of pair k at t (overlapping rows), see the top.
  auto reference_depth = [&](int k, double t, const Signed_distance_result& ref) {
    Depth d;
    const auto& [ia, ib] = scene.pairs[k];
    const Body_info& ba = info[ia];
    const Body_info& bb = info[ib];
    const Rigid_pose_3 X_A = pose_of(scene.bodies[ia], t), X_B = pose_of(scene.bodies[ib], t);
    if (ba.ball && bb.ball) {
      d.check = Closed_form_depth;
      d.value = d.lower = d.upper =
          (X_A.apply_point(ba.ball->centre) - X_B.apply_point(bb.ball->centre)).norm() -
          ba.ball->radius - bb.ball->radius;
      return d;
    }
    const Sheet_pair& sp = sheet_pairs[k];
    if (sp.plane >= 0) {
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
      const Shape::Kind solid = info[sp.solid].shape.kind;
      d.check = solid == Shape::Sphere || solid == Shape::Ellipsoid ? Closed_form_depth
                                                                    : Sheet_plane_depth;
      // Entered from above: its lowest point's height (below 0); from below: minus its highest's.
      d.lower = sp.side > 0 ? e.low_lo : -e.high_hi;
      d.upper = sp.side > 0 ? e.low_hi : -e.high_lo;
      d.value = 0.5 * (d.lower + d.upper);
      return d;
    }
    // A ball against a closed body or a point: its centre's signed distance less its radius.
    for (const auto& [p, q, X_p, X_q] :
         {std::make_tuple(ia, ib, X_A, X_B), std::make_tuple(ib, ia, X_B, X_A)}) {
      const Body_info& ball = info[p];
      const Body_info& other = info[q];
      if (!ball.ball || !(other.closed || scene.bodies[q].body.is_point)) continue;
      const Rigid_pose_3 X_c(X_p.rotation(), X_p.apply_point(ball.ball->centre));
      const Signed_distance_result c =
          signed_distance(point_body, point_hierarchy, X_c, scene.bodies[q].body, hierarchy(q),
                          X_q, request);
      if (!c.is_certified()) return d;  // counted as hull depth: sign only
      d.check = Ball_depth;
      d.value = c.distance - ball.ball->radius;
      d.lower = c.lower_bound - ball.ball->radius;
      d.upper = c.upper_bound - ball.ball->radius;
      return d;
    }
    // A point inside a closed body: minus its distance to the surface (the reference's).
    if ((scene.bodies[ia].body.is_point || scene.bodies[ib].body.is_point) &&
        ref.depth_is_translation_distance) {
      d.check = Point_depth;
      d.value = ref.distance;
      d.lower = ref.lower_bound;
      d.upper = ref.upper_bound;
      return d;
    }
    // Two convex bodies: the minimum translation distance, the support function's depth; two
    // closed meshes read their hulls' depth by definition (docs/behaviour.md, "Meshes").
    if (ref.depth_is_translation_distance || (ba.convex && bb.convex) ||
        (ba.closed_mesh && bb.closed_mesh)) {
      d.check = Convex_value;
      d.value = ref.distance;
      d.lower = ref.lower_bound;
      d.upper = ref.upper_bound;
      return d;
    }
    // A sheet that is no `plane` shape: its entry side's depth is not known here.
    if (ba.closed != bb.closed) d.why = Depth::Other_sheet;
    return d;
  };
  // The evidence of overlap at the poses, from the apart query `apart`.
  auto evidence_of = [&](int ia, int ib, const Rigid_pose_3& X_A, const Rigid_pose_3& X_B,
                         const Distance_result& apart) {
    if (apart.status == Distance_status::Intersecting || apart.status == Distance_status::Touching)
      return Evidence::Meet;
    if (!(apart.lower_bound > 0.0)) return Evidence::Unknown;
    bool unknown = false;
    // Whether the closed body `outer` holds the world point x (at least the apart query's lower
    // bound from its surface).
    auto holds = [&](int outer, const Rigid_pose_3& X, const Vec3& x) {
      if (!info[outer].closed) return false;
      const Bbox_3 box = transformed(hierarchy(outer).box(), X);
      if (!CGAL::do_overlap(to_point(x).bbox(), box)) return false;
      const Winding_number w = winding_number(hierarchy(outer), X, x, apart.lower_bound);
      if (!w.determined) unknown = true;
      return w.inside();
    };
    if (holds(ia, X_A, apart.point_b) || holds(ib, X_B, apart.point_a)) return Evidence::Contains;
    return unknown ? Evidence::Unknown : Evidence::Apart;
  };
  // A certified lower bound on s(n) = -(h_A(n) + h_B(-n)).
  auto support_lower = [&](int ia, int ib, const Rigid_pose_3& X_A, const Rigid_pose_3& X_B,
                           const Vec3& n, double scale) -> std::optional<double> {
    if (!n.allFinite() || n.norm() < 0.5) return std::nullopt;
    const Vec3 u = n.normalized();
    Support_request s;
    s.tolerance = std::max(1e-12, 1e-9 * scale);
    s.max_nets = k_support_nets;
    const double up = support_bound(hierarchy(ia), X_A, u, s).upper +
                      support_bound(hierarchy(ib), X_B, -u, s).upper;
    if (!std::isfinite(up)) return std::nullopt;
    return -up;
  };

  Scene_result result;
  result.tallies.resize(scene.pairs.size());
  for (const auto& [ia, ib] : scene.pairs)
    result.names.emplace_back(scene.bodies[ia].name, scene.bodies[ib].name);
  std::vector<Pair_tally>& tallies = result.tallies;
  const int steps = scene.step_count();
  int at_step = -1;
  if (o.at) {
    at_step = static_cast<int>(std::lround((*o.at - scene.start) / scene.step));
    at_step = std::clamp(at_step, 0, steps - 1);
  }
  double stepping = 0.0;
  const std::unique_ptr<Scene_stepper> run = scene_stepper(scene);
  auto clock = std::chrono::steady_clock::now();
  run_scene(scene, *run, [&](int step, double t, const std::vector<Pair_report>& reports) {
    stepping += std::chrono::duration<double>(std::chrono::steady_clock::now() - clock).count();
    const bool check =
        o.at ? step == at_step : (step % o.every == 0 || step == steps - 1);
    for (std::size_t k = 0; k < reports.size(); ++k) {
      const auto& [ia, ib] = scene.pairs[k];
      Sheet_pair& sp = sheet_pairs[k];
      const auto t0 = std::chrono::steady_clock::now();
      Row_reference R;
      const Pair_report r = o.doctor.empty() ? reports[k] : doctored(o.doctor, reports[k]);
      if (check) {
        // The body frame sits at the entry's pose times the body's placement in its file.
        const Scene_body& A = scene.bodies[ia];
        const Scene_body& B = scene.bodies[ib];
        const Rigid_pose_3 X_A = pose_of(A, t), X_B = pose_of(B, t);
        const Bbox_3 box_a = transformed(hierarchy(ia).box(), X_A);
        const Bbox_3 box_b = transformed(hierarchy(ib).box(), X_B);
        R.rounding = rounding_scale(box_a, box_b);
        R.ref = signed_distance(A.body, hierarchy(ia), X_A, B.body, hierarchy(ib), X_B, request);
        if (finite_row(r) && r.status != Pair_status::Farther) {
          const double scale = R.rounding / (k_rounding_ulps * k_eps);
          R.evidence = evidence_of(ia, ib, X_A, X_B, R.ref.apart);
          R.support_row = support_lower(ia, ib, X_A, X_B, r.normal, scale);
          if (R.ref.is_certified() && R.ref.overlap == Overlap_kind::None) {
            R.support_ref = support_lower(ia, ib, X_A, X_B, R.ref.normal, scale);
            if (info[ia].convex && info[ib].convex)
              R.convex = hull_signed_distance(hierarchy(ia), X_A, hierarchy(ib), X_B, request);
          }
        }
        if (R.ref.is_certified() && R.ref.overlap != Overlap_kind::None)
          R.depth = reference_depth(static_cast<int>(k), t, R.ref);
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
        judge_row(o, scene, static_cast<int>(k), t, r, R,
                  info[ia].edge_tolerance + info[ib].edge_tolerance, tallies[k], result);
    }
    clock = std::chrono::steady_clock::now();
  });

  std::printf("%s: %d steps, stepping %.3g s (%.3g ms per step, all pairs)\n", path.c_str(), steps,
              stepping, 1e3 * stepping / std::max(1, steps));
  for (std::size_t k = 0; k < tallies.size(); ++k) {
    const Pair_tally& p = tallies[k];
    const auto& [ia, ib] = scene.pairs[k];
    std::printf(
        "  %s - %s: %d rows checked (%d apart, %d overlapping, %d farther, %d reference "
        "uncertified): %d wrong (%d wrong sign, %d wrong depth, %d not finite); overlapping rows "
        "checked against a depth %d (closed form %d, ball %d, point %d, convex %d, sheet's plane "
        "%d), by sign only %d (hull depth %d, sheet no plane %d, across a sheet's border %d, no "
        "entry side %d); sign undecided %d; max apart error %.3g at t = %.9g; max depth error "
        "%.3g at t = %.9g; reference %.3g s\n",
        scene.bodies[ia].name.c_str(), scene.bodies[ib].name.c_str(), p.rows, p.apart,
        p.overlapping, p.farther, p.unjudged, p.wrong, p.failed[Apart_sign] + p.failed[Overlap_sign],
        p.failed[Closed_form_depth] + p.failed[Ball_depth] + p.failed[Point_depth] +
            p.failed[Sheet_plane_depth] + (p.failed[Convex_value]),
        p.failed[Finite], p.depth_rows() + p.checked[Convex_value], p.checked[Closed_form_depth],
        p.checked[Ball_depth], p.checked[Point_depth], p.checked[Convex_value],
        p.checked[Sheet_plane_depth], p.sign_rows(), p.hull_depth_rows, p.other_sheet_rows,
        p.sheet_border_rows, p.no_entry_side_rows, p.sign_undecided, p.max_apart_error,
        p.t_max_apart_error, p.max_depth_error, p.t_max_depth_error, p.reference_seconds);
    std::printf("    checks (judged/wrong):");
    for (int c = 0; c < k_check_count; ++c)
      if (p.checked[c] > 0) std::printf(" %s %d/%d", k_check_name[c], p.checked[c], p.failed[c]);
    std::printf("; max lower-bound excess %.3g", p.max_lower_bound_excess);
    if (p.uncertified_rows > 0)
      std::printf("; %d apart rows uncertified, at most %.3g above the reference (t = %.9g)",
                  p.uncertified_rows, p.max_uncertified_excess, p.t_max_uncertified_excess);
    std::printf("\n");
  }
  return result;
}

nlohmann::json scene_json(const std::string& path, const Scene_result& s) {
  nlohmann::json pairs = nlohmann::json::array();
  for (std::size_t k = 0; k < s.tallies.size(); ++k) {
    const Pair_tally& p = s.tallies[k];
    nlohmann::json checks = nlohmann::json::object();
    for (int c = 0; c < k_check_count; ++c) checks[k_check_name[c]] = {p.checked[c], p.failed[c]};
    nlohmann::json j = {{"rows", p.rows},         {"apart", p.apart},
                        {"overlapping", p.overlapping}, {"farther", p.farther},
                        {"reference_uncertified", p.unjudged}, {"wrong", p.wrong},
                        {"sign_only", p.sign_rows()}, {"sign_undecided", p.sign_undecided},
                        {"checks", checks}, {"max_apart_error", p.max_apart_error},
                        {"max_depth_error", p.max_depth_error},
                        {"uncertified_rows", p.uncertified_rows},
                        {"max_uncertified_excess", p.max_uncertified_excess},
                        {"t_max_uncertified_excess", p.t_max_uncertified_excess},
                        {"max_lower_bound_excess", p.max_lower_bound_excess}};
    j["body_a"] = s.names[k].first;
    j["body_b"] = s.names[k].second;
    pairs.push_back(j);
  }
  return {{"scene", path}, {"pairs", pairs}, {"wrong_rows", s.wrong_rows},
          {"apart_rows", s.apart_rows}};
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"Checks a scene's report rows against the certified signed distance and evidence"};
  app.add_option("scenes", o.scenes, "Scene file(s)")->required();
  auto* every = app.add_option("--every", o.every, "Check every Nth step (and the last)")
                    ->check(CLI::PositiveNumber);
  app.add_option("--at", o.at, "Check the step nearest this time only")->excludes(every);
  app.add_option("--tolerance", o.tolerance,
                 "Allowed error, relative to max(1, |distance|), beyond the reference's width")
      ->check(CLI::PositiveNumber);
  app.add_option("--seconds", o.seconds, "Time limit of each reference query")
      ->check(CLI::PositiveNumber);
  app.add_flag("--rows", o.rows, "Print every wrong row, with a command that replays it");
  app.add_option("--doctor", o.doctor,
                 "Self-test of the checks: make rows wrong first (lower_bound: raise apart rows' "
                 "lower bounds above their distance; value: move every distance 1% farther; sign: "
                 "negate every distance)")
      ->check(CLI::IsMember({"lower_bound", "value", "sign"}));
  app.add_option("--json", o.json,
                 "Write the counts per check, the wrong rows and the apart rows as JSON");
  app.footer(
      "Each row goes through every check that applies (docs/checking.md): finite numbers; its\n"
      "lower bound at most the reference's upper bound; at least the separating-plane bound\n"
      "along its normal; its sign against evidence (surfaces that meet, or a closed body holding\n"
      "a point of the other); apart, its distance; overlapping, its depth where a reference is\n"
      "known: two balls, a ball's centre less its radius, a point's distance to the surface,\n"
      "two convex bodies (the support function's depth), a solid through a `plane` shape (the\n"
      "entry side's depth); other overlapping rows by their sign only. Exit code 3 when a row\n"
      "is wrong, 4 when a scene's run threw.");
  CLI11_PARSE(app, argc, argv);
  int wrong = 0;
  bool threw = false;
  nlohmann::json scenes = nlohmann::json::array();
  for (const std::string& path : o.scenes) {
    try {
      const Scene_result s = verify(o, path);
      for (const Pair_tally& p : s.tallies) wrong += p.wrong;
      scenes.push_back(scene_json(path, s));
    } catch (const Invalid_input& e) {
      std::cerr << "verify_report: " << e.what() << '\n';
      return 1;
    } catch (const std::exception& e) {
      std::cerr << "verify_report: " << path << ": the run threw: " << e.what() << '\n';
      scenes.push_back({{"scene", path}, {"error", e.what()}});
      threw = true;
    }
  }
  if (!o.json.empty()) {
    std::ofstream f(o.json);
    f << nlohmann::json{{"scenes", scenes}}.dump() << '\n';
    if (!f) {
      std::cerr << "verify_report: cannot write " << o.json << '\n';
      return 1;
    }
  }
  if (threw) return 4;
  return wrong == 0 ? 0 : 3;
}
