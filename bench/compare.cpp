// Run time against error, side by side with OpenCASCADE and FCL (issue 9): one program, one run.
//
// Scenarios (each a motion over a few seconds, the same frames for every method):
//   (a) the seed's two moving ellipsoids (bench/experiments/Ellipsoid_experiment's set-up);
//   (b) a non-convex part of 3 x 3 bicubic faces (an egg crate) under a moving ellipsoid;
//   (c) two real STEP parts from ../shared/data in relative motion (io::load_bodies);
//   (e) meshes against FCL on the same meshes and poses (compare_meshes.cpp; --mesh FILE adds
//       a large mesh, e.g. one written by `extremal tessellate`).
// Methods, each timed per frame (median) and its error (maximum and median) measured against
// the certified reference at the same frames:
//   - our tracker: Extremal_tracker on single patches, Scene_stepper (Body_pair_tracker) on
//     bodies, at several rates and gains, started on the certified pair;
//   - our certified global solver (extremal_distance) at several tolerances;
//   - OpenCASCADE GeomAPI_ExtremaSurfaceSurface (single patches) and BRepExtrema_DistShapeShape,
//     on the same geometry (our NURBS converted by support/Occt_bridge; the STEP files read by
//     OpenCASCADE itself in (c));
//   - FCL distance (BVHModel<OBBRSS>) on tessellations of increasing resolution (our patches on
//     a uniform parameter grid; OpenCASCADE's BRepMesh of the STEP shapes in (c)).
// References: the support-function certificate for (a) (gap ~1e-15), our certified global
// solver at 1e-12 for (b) and (c) (BRepExtrema, an independent code, is compared with it).
// Prints one Markdown table per scenario with the speed-up over each peer, the targets, and
// writes bench/results/compare_<scenario>.svg (log-log time against error; a partial run only
// with --out).
//
// Usage: compare [--quick] [--trackers-only] [--rate HZ] [--own-basin-gap G] [--budget E] [--out DIR]
//                [--data DIR] [--mesh FILE] [a] [b] [c] [d] [e]
//        compare --budget-sweep [--quick] [--out DIR] [--data DIR] [b] [c] [d]
// (--rate: only the tracker rows at that rate, for profiling one rate under callgrind;
// --own-basin-gap: Body_pair_options::own_basin_gap of the body-pair rows; --budget: their
// error budget, Body_pair_options::tolerance, absolute and relative alike.)
// --budget-sweep (compare_budget.h): instead of the tables above, the body-pair tracker at the
// budgets 1e-3, 1e-6, 1e-9 and 1e-12 against FCL's tessellation ladder of the same scenario,
// in (b) (1 kHz and 10 kHz), (c) (1 kHz) and (d) (the ball and the probe over all solids,
// 1 kHz; FCL on our tessellations of the ball and the solids): a table per scenario and
// compare_budget_<scenario>.svg (the same rule for where it is written).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

// CGAL (through our headers) before OpenCASCADE: its Handle macro breaks CGAL's headers.
#include "algorithms/body_pair/Body_pair_tracker.h"
#include "algorithms/distance/Ellipsoid_distance.h"
#include "algorithms/pair/Extremal_tracker.h"
#include "algorithms/distance/Global_distance.h"
#include "algorithms/scene/Scene_stepper.h"
#include "compare_assembly.h"
#include "compare_budget.h"
#include "compare_meshes.h"
#include "experiments/Egg_crate.h"
#include "experiments/Ellipsoid_experiment.h"
#include "io/Model_reader.h"
#include "kernel/Motion.h"
#include "kernel/Shapes.h"
#include "support/Fcl_bridge.h"
#include "support/Loglog_plot.h"
#include "support/Occt_bridge.h"

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/narrowphase/distance.h>

#include <BRepBuilderAPI_Transform.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRep_Tool.hxx>
#include <GeomAPI_ExtremaSurfaceSurface.hxx>
#include <Poly_Triangulation.hxx>
#include <STEPControl_Reader.hxx>
#include <Standard_Failure.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <gp_Trsf.hxx>

using namespace extremal;
using Clock = std::chrono::steady_clock;

namespace {

constexpr double k_nan = std::numeric_limits<double>::quiet_NaN();

double median(std::vector<double> v) {
  if (v.empty()) return k_nan;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}
double maximum(const std::vector<double>& v) {
  return v.empty() ? k_nan : *std::max_element(v.begin(), v.end());
}
double micros_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
}

// ---- scenarios ------------------------------------------------------------------------------

struct Mesh {
  std::vector<fcl::Vector3d> vertices;
  std::vector<fcl::Triangle> triangles;
};

struct Scenario {
  std::string key, title;
  Body a, b;
  Motion motion_a = Motion::still(Rigid_pose_3()), motion_b = Motion::still(Rigid_pose_3());
  double duration = 3.0;
  double reference_dt = 1e-3;  // reference grid; errors are measured on it
  std::string reference_name;
  std::function<double(double)> reference;  // certified distance at t (on the grid)
  bool single_patch = false;
  // OpenCASCADE shapes in the frame the motions place (B-rep files: the file frame).
  TopoDS_Shape occt_a, occt_b;
  // Tessellations in the same frame, coarse to fine, with a label.
  std::vector<std::pair<std::string, std::pair<Mesh, Mesh>>> meshes;

  Rigid_pose_3 pose(int side, double t) const {
    return side == 0 ? motion_a.pose_at(t) * a.placement : motion_b.pose_at(t) * b.placement;
  }
};

// World pose and twist of a body frame (the motion's twist moved to the body origin).
void body_state(const Motion& m, const Body& body, double t, Rigid_pose_3& X, Twist_3& V) {
  const Rigid_pose_3 entry = m.pose_at(t);
  const Twist_3 v = m.twist_at(t);
  X = entry * body.placement;
  V.angular = v.angular;
  V.linear = v.linear + v.angular.cross(X.translation() - entry.translation());
}

// Uniform n x n parameter grid per face, two triangles per cell, body frame mapped by `X`.
Mesh tessellate(const Body& body, int n, const Rigid_pose_3& X = Rigid_pose_3()) {
  Mesh m;
  for (const Face& f : body.faces) {
    const Nurbs_surface_3& s = f.surface;
    const int base = static_cast<int>(m.vertices.size());
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j) {
        const double u = s.u_min() + (s.u_max() - s.u_min()) * i / n;
        const double v = s.v_min() + (s.v_max() - s.v_min()) * j / n;
        const Vec3 p = X.apply_point(to_vec3(s.point(u, v)));
        m.vertices.emplace_back(p.x(), p.y(), p.z());
      }
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const int a = base + i * (n + 1) + j, b = a + n + 1;
        m.triangles.emplace_back(a, b, b + 1);
        m.triangles.emplace_back(a, b + 1, a + 1);
      }
  }
  return m;
}

// OpenCASCADE's triangulation of a shape (BRepMesh at `deflection`), in the shape's frame.
Mesh occt_mesh(const TopoDS_Shape& shape, double deflection) {
  BRepMesh_IncrementalMesh mesher(shape, deflection, false, 0.2, false);
  Mesh m;
  for (TopExp_Explorer ex(shape, TopAbs_FACE); ex.More(); ex.Next()) {
    const TopoDS_Face& face = TopoDS::Face(ex.Current());
    TopLoc_Location loc;
    const Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(face, loc);
    if (tri.IsNull()) continue;
    const gp_Trsf T = loc.Transformation();
    const int base = static_cast<int>(m.vertices.size());
    for (int i = 1; i <= tri->NbNodes(); ++i) {
      const gp_Pnt p = tri->Node(i).Transformed(T);
      m.vertices.emplace_back(p.X(), p.Y(), p.Z());
    }
    for (int i = 1; i <= tri->NbTriangles(); ++i) {
      int n1, n2, n3;
      tri->Triangle(i).Get(n1, n2, n3);
      m.triangles.emplace_back(base + n1 - 1, base + n2 - 1, base + n3 - 1);
    }
  }
  return m;
}

// ---- measurements ---------------------------------------------------------------------------

struct Row {
  std::string family;   // plot series
  std::string method, setting;
  std::vector<double> times_us, errors;
  int failures = 0;
  bool ours = false;
  long frames = 0;  // frames per run (trackers); else the number of timed queries
  std::string point_label;  // beside its point in the plot
  std::optional<bench::Budget_check> check;  // body-pair tracker rows, read against the budget
};

// The reference on its grid, computed once per grid point.
class Reference_cache {
 public:
  explicit Reference_cache(const Scenario& s) : m_s(s) {}
  double at_index(long k) {
    auto it = m_values.find(k);
    if (it != m_values.end()) return it->second;
    const double v = m_s.reference(k * m_s.reference_dt);
    m_values.emplace(k, v);
    return v;
  }
  // Grid index of t, or -1 if t is not on the grid.
  long index_of(double t) const {
    const double x = t / m_s.reference_dt;
    const long k = std::lround(x);
    return std::abs(x - k) < 1e-6 ? k : -1;
  }
  long count() const { return std::lround(m_s.duration / m_s.reference_dt); }

 private:
  const Scenario& m_s;
  std::map<long, double> m_values;
};

// Frames of the grid spread evenly over the motion.
std::vector<long> sample_indices(const Reference_cache& ref, int n) {
  std::vector<long> k;
  const long total = ref.count();
  for (int i = 0; i < n; ++i) k.push_back(total * i / std::max(1, n - 1));
  k.erase(std::unique(k.begin(), k.end()), k.end());
  return k;
}

struct Tracker_config {
  double rate = 1000.0;
  double kdt = 1.0;  // K dt
  int corrections = 0;
  int audit_every = 0;
  double own_basin_gap = Body_pair_options{}.own_basin_gap;  // body pairs only
  double budget = Body_pair_options{}.tolerance.relative;   // absolute and relative, body pairs
};

// Our tracker over the whole motion at `rate`, started on the certified pair at t = 0.
Row run_tracker(const Scenario& s, Reference_cache& ref, const Tracker_config& c) {
  Row row;
  row.ours = true;
  char buf[160];
  std::snprintf(buf, sizeof buf, "%g Hz, K dt = %g%s", c.rate, c.kdt,
                c.corrections ? ", corrections" : "");
  row.setting = buf;
  if (c.audit_every) row.setting += ", audit every " + std::to_string(c.audit_every);
  if (!s.single_patch && c.own_basin_gap != Body_pair_options{}.own_basin_gap) {
    char gap[64];
    std::snprintf(gap, sizeof gap, ", own-basin gap %g", c.own_basin_gap);
    row.setting += gap;
  }
  if (!s.single_patch && c.budget != Body_pair_options{}.tolerance.relative) {
    char budget[64];
    std::snprintf(budget, sizeof budget, ", budget %g", c.budget);
    row.setting += budget;
  }
  std::snprintf(buf, sizeof buf, "tracker K dt = %g%s%s", c.kdt, c.corrections ? " + corr." : "",
                c.audit_every ? " + audits" : "");
  row.family = buf;
  std::snprintf(buf, sizeof buf, "%g Hz", c.rate);
  row.point_label = buf;
  const double dt = 1.0 / c.rate;
  const long steps = std::lround(s.duration * c.rate);
  // Poses and twists before the clock starts: the motion is the scene's, not ours to time.
  struct State {
    Rigid_pose_3 XA, XB;
    Twist_3 VA, VB;
  };
  std::vector<State> states(steps + 1);
  for (long i = 0; i <= steps; ++i)
    body_state(s.motion_a, s.a, i * dt, states[i].XA, states[i].VA),
        body_state(s.motion_b, s.b, i * dt, states[i].XB, states[i].VB);
  std::vector<double> distance(steps + 1, k_nan);
  Tracker_options options;
  options.gain.setConstant(c.kdt / dt);
  options.corrections = c.corrections;
  // Whole runs timed, no clock inside the loop: a row's time is the median over runs of the
  // mean time per frame (runs repeated until about 30,000 frames are timed).
  // Body pairs start with a global solve (up to seconds on real parts): at most 3 runs.
  const int runs = static_cast<int>(
      std::clamp<long>(30000 / (steps + 1), 1, s.single_patch ? 20 : 3));
  row.frames = steps + 1;
  if (s.single_patch) {
    row.method = "Extremal_tracker";
    Distance_request request;
    request.absolute_tolerance = request.relative_tolerance = 1e-12;
    const Distance_result start =
        extremal_distance(s.a, states[0].XA, s.b, states[0].XB, request);
    const Tracker_seed seed = tracker_seed(s.a, s.b, start);
    for (int run = 0; run < runs; ++run) {
      Extremal_tracker tracker(seed.feature_a, seed.feature_b, seed.params, options);
      const auto t0 = Clock::now();
      for (long i = 0; i <= steps; ++i) {
        const State& x = states[i];
        distance[i] = tracker.step(i * dt, x.XA, x.VA, x.XB, x.VB, dt).distance;
      }
      row.times_us.push_back(micros_since(t0) / (steps + 1));
    }
  } else {
    row.method = "Scene_stepper";
    Body_pair_options options_b;
    options_b.tracker = options;
    options_b.audit_every = c.audit_every;
    options_b.own_basin_gap = c.own_basin_gap;
    options_b.tolerance = {c.budget, c.budget};
    row.check = bench::Budget_check{options_b.tolerance};
    std::vector<Pair_report> reports(steps + 1);  // the last run's, read against the budget
    std::vector<double> starts;
    for (int run = 0; run < runs; ++run) {
      Scene_stepper stepper({{&s.a, &s.motion_a}, {&s.b, &s.motion_b}}, {{0, 1}}, options_b);
      // The first step seeds the trackers by the global solver: a start-up cost, reported apart.
      const auto t0 = Clock::now();
      reports[0] = stepper.step(0.0, dt)[0];
      starts.push_back(micros_since(t0));
      const auto t1 = Clock::now();
      for (long i = 1; i <= steps; ++i) reports[i] = stepper.step(i * dt, dt)[0];
      const Pair_statistics* last = steps > 0 ? &stepper.statistics(0) : nullptr;
      row.times_us.push_back(micros_since(t1) / std::max<long>(1, steps));
      if (run == 0 && last)
        std::fprintf(stderr, "(%s) %g Hz: candidate pairs without a tracker checked %ld times, "
                     "%ld restricted solves (%ld nodes; %ld on creases, %ld past their reach with the "
                     "bound clear, %ld partial); instead, %ld set-aside proofs and %ld bounds checked "
                     "again; %ld broad phases, %ld seeds, %ld transitions; %ld corrections, "
                     "%ld steps that ran all of them\n",
                     s.key.c_str(), c.rate, last->vacated_checks, last->vacated_solves,
                     last->vacated_nodes, last->vacated_crease_solves, last->vacated_reach_solves, last->vacated_partial_solves,
                     last->vacated_proof_checks, last->vacated_bound_checks,
                     last->broad_phases, last->seeds,
                     last->transitions, last->corrections, last->capped_corrections);
    }
    std::snprintf(buf, sizeof buf, " (start %.0f us)", median(starts));
    row.setting += buf;
    for (long i = 0; i <= steps; ++i) {
      distance[i] = reports[i].distance;
      row.check->add_report(reports[i]);
    }
  }
  for (long i = 0; i <= steps; ++i) {
    const long k = ref.index_of(i * dt);
    if (k < 0 || k > ref.count()) continue;
    if (!std::isfinite(distance[i])) {
      ++row.failures;
      continue;
    }
    row.errors.push_back(std::abs(distance[i] - ref.at_index(k)));
    if (row.check) row.check->add_error(row.errors.back(), ref.at_index(k));
  }
  return row;
}

Row run_global(const Scenario& s, Reference_cache& ref, const std::vector<long>& frames,
               double tolerance, const Distance_hierarchy& ha, const Distance_hierarchy& hb,
               Distance_workspace& ws) {
  Row row;
  row.ours = true;
  row.family = "global solver (certified)";
  row.method = "extremal_distance";
  char buf[64];
  std::snprintf(buf, sizeof buf, "tolerance %.0e", tolerance);
  row.setting = buf;
  row.point_label = buf + 10;  // the tolerance
  Distance_request request;
  request.absolute_tolerance = request.relative_tolerance = tolerance;
  for (long k : frames) {
    const double t = k * s.reference_dt;
    const Rigid_pose_3 XA = s.pose(0, t), XB = s.pose(1, t);
    const auto t0 = Clock::now();
    const Distance_result r = extremal_distance(ha, XA, hb, XB, request, ws);
    row.times_us.push_back(micros_since(t0));
    if (!r.is_certified()) ++row.failures;
    row.errors.push_back(std::abs(r.distance - ref.at_index(k)));
  }
  return row;
}

Row run_geomapi(const Scenario& s, Reference_cache& ref, const std::vector<long>& frames) {
  Row row;
  row.family = "OCCT GeomAPI_ExtremaSurfaceSurface";
  row.method = "GeomAPI_ExtremaSurfaceSurface";
  row.setting = "-";
  for (long k : frames) {
    const double t = k * s.reference_dt;
    const Handle(Geom_BSplineSurface) fa = bench::to_occt(s.a.faces[0].surface, s.pose(0, t));
    const Handle(Geom_BSplineSurface) fb = bench::to_occt(s.b.faces[0].surface, s.pose(1, t));
    double d = k_nan;
    const auto t0 = Clock::now();
    try {
      GeomAPI_ExtremaSurfaceSurface ext(fa, fb);
      if (ext.NbExtrema() > 0) d = ext.LowerDistance();
    } catch (const Standard_Failure&) {
    }
    row.times_us.push_back(micros_since(t0));
    if (!std::isfinite(d))
      ++row.failures;
    else
      row.errors.push_back(std::abs(d - ref.at_index(k)));
  }
  return row;
}

Row run_brep(const Scenario& s, Reference_cache& ref, const std::vector<long>& frames) {
  Row row;
  row.family = "OCCT BRepExtrema_DistShapeShape";
  row.method = "BRepExtrema_DistShapeShape";
  row.setting = "deflection 1e-7";
  for (long k : frames) {
    const double t = k * s.reference_dt;
    const TopoDS_Shape sa = bench::moved(s.occt_a, s.motion_a.pose_at(t));
    const TopoDS_Shape sb = bench::moved(s.occt_b, s.motion_b.pose_at(t));
    double d = k_nan;
    const auto t0 = Clock::now();
    try {
      BRepExtrema_DistShapeShape ext(sa, sb, 1e-7);
      if (ext.IsDone()) d = ext.Value();
    } catch (const Standard_Failure&) {
    }
    row.times_us.push_back(micros_since(t0));
    if (!std::isfinite(d))
      ++row.failures;
    else
      row.errors.push_back(std::abs(d - ref.at_index(k)));
  }
  return row;
}

Row run_fcl(const Scenario& s, Reference_cache& ref, const std::vector<long>& frames,
            const std::string& label, const Mesh& ma, const Mesh& mb) {
  Row row;
  row.family = "FCL distance, OBBRSS";
  row.method = "FCL distance (OBBRSS)";
  const auto t0 = Clock::now();
  const auto A = bench::fcl_model(ma.vertices, ma.triangles);
  const auto B = bench::fcl_model(mb.vertices, mb.triangles);
  char buf[160];
  std::snprintf(buf, sizeof buf, "%s: %zu + %zu triangles (build %.2f s)", label.c_str(),
                ma.triangles.size(), mb.triangles.size(), micros_since(t0) * 1e-6);
  row.setting = buf;
  std::snprintf(buf, sizeof buf, "%.2gM tri", (ma.triangles.size() + mb.triangles.size()) * 1e-6);
  row.point_label = buf;
  fcl::DistanceRequestd request;
  for (long k : frames) {
    const double t = k * s.reference_dt;
    const fcl::Transform3d TA = bench::fcl_pose(s.motion_a.pose_at(t)),
                           TB = bench::fcl_pose(s.motion_b.pose_at(t));
    fcl::DistanceResultd result;
    const auto t1 = Clock::now();
    fcl::distance(A.get(), TA, B.get(), TB, request, result);
    row.times_us.push_back(micros_since(t1));
    if (!std::isfinite(result.min_distance))
      ++row.failures;
    else
      row.errors.push_back(std::abs(result.min_distance - ref.at_index(k)));
  }
  return row;
}

// ---- reporting -----------------------------------------------------------------------------

const Row* find_peer(const std::vector<Row>& rows, const std::string& method) {
  for (const Row& r : rows)
    if (r.method == method) return &r;
  return nullptr;
}
// The FCL row with the smallest maximum error (FCL's best accuracy).
const Row* best_fcl(const std::vector<Row>& rows) {
  const Row* best = nullptr;
  for (const Row& r : rows)
    if (r.method.rfind("FCL", 0) == 0 && (!best || maximum(r.errors) < maximum(best->errors)))
      best = &r;
  return best;
}

std::string ratio(const Row* peer, const Row& r) {
  if (!peer || peer == &r) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", median(peer->times_us) / median(r.times_us));
  return buf;
}

// The fastest of our rows whose maximum error is at most `error` (and that never failed).
const Row* fastest_ours_within(const std::vector<Row>& rows, double error) {
  const Row* best = nullptr;
  for (const Row& r : rows)
    if (r.ours && r.failures == 0 && !r.errors.empty() && maximum(r.errors) <= error &&
        (!best || median(r.times_us) < median(best->times_us)))
      best = &r;
  return best;
}

void report(const Scenario& s, const std::vector<Row>& rows, const std::string& out_dir) {
  const Row* geomapi = find_peer(rows, "GeomAPI_ExtremaSurfaceSurface");
  const Row* brep = find_peer(rows, "BRepExtrema_DistShapeShape");
  const Row* fcl = best_fcl(rows);
  std::printf("\n### (%s) %s\n\nReference: %s. Speed-up = peer's median time / this row's.\n\n",
              s.key.c_str(), s.title.c_str(), s.reference_name.c_str());
  std::printf("| method | setting | frames | median time per frame (us) | max error | median error | "
              "failed | speed-up vs GeomAPI | vs BRepExtrema | vs FCL at its best error |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows)
    std::printf("| %s | %s | %ld | %.3g | %.1e | %.1e | %d | %s | %s | %s |\n", r.method.c_str(),
                r.setting.c_str(), r.frames ? r.frames : static_cast<long>(r.times_us.size()), median(r.times_us), maximum(r.errors),
                median(r.errors), r.failures, ratio(geomapi, r).c_str(), ratio(brep, r).c_str(),
                ratio(fcl, r).c_str());
  std::printf("\nTargets:\n");
  if (geomapi) {
    const double e = maximum(geomapi->errors);
    const Row* ours = fastest_ours_within(rows, e);
    if (ours)
      std::printf("- GeomAPI (max error %.1e, %.3g us): fastest of ours at equal or smaller error is "
                  "%s, %s: %.3g us, %.3gx faster (target 1000x): %s\n",
                  e, median(geomapi->times_us), ours->method.c_str(), ours->setting.c_str(),
                  median(ours->times_us), median(geomapi->times_us) / median(ours->times_us),
                  median(geomapi->times_us) / median(ours->times_us) >= 1000 ? "met" : "NOT met");
    else
      std::printf("- GeomAPI (max error %.1e): none of ours reaches that error\n", e);
  }
  if (fcl) {
    const double e = maximum(fcl->errors);
    const Row* ours = fastest_ours_within(rows, e);
    if (ours)
      std::printf("- FCL at its best error (%s, max error %.1e, %.3g us): fastest of ours at equal or "
                  "smaller error is %s, %s: %.3g us, %.3gx faster (target 10000x): %s\n",
                  fcl->setting.c_str(), e, median(fcl->times_us), ours->method.c_str(),
                  ours->setting.c_str(), median(ours->times_us),
                  median(fcl->times_us) / median(ours->times_us),
                  median(fcl->times_us) / median(ours->times_us) >= 10000 ? "met" : "NOT met");
    else
      std::printf("- FCL (max error %.1e): none of ours reaches that error\n", e);
  }
  if (brep) {
    // BRepExtrema against the reference: an independent check of (b) and (c)'s references.
    std::printf("- BRepExtrema against the reference: max difference %.1e over %zu frames\n",
                maximum(brep->errors), brep->errors.size());
  }
  std::fflush(stdout);

  bench::Loglog_plot plot =
      bench::time_error_plot("(" + s.key + ") " + s.title + ": time per frame against maximum error");
  for (const Row& r : rows)
    plot.add_point(r.family, median(r.times_us), maximum(r.errors), r.point_label);
  plot.write_or_note(out_dir, "compare_" + s.key + ".svg");
}

// ---- the scenarios --------------------------------------------------------------------------

Scenario seed_ellipsoids(bool quick) {
  Scenario s;
  s.key = "a";
  s.title = "the seed's two moving ellipsoids";
  const experiments::Ellipsoid_setup e = experiments::default_ellipsoid_setup();
  s.a = make_ellipsoid_body(e.axes_a.x(), e.axes_a.y(), e.axes_a.z());
  s.b = make_ellipsoid_body(e.axes_b.x(), e.axes_b.y(), e.axes_b.z());
  s.motion_a = Motion::twist(e.pose_a, e.twist_a, 0.0);
  s.motion_b = Motion::twist(e.pose_b, e.twist_b, 0.0);
  s.duration = 3.0;
  s.reference_dt = 1e-3;
  s.single_patch = true;
  s.reference_name = "support-function certificate of the two ellipsoids (gap <= 2e-15)";
  auto normal = std::make_shared<Vec3>(Vec3::Zero());
  const Motion ma = s.motion_a, mb = s.motion_b;
  s.reference = [=](double t) {
    const Ellipsoid_distance_result r =
        ellipsoid_distance({ma.pose_at(t), e.axes_a}, {mb.pose_at(t), e.axes_b}, *normal);
    *normal = r.normal;
    return r.separated ? 0.5 * (r.lower_bound + r.upper_bound) : k_nan;
  };
  s.occt_a = bench::to_occt_shape(s.a, Rigid_pose_3());
  s.occt_b = bench::to_occt_shape(s.b, Rigid_pose_3());
  for (int n : quick ? std::vector<int>{16, 64, 256} : std::vector<int>{16, 64, 256, 724}) {
    const std::string label = std::to_string(n) + " x " + std::to_string(n) + " grid";
    s.meshes.push_back({label, {tessellate(s.a, n), tessellate(s.b, n)}});
  }
  return s;
}

Scenario crate_and_ellipsoid(bool quick) {
  Scenario s;
  s.key = "b";
  s.title = "non-convex part (3 x 3 bicubic faces) under a moving ellipsoid";
  s.a = experiments::egg_crate();
  s.b = make_ellipsoid_body(0.6, 0.4, 0.3);
  Twist_3 v;
  v.linear = Vec3(0.6, 0.4, 0.0);
  v.angular = Vec3(0.3, 0.2, 0.5);
  s.motion_b = Motion::twist(Rigid_pose_3(Mat3::Identity(), Vec3(-0.9, -0.6, 0.95)), v, 0.0);
  s.duration = 3.0;
  s.reference_dt = 1e-2;
  s.reference_name = "our certified global solver at 1e-12 (BRepExtrema checks it)";
  auto ha = std::make_shared<Distance_hierarchy>(s.a);
  auto hb = std::make_shared<Distance_hierarchy>(s.b);
  auto ws = std::make_shared<Distance_workspace>();
  const Motion mb = s.motion_b;
  s.reference = [=](double t) {
    Distance_request r;
    r.absolute_tolerance = r.relative_tolerance = 1e-12;
    return extremal_distance(*ha, Rigid_pose_3(), *hb, mb.pose_at(t), r, *ws).distance;
  };
  s.occt_a = bench::to_occt_shape(s.a, Rigid_pose_3());
  s.occt_b = bench::to_occt_shape(s.b, Rigid_pose_3());
  const std::vector<std::pair<int, int>> grids =
      quick ? std::vector<std::pair<int, int>>{{4, 12}, {16, 48}, {64, 192}}
            : std::vector<std::pair<int, int>>{{4, 12}, {16, 48}, {64, 192}, {192, 576}};
  for (const auto& [na, nb] : grids) {
    const std::string label = std::to_string(na) + "^2 per face, ellipsoid " +
                              std::to_string(nb) + "^2";
    s.meshes.push_back({label, {tessellate(s.a, na), tessellate(s.b, nb)}});
  }
  return s;
}

Scenario step_parts(bool quick, const std::string& data, bool& ok) {
  Scenario s;
  s.key = "c";
  ok = false;
  const std::string file_a = data + "/step/screw.step", file_b = data + "/step/linkrods.step";
  s.title = "two STEP parts in relative motion (screw.step, linkrods.step)";
  std::vector<Body> ba, bb;
  try {
    ba = io::load_bodies(file_a, "mm", "mm");
    bb = io::load_bodies(file_b, "mm", "mm");
  } catch (const std::exception& e) {
    std::printf("\n(c) skipped: %s\n", e.what());
    return s;
  }
  if (ba.size() != 1 || bb.size() != 1) {
    std::printf("\n(c) skipped: expected one body per file, got %zu and %zu\n", ba.size(), bb.size());
    return s;
  }
  s.a = std::move(ba[0]);
  s.b = std::move(bb[0]);
  // OpenCASCADE reads the same files for its own distance and meshes (file frame).
  auto read = [](const std::string& path) {
    STEPControl_Reader reader;
    if (reader.ReadFile(path.c_str()) != IFSelect_RetDone) return TopoDS_Shape();
    reader.TransferRoots();
    return reader.OneShape();
  };
  s.occt_a = read(file_a);
  s.occt_b = read(file_b);
  if (s.occt_a.IsNull() || s.occt_b.IsNull()) {
    std::printf("\n(c) skipped: OpenCASCADE could not read the files\n");
    return s;
  }
  const Bbox_3 box_a = s.a.trimmed_bbox(s.a.placement), box_b = s.b.trimmed_bbox(s.b.placement);
  auto half = [](const Bbox_3& b) -> Vec3 {
    return 0.5 * Vec3(b.xmax() - b.xmin(), b.ymax() - b.ymin(), b.zmax() - b.zmin());
  };
  std::printf("\n(c) %s: %zu faces, box %.1f x %.1f x %.1f mm; %s: %zu faces, box %.1f x %.1f x %.1f mm\n",
              file_a.c_str(), s.a.faces.size(), 2 * half(box_a).x(), 2 * half(box_a).y(),
              2 * half(box_a).z(), file_b.c_str(), s.b.faces.size(), 2 * half(box_b).x(),
              2 * half(box_b).y(), 2 * half(box_b).z());
  // A still; B's frame recentred on its box centre, so that it turns about that centre. B
  // passes beside A's box along y while it turns slowly, never nearer than a tenth of A's size
  // to A's box (its box's half diagonal bounds how far it reaches from its centre).
  const double size_a = half(box_a).norm();
  const double reach_b = half(box_b).norm();
  const Rigid_pose_3 recentre(Mat3::Identity(), -box_centre(box_b));
  s.b.placement = recentre * s.b.placement;
  s.occt_b = bench::moved(s.occt_b, recentre);
  const Vec3 start = box_centre(box_a) + Vec3(half(box_a).x() + reach_b + 0.1 * size_a, -size_a, 0.0);
  Twist_3 v;
  v.linear = Vec3(0.0, size_a, 0.0);
  v.angular = Vec3(0.05, 0.1, 0.15);
  s.motion_b = Motion::twist(Rigid_pose_3(Mat3::Identity(), start), v, 0.0);
  s.duration = 2.0;
  s.reference_dt = 0.1;
  s.reference_name = "our certified global solver at 1e-12 (BRepExtrema checks it)";
  auto ha = std::make_shared<Distance_hierarchy>(s.a);
  auto hb = std::make_shared<Distance_hierarchy>(s.b);
  auto ws = std::make_shared<Distance_workspace>();
  const Motion mb = s.motion_b;
  const Rigid_pose_3 pa = s.a.placement, pb = s.b.placement;
  s.reference = [=](double t) {
    Distance_request r;
    r.absolute_tolerance = r.relative_tolerance = 1e-12;
    return extremal_distance(*ha, pa, *hb, mb.pose_at(t) * pb, r, *ws).distance;
  };
  const double size = std::max(size_a, reach_b);
  // Down to the resolutions (a) and (b) reach (about a million triangles), where FCL is at its
  // most accurate: BRepMesh's linear deflection, not its angle, decides these.
  for (double rel : quick ? std::vector<double>{1e-2, 1e-3}
                          : std::vector<double>{1e-2, 1e-3, 1e-4, 1e-5, 1e-6}) {
    char label[64];
    std::snprintf(label, sizeof label, "BRepMesh deflection %.0e of size", rel);
    s.meshes.push_back({label, {occt_mesh(s.occt_a, rel * size), occt_mesh(s.occt_b, rel * size)}});
  }
  ok = true;
  return s;
}

// The frames the one-shot methods (the global solver, FCL) are timed and checked on.
std::vector<long> one_shot_frames(const Scenario& s, const Reference_cache& ref, bool quick) {
  return sample_indices(ref, quick || s.key == "c" ? 10 : 40);
}

// FCL on each of the scenario's tessellations, coarse to fine.
void run_fcl_ladder(const Scenario& s, Reference_cache& ref, const std::vector<long>& frames,
                    Clock::time_point t_start, std::vector<Row>& rows) {
  for (const auto& [label, meshes] : s.meshes) {
    rows.push_back(run_fcl(s, ref, frames, label, meshes.first, meshes.second));
    std::fprintf(stderr, "(%s) FCL %s: %.0f s\n", s.key.c_str(), label.c_str(),
                 micros_since(t_start) * 1e-6);
  }
}

void run_scenario(Scenario& s, bool quick, bool trackers_only, double only_rate,
                  double own_basin_gap, double budget, const std::string& out_dir) {
  Reference_cache ref(s);
  std::vector<Row> rows;
  const auto t_start = Clock::now();
  // Our tracker at several rates and gains (the whole motion at each rate).
  std::vector<Tracker_config> configs;
  const std::vector<double> rates = s.key == "c" ? std::vector<double>{20, 100, 1000}
                                                 : std::vector<double>{100, 1000, 10000};
  for (double rate : rates) configs.push_back({rate, 1.0, 0, 0});
  if (s.key != "c")
    for (double rate : rates) configs.push_back({rate, 0.5, 0, 0});
  if (!s.single_patch) {
    for (double rate : rates) configs.push_back({rate, 1.0, 10, 0});
    for (double rate : rates) configs.push_back({rate, 1.0, 10, static_cast<int>(rate / 10)});
  }
  for (Tracker_config& c : configs) {
    if (only_rate > 0.0 && c.rate != only_rate) continue;
    c.own_basin_gap = own_basin_gap;
    c.budget = budget;
    rows.push_back(run_tracker(s, ref, c));
    std::fprintf(stderr, "(%s) %s %s: %.0f s\n", s.key.c_str(), rows.back().method.c_str(),
                 rows.back().setting.c_str(), micros_since(t_start) * 1e-6);
  }
  if (trackers_only) {  // for profiling the tracker (valgrind --tool=callgrind)
    report(s, rows, out_dir);
    return;
  }
  // Our certified global solver.
  const Distance_hierarchy ha(s.a), hb(s.b);
  Distance_workspace ws;
  const std::vector<long> frames = one_shot_frames(s, ref, quick);
  for (double tol : {1e-3, 1e-6, 1e-9, 1e-12}) rows.push_back(run_global(s, ref, frames, tol, ha, hb, ws));
  std::fprintf(stderr, "(%s) global: %.0f s\n", s.key.c_str(), micros_since(t_start) * 1e-6);
  // OpenCASCADE.
  if (s.single_patch) rows.push_back(run_geomapi(s, ref, frames));
  const std::vector<long> few = sample_indices(ref, quick || s.key == "c" ? 2 : 5);
  rows.push_back(run_brep(s, ref, few));
  std::fprintf(stderr, "(%s) OpenCASCADE: %.0f s\n", s.key.c_str(), micros_since(t_start) * 1e-6);
  run_fcl_ladder(s, ref, frames, t_start, rows);
  report(s, rows, out_dir);
}

// A row of the budget sweep's table: a tracker row's point labelled by its budget, on the
// line of its rate; FCL's as in the scenario's plot.
bench::Budget_sweep_row budget_sweep_row(const Row& r) {
  bench::Budget_sweep_row b;
  b.method = r.method;
  b.setting = r.setting;
  b.frames = r.frames ? r.frames : static_cast<long>(r.times_us.size());
  b.median_us = median(r.times_us);
  b.max_error = maximum(r.errors);
  b.failures = r.failures;
  b.check = r.check;
  if (r.check) {
    b.series = r.method + ", " + r.point_label;
    char budget[32];
    std::snprintf(budget, sizeof budget, "%.0e", r.check->budget.absolute);
    b.point_label = budget;
  } else {
    b.series = r.family;
    b.point_label = r.point_label;
  }
  return b;
}

// --budget-sweep: the body-pair tracker as a scene runs it (K dt = 1 with corrections,
// Body_pair_options' default) at each swept budget, at (b)'s 1 kHz and 10 kHz or (c)'s 1 kHz,
// and FCL's tessellation ladder on the frames run_scenario times it on; one table, one plot.
void run_budget_sweep(Scenario& s, bool quick, const std::string& out_dir) {
  Reference_cache ref(s);
  std::vector<Row> rows;
  const auto t_start = Clock::now();
  const std::vector<double> rates =
      s.key == "b" ? std::vector<double>{1000, 10000} : std::vector<double>{1000};
  for (double rate : rates)
    for (double budget : bench::k_swept_budgets) {
      Tracker_config c{rate, 1.0, Body_pair_options{}.tracker.corrections, 0};
      c.budget = budget;
      rows.push_back(run_tracker(s, ref, c));
      std::fprintf(stderr, "(%s) %s %s: %.0f s\n", s.key.c_str(), rows.back().method.c_str(),
                   rows.back().setting.c_str(), micros_since(t_start) * 1e-6);
    }
  const std::vector<long> frames = one_shot_frames(s, ref, quick);
  run_fcl_ladder(s, ref, frames, t_start, rows);
  bench::Budget_sweep sweep;
  sweep.key = s.key;
  sweep.title = s.title;
  char notes[512];
  std::snprintf(notes, sizeof notes,
                "Reference: %s, every %g s. Tracker rows: Scene_stepper over the whole motion, "
                "started on the certified pair; time the median over runs of the mean per frame "
                "(the start apart). FCL rows: BVHModel<OBBRSS> on the scenario's tessellations, "
                "the median per query over %zu frames.",
                s.reference_name.c_str(), s.reference_dt, frames.size());
  sweep.notes = notes;
  for (const Row& r : rows) sweep.rows.push_back(budget_sweep_row(r));
  bench::report_budget_sweep(sweep, out_dir);
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false, trackers_only = false, budget_sweep = false;
  double only_rate = 0.0;
  double own_basin_gap = Body_pair_options{}.own_basin_gap;
  double budget = Body_pair_options{}.tolerance.relative;
  std::string out_dir;  // bench/results for full runs (below)
  std::string data = EXTREMAL_SHARED_DATA;
  std::string large_mesh;  // (e): a mesh of 10^5 triangles or more
  std::vector<std::string> only;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--quick"))
      quick = true;
    else if (!std::strcmp(argv[i], "--trackers-only"))
      trackers_only = true;
    else if (!std::strcmp(argv[i], "--rate") && i + 1 < argc)
      only_rate = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--own-basin-gap") && i + 1 < argc)
      own_basin_gap = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--budget") && i + 1 < argc)
      budget = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--budget-sweep"))
      budget_sweep = true;
    else if (!std::strcmp(argv[i], "--out") && i + 1 < argc)
      out_dir = argv[++i];
    else if (!std::strcmp(argv[i], "--data") && i + 1 < argc)
      data = argv[++i];
    else if (!std::strcmp(argv[i], "--mesh") && i + 1 < argc)
      large_mesh = argv[++i];
    else if (!std::strcmp(argv[i], "a") || !std::strcmp(argv[i], "b") || !std::strcmp(argv[i], "c") ||
             !std::strcmp(argv[i], "d") || !std::strcmp(argv[i], "e"))
      only.push_back(argv[i]);
    else {
      const bool help = !std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h");
      if (!help) std::fprintf(stderr, "compare: unknown argument '%s'\n", argv[i]);
      std::fprintf(help ? stdout : stderr,
                   "usage: compare [--quick] [--trackers-only] [--rate HZ] [--own-basin-gap G] [--budget E] "
                   "[--out DIR] [--data DIR] [--mesh FILE] [a] [b] [c] [d] [e]\n"
                   "       compare --budget-sweep [--quick] [--out DIR] [--data DIR] [b] [c] [d]\n");
      return help ? 0 : 2;
    }
  }
  if (budget_sweep && std::any_of(only.begin(), only.end(),
                                  [](const std::string& key) { return key == "a" || key == "e"; })) {
    std::fprintf(stderr, "compare: --budget-sweep runs (b), (c) and (d) only\n");
    return 2;
  }
  // A partial run (--quick, --trackers-only, --rate) leaves the committed plots of the full
  // runs that bench/RESULTS.md shows alone unless --out says where to write.
  if (out_dir.empty() && !quick && !trackers_only && !(only_rate > 0.0)) out_dir = "bench/results";
  auto wanted = [&](const char* key) {
    return only.empty() || std::find(only.begin(), only.end(), key) != only.end();
  };
  std::printf("bench/compare%s%s: time per frame and error against the certified reference\n",
              budget_sweep ? " --budget-sweep" : "", quick ? " --quick" : "");
  try {
    if (budget_sweep) {
      if (wanted("b")) {
        Scenario b = crate_and_ellipsoid(quick);
        run_budget_sweep(b, quick, out_dir);
      }
      if (wanted("c")) {
        bool ok = false;
        Scenario c = step_parts(quick, data, ok);
        if (ok) run_budget_sweep(c, quick, out_dir);
      }
      if (wanted("d")) extremal::bench::run_assembly_budget_sweep(quick, data, out_dir);
      return 0;
    }
    if (wanted("a")) {
      Scenario a = seed_ellipsoids(quick);
      run_scenario(a, quick, trackers_only, only_rate, own_basin_gap, budget, out_dir);
    }
    if (wanted("b")) {
      Scenario b = crate_and_ellipsoid(quick);
      run_scenario(b, quick, trackers_only, only_rate, own_basin_gap, budget, out_dir);
    }
    if (wanted("c")) {
      bool ok = false;
      Scenario c = step_parts(quick, data, ok);
      if (ok) run_scenario(c, quick, trackers_only, only_rate, own_basin_gap, budget, out_dir);
    }
    if (wanted("d")) extremal::bench::run_assembly_scenario(quick, data);
    if (wanted("e")) extremal::bench::run_mesh_scenario(quick, data, large_mesh);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "compare: %s\n", e.what());
    return 1;
  }
  return 0;
}
