// Certified global distance against OpenCASCADE, same geometry, same process.
//
// Every case is built once as our Body and once in OpenCASCADE from the same poles, knots and
// weights (Geom_BSplineSurface, placed in the world; BRepBuilderAPI_MakeFace for
// BRepExtrema_DistShapeShape), so both sides measure the identical point sets. Truth: the
// support-function certificate for ellipsoids, the closed form for a sphere and a torus, and our
// own certificate at 1e-13 elsewhere (its gap is printed).
//
//   single-patch pairs: extremal_distance at tolerances 1e-3 .. 1e-12 (absolute and relative)
//                       against GeomAPI_ExtremaSurfaceSurface (no tolerance setting);
//   multi-face parts:   extremal_distance against BRepExtrema_DistShapeShape (deflection 1e-7,
//                       its default Precision::Confusion()).
// Prints a Markdown table of medians per query and ratios, and every case where a peer's answer
// is wrong (error > 1e-6 (1 + d): far beyond its own precision) or missing.
//
// Usage: bench_global_distance [--quick] [--seed N] [--only TEXT] [--no-peers]
//   --only TEXT: only the sets whose name contains TEXT (the cases are drawn as in a full run);
//   --no-peers:  ours only (for profiling; the ratio column is then empty).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

// CGAL before OpenCASCADE: OpenCASCADE's Handle macro breaks CGAL's headers.
#include "algorithms/distance/Ellipsoid_distance.h"
#include "algorithms/distance/Global_distance.h"
#include "kernel/Shapes.h"
#include "support/Occt_bridge.h"

#include <BRepExtrema_DistShapeShape.hxx>
#include <GeomAPI_ExtremaSurfaceSurface.hxx>
#include <Standard_Failure.hxx>

using namespace extremal;
using extremal::bench::to_occt;
using extremal::bench::to_occt_shape;

namespace {

using Clock = std::chrono::steady_clock;

double median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Times f (returning a distance) `reps` times; the median in microseconds.
double time_us(int reps, const std::function<double()>& f, double& value) {
  std::vector<double> t;
  for (int k = 0; k < reps; ++k) {
    const auto t0 = Clock::now();
    value = f();
    t.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
  }
  return median(t);
}

Rigid_pose_3 random_pose(std::mt19937_64& rng, double spread) {
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(-spread, spread);
  const Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
  return Rigid_pose_3::from_quaternion(Vec3(u(rng), u(rng), u(rng)), q.w(), q.x(), q.y(), q.z());
}

Nurbs_surface_3 wavy_patch(std::mt19937_64& rng, double x0, double y0, double size, int n) {
  std::uniform_real_distribution<double> bump(-0.25, 0.25);
  std::vector<Point_3> poles;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      poles.emplace_back(x0 + size * i / (n - 1), y0 + size * j / (n - 1), size * bump(rng));
  return make_freeform(3, 3, n, n, std::move(poles));
}

// A bicubic dome over [-1.5, 1.5]^2 of height h, with small bumps.
Nurbs_surface_3 dome_patch(std::mt19937_64& rng, double h) {
  std::uniform_real_distribution<double> bump(-0.03, 0.03);
  const int n = 6;
  std::vector<Point_3> poles;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double x = 3.0 * i / (n - 1) - 1.5, y = 3.0 * j / (n - 1) - 1.5;
      poles.emplace_back(x, y, h * (1.0 - (x * x + y * y) / 4.5) + bump(rng));
    }
  return make_freeform(3, 3, n, n, std::move(poles));
}

// A part of k x k freeform faces tiling a wavy square of side k * size.
Body wavy_part(std::mt19937_64& rng, int k, double size) {
  Body b;
  b.name = "wavy";
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j)
      b.faces.push_back({wavy_patch(rng, (i - 0.5 * k) * size, (j - 0.5 * k) * size, size, 6),
                         "bspline"});
  return b;
}

struct Case {
  std::string group;
  std::string name;
  Body a, b;
  Rigid_pose_3 X_WA, X_WB;
  double truth = NAN;      // NaN: take our certificate at 1e-13
  double truth_gap = 0.0;  // width of the truth's own certificate
};

struct Row {
  std::string group, solver;
  double tolerance = 0.0;  // 0 for peers
  std::vector<double> times, errors;
  int failures = 0;
  std::vector<double> nodes;  // ours: sub-patch nodes made per query (repeatable work measure)
};

}  // namespace

int main(int argc, char** argv) {
  bool quick = false, peers = true;
  std::string only;
  std::uint64_t seed = 20261123;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--quick")) quick = true;
    if (!std::strcmp(argv[i], "--no-peers")) peers = false;
    if (!std::strcmp(argv[i], "--only") && i + 1 < argc) only = argv[++i];
    if (!std::strcmp(argv[i], "--seed") && i + 1 < argc) seed = std::strtoull(argv[++i], nullptr, 10);
  }
  std::printf("seed %llu%s\n", static_cast<unsigned long long>(seed), quick ? " (quick)" : "");
  std::mt19937_64 rng(seed);
  std::vector<Case> cases;
  const int n_single = quick ? 4 : 12;
  // Single patch: two ellipsoids (the anchor set-up's shapes), certified truth.
  for (int k = 0; k < n_single; ++k) {
    Case c{"ellipsoid-ellipsoid (1 patch each)", "ellipsoids " + std::to_string(k),
           make_ellipsoid_body(3, 2, 1.5), make_ellipsoid_body(2, 1.2, 1), random_pose(rng, 1.0),
           Rigid_pose_3()};
    do c.X_WB = random_pose(rng, 7.0);
    while (!ellipsoid_distance({c.X_WA, Vec3(3, 2, 1.5)}, {c.X_WB, Vec3(2, 1.2, 1)}).separated ||
           ellipsoid_distance({c.X_WA, Vec3(3, 2, 1.5)}, {c.X_WB, Vec3(2, 1.2, 1)}).lower_bound < 0.1);
    const auto t = ellipsoid_distance({c.X_WA, Vec3(3, 2, 1.5)}, {c.X_WB, Vec3(2, 1.2, 1)});
    c.truth = 0.5 * (t.lower_bound + t.upper_bound);
    c.truth_gap = t.upper_bound - t.lower_bound;
    cases.push_back(std::move(c));
  }
  // Single patch: a sphere in the hole of a torus, off the axis (closed form).
  for (int k = 0; k < n_single; ++k) {
    std::uniform_real_distribution<double> ux(0.2, 1.2), uz(-1.5, 1.5), ur(0.2, 0.8);
    const double rs = ur(rng);
    // Turned about the axis so that the nearest torus point is off the parametrisation's seam
    // (a boundary for a non-periodic B-spline: peers would see an edge there).
    const double turn = std::uniform_real_distribution<double>(0.3, 1.2)(rng);
    const double rho = ux(rng);
    const Vec3 p(rho * std::cos(turn), rho * std::sin(turn), uz(rng));
    const Rigid_pose_3 X = random_pose(rng, 3.0);
    Case c{"sphere in torus hole (1 patch each)", "torus " + std::to_string(k),
           make_torus_body(3, 1), make_sphere_body(rs), X,
           X * Rigid_pose_3(Mat3::Identity(), p) * random_pose(rng, 0.0)};
    c.truth = std::hypot(rho - 3.0, p.z()) - 1.0 - rs;
    cases.push_back(std::move(c));
  }
  // Single patch: freeform domes facing each other (bicubic, 3 x 3 Bezier pieces each, small
  // bumps): the minimum is interior, where surface-surface extrema look.
  for (int k = 0; k < n_single; ++k) {
    Body a, b;
    a.faces.push_back({dome_patch(rng, 0.6), "bspline"});
    b.faces.push_back({dome_patch(rng, 0.6), "bspline"});
    std::normal_distribution<double> g(0.0, 0.05);
    const Rigid_pose_3 X = random_pose(rng, 2.0);
    // B upside down (a half turn about x), above A.
    cases.push_back({"freeform domes, interior minimum (1 patch each)", "dome " + std::to_string(k),
                     std::move(a), std::move(b), X,
                     X * Rigid_pose_3::from_quaternion(Vec3(g(rng), g(rng), 1.6), 0.0, 1.0,
                                                       g(rng), g(rng))});
  }
  // Single patch: wavy bicubic patches one above the other: the minimum is often on an edge.
  for (int k = 0; k < n_single; ++k) {
    Body a, b;
    a.faces.push_back({wavy_patch(rng, -1.5, -1.5, 3.0, 6), "bspline"});
    b.faces.push_back({wavy_patch(rng, -1.5, -1.5, 3.0, 6), "bspline"});
    std::normal_distribution<double> g(0.0, 0.1);
    const Rigid_pose_3 X = random_pose(rng, 2.0);
    cases.push_back({"wavy freeform, minimum often on an edge (1 patch each)", "freeform " + std::to_string(k),
                     std::move(a), std::move(b), X,
                     X * Rigid_pose_3::from_quaternion(Vec3(g(rng), g(rng), 1.8), 1, g(rng),
                                                       g(rng), g(rng))});
  }
  // Multi-face parts.
  const int n_multi = quick ? 2 : 5;
  for (int k = 0; k < n_multi; ++k) {
    const Rigid_pose_3 X = random_pose(rng, 3.0);
    std::normal_distribution<double> g(0.0, 0.2);
    cases.push_back({"wavy part (16 faces) vs ellipsoid", "wavy-ellipsoid " + std::to_string(k),
                     wavy_part(rng, 4, 1.0), make_ellipsoid_body(1.5, 1.0, 0.6), X,
                     X * Rigid_pose_3::from_quaternion(Vec3(g(rng), g(rng), 1.6), 1, g(rng),
                                                       g(rng), g(rng))});
  }
  for (int k = 0; k < n_multi; ++k) {
    const Rigid_pose_3 X = random_pose(rng, 3.0);
    std::normal_distribution<double> g(0.0, 0.2);
    cases.push_back({"wavy part (16 faces) vs wavy part (9 faces)", "wavy-wavy " + std::to_string(k),
                     wavy_part(rng, 4, 1.0), wavy_part(rng, 3, 1.0), X,
                     X * Rigid_pose_3::from_quaternion(Vec3(g(rng), g(rng), 1.5), 1, g(rng),
                                                       g(rng), g(rng))});
  }
  for (int k = 0; k < n_multi; ++k) {
    const Rigid_pose_3 X = random_pose(rng, 3.0);
    cases.push_back({"cylinder (3 faces) vs torus", "cylinder-torus " + std::to_string(k),
                     make_cylinder_body(1.0, 2.0), make_torus_body(2.0, 0.5), X,
                     X * random_pose(rng, 1.0) * Rigid_pose_3(Mat3::Identity(), Vec3(3.5, 0.5, 1.0))});
  }

  const std::vector<double> tolerances = {1e-3, 1e-6, 1e-9, 1e-12};
  const int reps = quick ? 3 : 7;
  std::vector<Row> rows;
  auto row = [&](const std::string& group, const std::string& solver, double tol) -> Row& {
    for (Row& r : rows)
      if (r.group == group && r.solver == solver && r.tolerance == tol) return r;
    rows.push_back({group, solver, tol, {}, {}, 0, {}});
    return rows.back();
  };
  std::vector<std::string> wrong;
  Distance_workspace ws;

  for (Case& c : cases) {
    if (c.group.find(only) == std::string::npos) continue;
    const bool multi = c.a.faces.size() > 1 || c.b.faces.size() > 1;
    const Distance_hierarchy ha(c.a), hb(c.b);
    if (std::isnan(c.truth)) {
      Distance_request req;
      req.absolute_tolerance = req.relative_tolerance = 1e-13;
      req.max_nodes = 2000000;
      const Distance_result r = extremal_distance(ha, c.X_WA, hb, c.X_WB, req, ws);
      c.truth = r.upper_bound;
      c.truth_gap = r.upper_bound - r.lower_bound;
      if (!r.is_certified()) std::printf("note: %s: truth not certified (%s)\n", c.name.c_str(), to_string(r.status));
    }
    for (double tol : tolerances) {
      Distance_request req;
      req.absolute_tolerance = req.relative_tolerance = tol;
      Distance_result r;
      double d = 0.0;
      const double t = time_us(reps, [&] {
        r = extremal_distance(ha, c.X_WA, hb, c.X_WB, req, ws);
        return r.distance;
      }, d);
      Row& w = row(c.group, "extremal_distance", tol);
      w.times.push_back(t);
      w.errors.push_back(std::abs(d - c.truth));
      w.nodes.push_back(static_cast<double>(r.nodes_created));
      if (!r.is_certified()) ++w.failures;
    }
    if (!multi && peers) {
      const Handle(Geom_BSplineSurface) sa = to_occt(c.a.faces[0].surface, c.X_WA);
      const Handle(Geom_BSplineSurface) sb = to_occt(c.b.faces[0].surface, c.X_WB);
      double d = NAN;
      bool ok = true;
      const double t = time_us(reps, [&] {
        try {
          GeomAPI_ExtremaSurfaceSurface ext(sa, sb);
          if (ext.NbExtrema() == 0) {
            ok = false;
            return std::numeric_limits<double>::quiet_NaN();
          }
          return ext.LowerDistance();
        } catch (const Standard_Failure&) {
          ok = false;
          return std::numeric_limits<double>::quiet_NaN();
        }
      }, d);
      Row& w = row(c.group, "GeomAPI_ExtremaSurfaceSurface", 0.0);
      w.times.push_back(t);
      if (!ok || !std::isfinite(d)) {
        ++w.failures;
        wrong.push_back(c.name + ": GeomAPI_ExtremaSurfaceSurface found no extremum (truth " +
                        std::to_string(c.truth) + ")");
      } else {
        w.errors.push_back(std::abs(d - c.truth));
        if (std::abs(d - c.truth) > 1e-6 * (1 + c.truth)) {
          char buf[256];
          std::snprintf(buf, sizeof buf, "%s: GeomAPI_ExtremaSurfaceSurface %.12g, certified %.12g (gap %.1e), error %.2e",
                        c.name.c_str(), d, c.truth, c.truth_gap, d - c.truth);
          wrong.push_back(buf);
        }
      }
    }
    if (peers) {
      const TopoDS_Shape sa = to_occt_shape(c.a, c.X_WA), sb = to_occt_shape(c.b, c.X_WB);
      double d = NAN;
      bool ok = true;
      const double t = time_us(multi ? std::max(1, reps / 2) : reps, [&] {
        try {
          BRepExtrema_DistShapeShape ext(sa, sb, 1e-7);
          if (!ext.IsDone()) {
            ok = false;
            return std::numeric_limits<double>::quiet_NaN();
          }
          return ext.Value();
        } catch (const Standard_Failure&) {
          ok = false;
          return std::numeric_limits<double>::quiet_NaN();
        }
      }, d);
      Row& w = row(c.group, "BRepExtrema_DistShapeShape", 0.0);
      w.times.push_back(t);
      if (!ok || !std::isfinite(d)) {
        ++w.failures;
        wrong.push_back(c.name + ": BRepExtrema_DistShapeShape not done");
      } else {
        w.errors.push_back(std::abs(d - c.truth));
        if (std::abs(d - c.truth) > 1e-6 * (1 + c.truth)) {
          char buf[256];
          std::snprintf(buf, sizeof buf, "%s: BRepExtrema_DistShapeShape %.12g, certified %.12g (gap %.1e), error %.2e",
                        c.name.c_str(), d, c.truth, c.truth_gap, d - c.truth);
          wrong.push_back(buf);
        }
      }
    }
    std::fprintf(stderr, "done %s\n", c.name.c_str());
  }

  std::printf("\n| pair set | solver | tolerance | median time per query (us) | max error | median error | not certified / failed | time vs peer | median nodes |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  std::string last;
  for (const Row& r : rows) {
    // Ratio against the peer of the set: GeomAPI for single patches, BRepExtrema for parts.
    double peer = NAN;
    for (const Row& p : rows)
      if (p.group == r.group && p.solver == "GeomAPI_ExtremaSurfaceSurface") peer = median(p.times);
    if (std::isnan(peer))
      for (const Row& p : rows)
        if (p.group == r.group && p.solver == "BRepExtrema_DistShapeShape") peer = median(p.times);
    const double t = median(r.times);
    char tol[32];
    if (r.tolerance > 0)
      std::snprintf(tol, sizeof tol, "%.0e", r.tolerance);
    else
      std::snprintf(tol, sizeof tol, "-");
    const double maxerr = r.errors.empty() ? NAN : *std::max_element(r.errors.begin(), r.errors.end());
    char nodes[32] = "-";
    if (!r.nodes.empty()) std::snprintf(nodes, sizeof nodes, "%.0f", median(r.nodes));
    std::printf("| %s | %s | %s | %.1f | %.1e | %.1e | %d of %zu | %.3gx | %s |\n",
                r.group == last ? "" : r.group.c_str(), r.solver.c_str(), tol, t, maxerr,
                median(r.errors), r.failures, r.times.size(), t / peer, nodes);
    last = r.group;
  }
  std::printf("\n%zu wrong or missing peer answers (error > 1e-6 (1 + d)):\n", wrong.size());
  for (const auto& w : wrong) std::printf("- %s\n", w.c_str());
  return 0;
}
