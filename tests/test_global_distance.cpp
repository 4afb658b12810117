// The certified global distance: ellipsoids against the support-function certificate, a sphere in
// the hole of a torus (closed form, many local minima), multi-patch freeform patches against dense
// sampling plus Newton, every pair kind (surface, curve, point), intersections reported as exactly
// zero, budgets, symmetry and rigid invariance, tracker seeding and audits. Random cases come from
// a seeded std::mt19937_64 (EXTREMAL_SEED=n reproduces a run).
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <random>
#include <vector>

#include "algorithms/distance/Ellipsoid_distance.h"
#include "algorithms/pair/Extremal_tracker.h"
#include "algorithms/distance/Global_distance.h"
#include "algorithms/distance/internal/Restricted_solve.h"
#include "algorithms/distance/internal/Bezier_net.h"
#include "kernel/Error.h"
#include "kernel/Nurbs_refinement.h"
#include "kernel/Shapes.h"
#include "support/Random.h"

#include "support/Allocation_counter.h"

namespace extremal {
namespace {

constexpr double k_pi = 3.14159265358979323846;

using test::random_pose;

Rigid_pose_3 translation(double x, double y, double z) {
  return Rigid_pose_3(Mat3::Identity(), Vec3(x, y, z));
}

// Distance from a world point to body element at the witness parameters (checks the witness is
// really on the element).
Vec3 element_point(const Body& body, const Rigid_pose_3& X, Element_kind kind, int index,
                   const std::array<double, 2>& q) {
  switch (kind) {
    case Element_kind::Point: return X.translation();
    case Element_kind::Curve: return X.apply_point(to_vec3(body.curves[index].point(q[0])));
    case Element_kind::Face: return X.apply_point(to_vec3(body.faces[index].surface.point(q[0], q[1])));
  }
  return Vec3::Zero();
}

// Everything a certified result promises, against a known true distance `truth` (known to
// `truth_error`).
void expect_certified(const Distance_result& r, double truth, double truth_error,
                      const Distance_request& req, const Body& A, const Rigid_pose_3& X_WA,
                      const Body& B, const Rigid_pose_3& X_WB) {
  ASSERT_EQ(r.status, Distance_status::Converged) << to_string(r.status);
  EXPECT_LE(r.lower_bound, truth + truth_error);
  EXPECT_GE(r.upper_bound, truth - truth_error);
  const double tol = std::max(req.absolute_tolerance, req.relative_tolerance * r.upper_bound);
  EXPECT_LE(r.upper_bound - r.lower_bound, tol * (1 + 1e-12) + 1e-15 * std::abs(truth));
  EXPECT_NEAR(r.distance, truth, tol + truth_error);
  EXPECT_EQ(r.distance, r.upper_bound);
  // Normal convention: p_B - p_A = distance * normal, |normal| = 1.
  EXPECT_NEAR(r.normal.norm(), 1.0, 1e-12);
  EXPECT_LE((r.point_b - r.point_a - r.distance * r.normal).norm(), 1e-12 * (1 + truth));
  // The witnesses lie on the elements they name, at the parameters they give.
  const double scale = 1.0 + r.point_a.norm() + r.point_b.norm();
  EXPECT_LE((element_point(A, X_WA, r.kind_a, r.element_a, r.params_a) - r.point_a).norm(),
            1e-12 * scale);
  EXPECT_LE((element_point(B, X_WB, r.kind_b, r.element_b, r.params_b) - r.point_b).norm(),
            1e-12 * scale);
}

// ---- Ellipsoids: certified truth -----------------------------------------------------------

TEST(GlobalDistance, EllipsoidsAgainstSupportFunctionCertificate) {
  auto rng = test::seeded_rng();
  const Vec3 axes_a(3, 2, 1.5), axes_b(2, 1.2, 1);
  const Body A = make_ellipsoid_body(axes_a.x(), axes_a.y(), axes_a.z());
  const Body B = make_ellipsoid_body(axes_b.x(), axes_b.y(), axes_b.z());
  const Distance_hierarchy ha(A), hb(B);
  Distance_workspace ws;
  int cases = 0;
  for (int trial = 0; trial < 200 && cases < 40; ++trial) {
    const Rigid_pose_3 X_WA = random_pose(rng, 1.0);
    const Rigid_pose_3 X_WB = random_pose(rng, 8.0);
    const auto truth = ellipsoid_distance({X_WA, axes_a}, {X_WB, axes_b});
    if (!truth.separated || truth.lower_bound < 1e-3) continue;
    ++cases;
    for (double tol : {1e-3, 1e-6, 1e-9, 1e-12}) {
      SCOPED_TRACE(::testing::Message() << "case " << cases << " tolerance " << tol);
      Distance_request req;
      req.absolute_tolerance = tol;
      req.relative_tolerance = tol;
      const Distance_result r = extremal_distance(ha, X_WA, hb, X_WB, req, ws);
      expect_certified(r, 0.5 * (truth.lower_bound + truth.upper_bound),
                       0.5 * (truth.upper_bound - truth.lower_bound) + 1e-14, req, A, X_WA, B,
                       X_WB);
    }
  }
  EXPECT_GE(cases, 30);
}

// A ball resting on a plane, its lowest point near the pole of its parametrisation: the
// witnesses 6e-13 apart, their direction rounding ((-0.77, 0.60, -0.20) before); the normal
// is the ball's outward one there, from A to B; and the plane's when the ball touches exactly
// at its pole (zero before).
TEST(GlobalDistance, TheNormalOfBodiesThatTouchIsTheSurfaces) {
  const Body ball = make_sphere_body(1.0), plane = make_plane_body(10.0, 10.0);
  for (const Vec3& centre : {Vec3(0.01, 0, 1), Vec3(0, 0, 1), Vec3(0.3, -0.2, 1 + 1e-9)}) {
    SCOPED_TRACE(::testing::Message() << "ball at " << centre.transpose());
    const Distance_result r =
        extremal_distance(ball, Rigid_pose_3(Mat3::Identity(), centre), plane, Rigid_pose_3());
    EXPECT_NEAR(r.distance, centre.z() - 1.0, 1e-9);
    EXPECT_LE((r.normal - Vec3(0, 0, -1)).norm(), 1e-6);
    const Distance_result s =
        extremal_distance(plane, Rigid_pose_3(), ball, Rigid_pose_3(Mat3::Identity(), centre));
    EXPECT_LE((s.normal - Vec3(0, 0, 1)).norm(), 1e-6);
  }
  // Behind the open plane: from it to the ball is down, against its normal (b - a = d n).
  const Distance_result behind = extremal_distance(
      plane, Rigid_pose_3(), ball, Rigid_pose_3(Mat3::Identity(), Vec3(0.2, 0, -1 - 1e-7)));
  EXPECT_LE((behind.normal - Vec3(0, 0, -1)).norm(), 1e-6);
  // A cylinder tilted onto its rim over the plane: the side's and the cap's normals are not
  // the pair's direction there (the cap's read 23 degrees off), the plane's is.
  const Body cylinder = make_cylinder_body(1.0, 4.0);
  const Mat3 tilt = Eigen::AngleAxisd(0.4, Vec3::UnitX()).toRotationMatrix();
  for (double gap : {1e-5, 1e-7, 1e-9}) {
    SCOPED_TRACE(::testing::Message() << "cylinder on its rim, gap " << gap);
    const Distance_result r = extremal_distance(
        cylinder, Rigid_pose_3(tilt, Vec3(0, 0, std::sin(0.4) + gap)), plane, Rigid_pose_3());
    EXPECT_NEAR(r.distance, gap, 1e-12);
    EXPECT_LE((r.normal - Vec3(0, 0, -1)).norm(), 1e-6);
  }
}

// A restricted query started from the sub-patch pairs of an earlier one (Body_pair_tracker
// solves again only the pairs whose kept proofs fail): from all of them at the same poses, the
// distance; after B moved, the pairs whose re-bound fell below the earlier distance solved
// again, with the others' re-bounds, give a bound that holds and the distance where the
// re-bounds clear it, against the support-function certificate.
TEST(GlobalDistance, RestartedFromKeptPairsTheEllipsoidsKeepTheirDistance) {
  auto rng = test::seeded_rng();
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const Vec3 axes_a(3, 2, 1.5), axes_b(2, 1.2, 1);
  const Body A = make_ellipsoid_body(axes_a.x(), axes_a.y(), axes_a.z());
  const Body B = make_ellipsoid_body(axes_b.x(), axes_b.y(), axes_b.z());
  const Distance_hierarchy ha(A), hb(B);
  const int ea = ha.element_of(Element_kind::Face, 0), eb = hb.element_of(Element_kind::Face, 0);
  Distance_workspace ws, ws_again;
  Distance_request req;
  req.absolute_tolerance = req.relative_tolerance = 1e-10;
  internal::Proof_request keep;
  keep.keep_proofs = true;
  int cases = 0, found = 0;
  long part_nodes = 0, anew_nodes = 0;
  for (int trial = 0; trial < 200 && cases < 20; ++trial) {
    const Rigid_pose_3 X_WA = random_pose(rng, 1.0);
    const Rigid_pose_3 X_WB = random_pose(rng, 8.0);
    const auto truth = ellipsoid_distance({X_WA, axes_a}, {X_WB, axes_b});
    if (!truth.separated || truth.lower_bound < 1e-2) continue;
    ++cases;
    SCOPED_TRACE(::testing::Message() << "case " << cases);
    const Distance_result first =
        internal::extremal_distance_between(ha, X_WA, ea, hb, X_WB, eb, req, keep, ws);
    ASSERT_TRUE(first.is_certified()) << to_string(first.status);
    const std::vector<Bound_proof> bounds = ws.bound_proofs();
    ASSERT_FALSE(bounds.empty());
    std::vector<internal::Sub_patch_pair> all;
    for (const Bound_proof& b : bounds) all.push_back({b.a_lo, b.a_hi, b.b_lo, b.b_hi});
    const Distance_result same =
        internal::extremal_distance_between(ha, X_WA, ea, hb, X_WB, eb, all, req, keep, ws_again);
    EXPECT_TRUE(same.is_certified()) << to_string(same.status);
    EXPECT_NEAR(same.distance, truth.upper_bound, 1e-9 * truth.upper_bound);
    EXPECT_NEAR(same.lower_bound, truth.lower_bound, 1e-9 * truth.upper_bound);

    // B turned about a point near it and shifted, by a few percent of the distance.
    const double scale = 0.05 * truth.upper_bound;
    const Vec3 centre = X_WB.translation() + Vec3(unit(rng), unit(rng), unit(rng));
    const Rigid_pose_3 motion =
        Rigid_pose_3(Mat3::Identity(), centre + scale * Vec3(unit(rng), unit(rng), unit(rng))) *
        Rigid_pose_3(Eigen::AngleAxisd(0.02 * unit(rng), Vec3(unit(rng), unit(rng), unit(rng)).normalized())
                         .toRotationMatrix(),
                     Vec3::Zero()) *
        Rigid_pose_3(Mat3::Identity(), -centre);
    const Rigid_pose_3 X_WB1 = motion * X_WB;
    const auto truth1 = ellipsoid_distance({X_WA, axes_a}, {X_WB1, axes_b});
    std::vector<internal::Sub_patch_pair> restarts;
    double kept = HUGE_VAL;
    for (const Bound_proof& b : bounds) {
      const double now = bound_after_motion(b, motion, X_WB.translation().norm());
      if (now >= first.distance)
        kept = std::min(kept, now);
      else
        restarts.push_back({b.a_lo, b.a_hi, b.b_lo, b.b_hi});
    }
    const Distance_result part = internal::extremal_distance_between(ha, X_WA, ea, hb, X_WB1, eb,
                                                                    restarts, req, keep, ws_again);
    const Distance_result anew = extremal_distance_between(ha, X_WA, ea, hb, X_WB1, eb, req, ws_again);
    part_nodes += part.nodes_created;
    anew_nodes += anew.nodes_created;
    EXPECT_LE(std::min(part.lower_bound, kept), truth1.upper_bound + 1e-12);
    if (part.element_a >= 0) {
      EXPECT_GE(part.distance, truth1.lower_bound - 1e-12);
    }
    if (kept > truth1.upper_bound) {
      ++found;
      EXPECT_NEAR(part.distance, truth1.upper_bound, 1e-9 * truth1.upper_bound);
    }
  }
  std::printf("[ case     ] %d cases, %d found by the pairs solved again; %ld nodes against %ld "
              "solving anew\n", cases, found, part_nodes, anew_nodes);
  EXPECT_GE(cases, 15);
  EXPECT_GE(found, cases / 2);
  EXPECT_LT(part_nodes, anew_nodes);

  // A sub-patch in no piece of its element is an error that names the element.
  internal::Sub_patch_pair outside;
  outside.a_lo = {10.0, 0.0};
  outside.a_hi = {11.0, 0.5};
  outside.b_hi = {0.5, 0.5};
  try {
    (void)internal::extremal_distance_between(ha, Rigid_pose_3(), ea, hb, random_pose(rng, 8.0), eb,
                                              {outside}, req, keep, ws);
    ADD_FAILURE() << "no error for a sub-patch outside its element";
  } catch (const Precondition_violation& e) {
    EXPECT_NE(std::string(e.what()).find("lies in no piece of element"), std::string::npos) << e.what();
  }
}

// ---- A sphere in the hole of a torus -------------------------------------------------------

// Distance from a sphere (centre p, radius rs) to a torus (axis z, radii R, r) it does not touch:
// the distance from p to the torus's core circle, less both radii.
double sphere_torus_distance(const Vec3& p, double R, double r, double rs) {
  const double rho = std::hypot(p.x(), p.y());
  return std::hypot(rho - R, p.z()) - r - rs;
}

// A restricted query proving a cutoff just below a known minimum (the own-basin watch of
// Body_pair_tracker) settles the minimum's neighbourhood by a convexity certificate about the
// stationary point it is given, instead of hull bounds down to sub-patches of the square root
// of the gap: the same certified bound with fewer nodes, and never above the true minimum.
TEST(GlobalDistance, AStationaryPointSettlesItsNeighbourhoodBelowACutoff) {
  const Body ring = make_torus_body(3.0, 1.0), rod = make_cylinder_body(0.5, 10.0);
  const Distance_hierarchy ha(ring), hb(rod);
  const Rigid_pose_3 X_B(Mat3::Identity(), Vec3(-1.0, 0.3, -5.0));
  // Exact: 2 - |(-1, 0.3)| - 0.5 from the ring's inner circle to the rod's axis.
  const double exact = 2.0 - std::hypot(1.0, 0.3) - 0.5;
  Distance_request r;
  const Distance_result g = extremal_distance(ha, Rigid_pose_3(), hb, X_B, r);
  ASSERT_TRUE(g.is_certified());
  ASSERT_NEAR(g.distance, exact, 1e-9);
  const int ea = ha.element_of(g.kind_a, g.element_a), eb = hb.element_of(g.kind_b, g.element_b);
  Distance_workspace ws;
  for (const double gap : {1e-6, 1e-9}) {
    long nodes[2] = {0, 0};
    for (const bool given : {false, true}) {
      Distance_request q;
      q.max_nodes = 20000;
      q.cutoff = g.distance - 0.5 * gap;
      internal::Proof_request proof;
      proof.keep_proofs = true;
      proof.cutoff_floor = g.distance - gap;
      if (given)
        proof.stationary =
            std::array<double, 4>{{g.params_a[0], g.params_a[1], g.params_b[0], g.params_b[1]}};
      const Distance_result w =
          internal::extremal_distance_between(ha, Rigid_pose_3(), ea, hb, X_B, eb, q, proof, ws);
      ASSERT_TRUE(w.is_certified()) << gap << " " << given;
      EXPECT_EQ(w.element_a, -1) << "nothing below the cutoff";
      EXPECT_GE(w.uncarried_lower_bound, q.cutoff - 2e-9) << gap << " " << given;
      EXPECT_LE(w.uncarried_lower_bound, exact + 1e-12) << gap << " " << given;
      nodes[given] = w.nodes_created;
    }
    std::printf("[ watch    ] gap %g: %ld nodes by hull bounds, %ld with the stationary point\n", gap,
                nodes[0], nodes[1]);
    EXPECT_LT(nodes[1], nodes[0]);
  }
}

// Knot lines a face may fold along (Distance_hierarchy::reaches_kink): a rational circle's
// double knots join its arcs without a corner and are not listed; a degree-1 ridge is.
TEST(GlobalDistance, FoldsInsideAFaceAreTheCornersOnly) {
  const Body cylinder = make_cylinder_body(1.0, 2.0);
  const Distance_hierarchy hc(cylinder);
  int smooth_knots = 0;
  for (int e = 0; e < static_cast<int>(hc.elements().size()); ++e) {
    const Nurbs_surface_3* s = hc.elements()[e].feature.surface();
    if (s == nullptr) continue;
    for (int dir = 0; dir < 2; ++dir) {
      const std::vector<double>& k = dir == 0 ? s->knots_u() : s->knots_v();
      const int degree = dir == 0 ? s->degree_u() : s->degree_v();
      for (std::size_t i = static_cast<std::size_t>(degree) + 1; i + degree + 1 < k.size(); ++i) {
        if (std::count(k.begin(), k.end(), k[i]) < degree) continue;
        const double lo[2] = {dir == 0 ? k[i] : s->u_min(), dir == 1 ? k[i] : s->v_min()};
        const double hi[2] = {dir == 0 ? k[i] : s->u_min(), dir == 1 ? k[i] : s->v_min()};
        EXPECT_FALSE(hc.reaches_kink(e, lo, hi)) << "element " << e << " knot " << k[i];
        ++smooth_knots;
      }
    }
  }
  EXPECT_GT(smooth_knots, 0);  // the circle's double knots were looked at

  // A roof: degree 1 across a ridge at v = 0.5, and a flat degree-1 strip with the same knots.
  auto roof = [](double ridge) {
    std::vector<Point_3> poles;
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 3; ++j) poles.emplace_back(i, j, j == 1 ? ridge : 0.0);
    Body b;
    b.faces.emplace_back(Nurbs_surface_3(1, 1, 2, 3, poles, {0, 0, 1, 1}, {0, 0, 0.5, 1, 1}), "roof");
    return b;
  };
  const Body ridged = roof(1.0), flat = roof(0.0);
  const Distance_hierarchy hr(ridged), hf(flat);
  const double at_ridge_lo[2] = {0.2, 0.3}, at_ridge_hi[2] = {0.4, 0.5};
  const double away_lo[2] = {0.2, 0.6}, away_hi[2] = {0.4, 0.9};
  EXPECT_TRUE(hr.reaches_kink(0, at_ridge_lo, at_ridge_hi));
  EXPECT_FALSE(hr.reaches_kink(0, away_lo, away_hi));
  EXPECT_FALSE(hf.reaches_kink(0, at_ridge_lo, at_ridge_hi));
}

// A face's trim boundary is carried by its B-rep edges' curve elements; an edge without a 3D
// curve carries it only if it is degenerate (a pole). One the file gave no curve for leaves
// the boundary open (Element::open_sides bit 4), so no gradient argument drops a sub-patch for
// an extremum that would lie there.
TEST(GlobalDistance, AnEdgeWithoutACurveCarriesNothingUnlessDegenerate) {
  auto square = [](bool last_has_curve, bool last_degenerate) {
    std::vector<Point_3> poles = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0}};
    Body b;
    b.faces.emplace_back(Nurbs_surface_3(1, 1, 2, 2, poles, {0, 0, 1, 1}, {0, 0, 1, 1}), "plane");
    const double corner[5][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}};
    Trim_loop loop;
    for (int k = 0; k < 4; ++k) {
      const Point_3 a(corner[k][0], corner[k][1], 0), c(corner[k + 1][0], corner[k + 1][1], 0);
      loop.curves.push_back({Nurbs_curve_3(1, {a, c}, {0, 0, 1, 1}), k, false});
      Edge e;
      e.t_min = 0.0;
      e.t_max = 1.0;
      if (k < 3 || last_has_curve) e.curve = Nurbs_curve_3(1, {a, c}, {0, 0, 1, 1});
      e.degenerate = k == 3 && last_degenerate;
      e.uses.push_back({0, 0, k});
      b.edges.push_back(std::move(e));
    }
    b.faces[0].trims.push_back(std::move(loop));
    b.faces[0].update_trim_region(1e-9);
    return b;
  };
  auto face_open = [](const Body& b) {
    const Distance_hierarchy h(b);
    for (const auto& e : h.elements())
      if (e.kind == Element_kind::Face) return e.open_sides;
    return 0xFFu;
  };
  EXPECT_EQ(face_open(square(true, false)), 0u);            // every side a curve element
  EXPECT_EQ(face_open(square(false, true)), 0u);            // a degenerate edge: its point
  EXPECT_NE(face_open(square(false, false)) & 0x10u, 0u);   // no curve, not degenerate: open
}

TEST(GlobalDistance, SphereOnTheAxisOfATorus) {
  // On the axis every point of a circle on the tube is nearest: a continuum of minimisers. The
  // hull bounds converge quadratically in the sub-patch size, so the node count grows like
  // 1 / sqrt(tolerance) along the circle: tested at 1e-4 (and one case at 1e-6).
  auto rng = test::seeded_rng();
  const double R = 3.0, r = 1.0;
  const Body torus = make_torus_body(R, r);
  const Distance_hierarchy ht(torus);
  Distance_workspace ws;
  int cases = 0;
  for (int trial = 0; trial < 40 && cases < 8; ++trial) {
    const double rs = std::uniform_real_distribution<double>(0.2, 1.5)(rng);
    const double h = std::uniform_real_distribution<double>(-3.0, 3.0)(rng);
    const double truth = std::sqrt(R * R + h * h) - r - rs;
    if (truth < 1e-2) continue;
    ++cases;
    const Body sphere = make_sphere_body(rs);
    const Distance_hierarchy hs(sphere);
    // The same rigid motion of the pair, and a spin of the sphere about its centre.
    const Rigid_pose_3 X = random_pose(rng, 5.0);
    const Rigid_pose_3 X_WT = X;
    const Rigid_pose_3 spin = random_pose(rng, 0.0);
    const Rigid_pose_3 X_WS = X * translation(0, 0, h) * spin;
    for (double tol : {1e-4, 1e-6}) {
      if (tol < 1e-4 && cases > 1) continue;
      SCOPED_TRACE(::testing::Message() << "rs " << rs << " h " << h << " tol " << tol);
      Distance_request req;
      req.absolute_tolerance = req.relative_tolerance = tol;
      req.max_nodes = 2000000;
      const Distance_result res = extremal_distance(ht, X_WT, hs, X_WS, req, ws);
      expect_certified(res, truth, 1e-13, req, torus, X_WT, sphere, X_WS);
    }
  }
  EXPECT_GE(cases, 6);
}

// Concentric and coaxial bodies reach their distance on a whole sphere, band or circle of equal
// minima, which hull bounds close only quadratically in the sub-patch size everywhere along it
// (each of these spent the default 200,000 nodes short of 1e-9 before the bounds about centres
// and axes of symmetry, algorithms/Symmetry.h). Under random placements of the pair.
TEST(GlobalDistance, ConcentricAndCoaxialBodiesConvergeAtTightTolerance) {
  auto rng = test::seeded_rng();
  std::uniform_real_distribution<double> turn(-k_pi, k_pi);
  struct Case {
    const char* name;
    Body a, b;
    Rigid_pose_3 a_in_b;  // A's placement relative to B's
    double truth;
  };
  const auto spin_z = [](double angle) {
    return Rigid_pose_3(Eigen::AngleAxisd(angle, Vec3::UnitZ()).toRotationMatrix(), Vec3::Zero());
  };
  std::vector<Case> cases;
  cases.push_back({"point at a sphere's centre", make_point_body(), make_sphere_body(2.0),
                   random_pose(rng, 0.0), 2.0});
  cases.push_back({"nested spheres", make_sphere_body(1.0), make_sphere_body(2.5),
                   random_pose(rng, 0.0), 1.5});
  cases.push_back({"shaft in a bore", make_cylinder_body(1.0, 4.0), make_cylinder_body(2.0, 8.0),
                   translation(0, 0, 2) * spin_z(turn(rng)), 1.0});
  cases.push_back({"sphere at a torus' centre", make_sphere_body(1.0), make_torus_body(3.0, 1.0),
                   random_pose(rng, 0.0), 1.0});
  cases.push_back({"point on a cylinder's axis", make_point_body(), make_cylinder_body(1.5, 4.0),
                   translation(0, 0, 1.5), 1.5});
  cases.push_back({"shaft off the bore's axis by 1e-3", make_cylinder_body(1.0, 4.0),
                   make_cylinder_body(2.0, 8.0), translation(1e-3, 0, 2) * spin_z(turn(rng)),
                   1.0 - 1e-3});
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const Rigid_pose_3 X_WB = random_pose(rng, 10.0);
    const Rigid_pose_3 X_WA = X_WB * c.a_in_b;
    Distance_request req;  // 1e-9, 200,000 nodes
    const Distance_result r = extremal_distance(c.a, X_WA, c.b, X_WB, req);
    expect_certified(r, c.truth, 1e-12, req, c.a, X_WA, c.b, X_WB);
    EXPECT_LT(r.nodes_created, 5000);
  }
}

// Kept bounds about a shared axis (a shaft in its bore), re-bounded after motion
// (bound_after_motion): never above the distance sampled on the two moved sub-patches, and
// after a pure turn of the shaft about the axis still the gap between their distance ranges.
TEST(GlobalDistance, BoundsAboutAnAxisOutlastTurnsAboutIt) {
  auto rng = test::seeded_rng();
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const Body bore = make_cylinder_body(2.0, 8.0), shaft = make_cylinder_body(1.0, 4.0);
  const Distance_hierarchy ha(bore), hb(shaft);
  const Rigid_pose_3 X_WA = random_pose(rng, 10.0);
  const Rigid_pose_3 X_WB = X_WA * translation(0, 0, 2);
  Distance_request req;
  internal::Proof_request keep;
  keep.keep_proofs = true;
  Distance_workspace ws;
  const Distance_result r = internal::extremal_distance(ha, X_WA, hb, X_WB, req, keep, ws);
  ASSERT_EQ(r.status, Distance_status::Converged) << to_string(r.status);
  EXPECT_NEAR(r.distance, 1.0, 1e-9);
  std::vector<Bound_proof> kept;
  for (const Bound_proof& p : ws.bound_proofs())
    if (p.symmetry_side >= 0 && p.a_element >= 0 && p.b_element >= 0) kept.push_back(p);
  ASSERT_GE(kept.size(), 10u);
  // A point of element e of side (0 bore, 1 shaft) at the grid point (i, j) of [lo, hi], placed
  // by X (the side's pose, the shaft's after the motion).
  const auto point = [&](int side, int e, const std::array<double, 2>& lo,
                         const std::array<double, 2>& hi, int i, int j, const Rigid_pose_3& X) {
    const Feature& f = (side == 0 ? ha : hb).elements()[e].feature;
    const double u = lo[0] + (hi[0] - lo[0]) * i / 4, v = lo[1] + (hi[1] - lo[1]) * j / 4;
    return X.apply_point(f.surface() ? to_vec3(f.surface()->point(u, v)) : to_vec3(f.curve()->point(u)));
  };
  const Vec3 axis = X_WA.apply_vector(Vec3::UnitZ()), on_axis = X_WA.translation();
  int checked = 0, kept_whole = 0, turns = 0;
  for (int m = 0; m < 24; ++m) {
    // A turn of the shaft about the common axis, then (but for every third motion) a small
    // rigid motion of it of another kind.
    const Rigid_pose_3 about(Eigen::AngleAxisd(0.5 * unit(rng), axis).toRotationMatrix(), Vec3::Zero());
    Rigid_pose_3 motion = translation(on_axis.x(), on_axis.y(), on_axis.z()) * about *
                          translation(-on_axis.x(), -on_axis.y(), -on_axis.z());
    const bool pure = m % 3 == 0;
    if (!pure) {
      const double scale = m % 3 == 1 ? 1e-3 : 0.1;
      const Vec3 w = Vec3(unit(rng), unit(rng), unit(rng)).normalized();
      motion = Rigid_pose_3(Eigen::AngleAxisd(scale * unit(rng), w).toRotationMatrix(),
                            scale * Vec3(unit(rng), unit(rng), unit(rng))) * motion;
    }
    for (const Bound_proof& p : kept) {
      const double bound = bound_after_motion(p, motion, 0.0);
      double sampled = HUGE_VAL;
      for (int a = 0; a < 25; ++a) {
        const Vec3 pa = point(0, p.a_element, p.a_lo, p.a_hi, a / 5, a % 5, X_WA);
        for (int b = 0; b < 25; ++b)
          sampled = std::min(
              sampled, (pa - point(1, p.b_element, p.b_lo, p.b_hi, b / 5, b % 5, motion * X_WB)).norm());
      }
      ASSERT_LE(bound, sampled + 1e-12) << "motion " << m;
      ++checked;
      if (pure) {
        ++turns;
        const double gap = std::max(p.b_range[0] - p.a_range[1], p.a_range[0] - p.b_range[1]);
        if (bound >= gap - 1e-12) ++kept_whole;
      }
    }
  }
  std::printf("[ case     ] %zu bounds about the axis; %d re-bounded, %d of %d after pure turns "
              "whole\n", kept.size(), checked, kept_whole, turns);
  EXPECT_EQ(kept_whole, turns);
}

TEST(GlobalDistance, SphereInTheHoleOfATorusOffTheAxis) {
  // Off the axis the minimum is isolated (plus a worse local minimum across the hole, and
  // saddles): tight tolerances are cheap.
  auto rng = test::seeded_rng();
  const double R = 3.0, r = 1.0;
  const Body torus = make_torus_body(R, r);
  const Distance_hierarchy ht(torus);
  Distance_workspace ws;
  int cases = 0;
  for (int trial = 0; trial < 100 && cases < 20; ++trial) {
    const double rs = std::uniform_real_distribution<double>(0.2, 1.2)(rng);
    const Vec3 c(std::uniform_real_distribution<double>(0.1, 1.5)(rng), 0.0,
                 std::uniform_real_distribution<double>(-2.0, 2.0)(rng));
    const double truth = sphere_torus_distance(c, R, r, rs);
    if (truth < 1e-2) continue;
    ++cases;
    const Body sphere = make_sphere_body(rs);
    const Rigid_pose_3 X = random_pose(rng, 5.0);
    const Rigid_pose_3 turn = Rigid_pose_3::from_quaternion(Vec3::Zero(), std::cos(0.5 * trial),
                                                            0, 0, std::sin(0.5 * trial));
    const Rigid_pose_3 X_WT = X, X_WS = X * turn * translation(c.x(), c.y(), c.z()) *
                                        random_pose(rng, 0.0);
    for (double tol : {1e-6, 1e-12}) {
      SCOPED_TRACE(::testing::Message() << "rs " << rs << " centre " << c.transpose() << " tol "
                                        << tol);
      Distance_request req;
      req.absolute_tolerance = req.relative_tolerance = tol;
      const Distance_result res =
          extremal_distance(ht, X_WT, Distance_hierarchy(sphere), X_WS, req, ws);
      expect_certified(res, truth, 1e-13, req, torus, X_WT, sphere, X_WS);
    }
  }
  EXPECT_GE(cases, 15);
}

// ---- Multi-patch freeform patches against dense sampling + Newton --------------------------

Body random_freeform_body(std::mt19937_64& rng, double z0, int n, bool rational) {
  std::uniform_real_distribution<double> bump(-0.6, 0.6), w(0.5, 2.0);
  std::vector<Point_3> poles;
  std::vector<double> weights;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      poles.emplace_back(4.0 * i / (n - 1) - 2.0 + 0.2 * bump(rng),
                         4.0 * j / (n - 1) - 2.0 + 0.2 * bump(rng), z0 + bump(rng));
      weights.push_back(rational ? w(rng) : 1.0);
    }
  Body b;
  b.name = "freeform";
  b.faces.push_back({make_freeform(3, 3, n, n, std::move(poles), std::move(weights)), "bspline"});
  return b;
}

// Dense sampling of both faces, then Newton from the best samples: an upper bound on the true
// minimum that is usually the minimum itself.
double sampled_minimum(const Body& A, const Rigid_pose_3& X_WA, const Body& B,
                       const Rigid_pose_3& X_WB, int samples) {
  struct Sample {
    Vec3 p;
    double u, v;
  };
  auto sample = [&](const Nurbs_surface_3& s, const Rigid_pose_3& X) {
    std::vector<Sample> out;
    for (int i = 0; i <= samples; ++i)
      for (int j = 0; j <= samples; ++j) {
        const double u = s.u_min() + (s.u_max() - s.u_min()) * i / samples;
        const double v = s.v_min() + (s.v_max() - s.v_min()) * j / samples;
        out.push_back({X.apply_point(to_vec3(s.point(std::min(u, s.u_max()), std::min(v, s.v_max())))),
                       std::min(u, s.u_max()), std::min(v, s.v_max())});
      }
    return out;
  };
  const auto sa = sample(A.faces[0].surface, X_WA);
  const auto sb = sample(B.faces[0].surface, X_WB);
  std::vector<std::pair<double, Vec4>> best;
  for (const auto& a : sa)
    for (const auto& b : sb) {
      const double d = (a.p - b.p).norm();
      if (best.size() < 8 || d < best.back().first) {
        best.push_back({d, Vec4(a.u, a.v, b.u, b.v)});
        std::sort(best.begin(), best.end(),
                  [](const auto& x, const auto& y) { return x.first < y.first; });
        if (best.size() > 8) best.pop_back();
      }
    }
  const Feature fa = Feature::surface(A.faces[0].surface), fb = Feature::surface(B.faces[0].surface);
  double m = best.front().first;
  for (const auto& [d, start] : best) {
    const auto r = solve_pair_at_rest({&fa, &X_WA, nullptr}, {&fb, &X_WB, nullptr}, start);
    Feature_point xa, xb;
    evaluate_feature(fa, X_WA, r.params.data(), xa, 0);
    evaluate_feature(fb, X_WB, r.params.data() + 2, xb, 0);
    m = std::min(m, (xa.p - xb.p).norm());
  }
  return m;
}

TEST(GlobalDistance, FreeformPatchesAgainstDenseSamplingAndNewton) {
  auto rng = test::seeded_rng();
  Distance_workspace ws;
  for (int trial = 0; trial < 12; ++trial) {
    SCOPED_TRACE(::testing::Message() << "trial " << trial);
    const bool rational = trial % 2 == 1;
    const Body A = random_freeform_body(rng, 0.0, 6, rational);   // 3 x 3 Bezier pieces
    const Body B = random_freeform_body(rng, 2.5, 5, !rational);  // 2 x 2
    const Rigid_pose_3 X_WA = random_pose(rng, 0.3);
    // B above A, tilted a little.
    std::normal_distribution<double> g(0.0, 0.15);
    const Rigid_pose_3 X_WB =
        X_WA * Rigid_pose_3::from_quaternion(Vec3(g(rng), g(rng), 0.5), 1.0, g(rng), g(rng), g(rng));
    Distance_request req;
    req.absolute_tolerance = req.relative_tolerance = 1e-10;
    const Distance_result r = extremal_distance(Distance_hierarchy(A), X_WA, Distance_hierarchy(B),
                                                X_WB, req, ws);
    if (r.status == Distance_status::Intersecting || r.status == Distance_status::Touching) {
      EXPECT_EQ(r.distance, 0.0);
      continue;
    }
    ASSERT_EQ(r.status, Distance_status::Converged);
    const double sampled = sampled_minimum(A, X_WA, B, X_WB, 60);
    // The sampled answer is a real pair: the certificate's lower bound cannot exceed it; and
    // our witness is no worse than it beyond the tolerance.
    EXPECT_LE(r.lower_bound, sampled + 1e-12);
    EXPECT_LE(r.upper_bound, sampled + 1e-9);
    EXPECT_LE(r.upper_bound - r.lower_bound, 1e-10 * std::max(1.0, r.upper_bound) + 1e-15);
  }
}

// ---- Derivative enclosures (the convexity certificates' input) ------------------------------

// The hodograph enclosures of a Bezier piece over random sub-boxes hold the point and its first,
// second and third derivatives sampled on the sub-box (third derivatives by central differences
// of the exact second ones): the convex regions around Newton solutions rest on them.
TEST(GlobalDistance, DerivativeEnclosuresHoldSampledDerivativesToThirdOrder) {
  auto rng = test::seeded_rng();
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Body> bodies;
  bodies.push_back(make_torus_body(3.0, 1.0));
  bodies.push_back(make_sphere_body(0.7));
  bodies.push_back(random_freeform_body(rng, 0.0, 6, true));
  int checked = 0;
  for (const Body& body : bodies) {
    const Bezier_patches pieces = extract_bezier(body.faces[0].surface);
    for (int trial = 0; trial < 24; ++trial) {
      const Nurbs_surface_3& piece =
          pieces.patches[std::uniform_int_distribution<std::size_t>(0, pieces.patches.size() - 1)(rng)];
      SCOPED_TRACE(::testing::Message() << body.name << " trial " << trial);
      // A sub-box of relative size 1 down to 1/64 of the piece.
      const double size = std::pow(2.0, -6.0 * unit(rng));
      double s0[2], s1[2], lo[2], hi[2], width[2];
      const double dmin[2] = {piece.u_min(), piece.v_min()}, dmax[2] = {piece.u_max(), piece.v_max()};
      for (int k = 0; k < 2; ++k) {
        s0[k] = (1.0 - size) * unit(rng);
        s1[k] = s0[k] + size;
        lo[k] = dmin[k] + s0[k] * (dmax[k] - dmin[k]);
        hi[k] = dmin[k] + s1[k] * (dmax[k] - dmin[k]);
        width[k] = hi[k] - lo[k];
      }
      auto net = piece.homogeneous_poles();
      const int nu = piece.degree_u() + 1, nv = piece.degree_v() + 1;
      internal::restrict_net(net.data(), nu, nv, s0[0], s1[0], s0[1], s1[1]);
      internal::Derivative_enclosure e;
      ASSERT_TRUE(internal::enclose_piece(net.data(), nu, nv, 2, width, e, 3));
      auto expect_in = [&](const internal::Interval3& box, const Vec3& v, double slack,
                           const char* what) {
        for (int c = 0; c < 3; ++c) {
          EXPECT_GE(v[c], box[c].lo - slack) << what << " component " << c;
          EXPECT_LE(v[c], box[c].hi + slack) << what << " component " << c;
        }
      };
      for (int i = 0; i <= 6; ++i)
        for (int j = 0; j <= 6; ++j) {
          const double u = lo[0] + width[0] * i / 6.0, v = lo[1] + width[1] * j / 6.0;
          Surface_point sp;
          piece.evaluate(u, v, sp, 2);
          const double scale = 1e-9 * (1.0 + sp.p.norm() + sp.duu.norm() + sp.dvv.norm());
          expect_in(e.p, sp.p, scale, "point");
          expect_in(e.d[0], sp.du, scale, "f_u");
          expect_in(e.d[1], sp.dv, scale, "f_v");
          expect_in(e.dd[0][0], sp.duu, scale, "f_uu");
          expect_in(e.dd[0][1], sp.duv, scale, "f_uv");
          expect_in(e.dd[1][1], sp.dvv, scale, "f_vv");
          // Third derivatives: central differences of the second ones, inside the piece.
          const double hu = 1e-4 * width[0], hv = 1e-4 * width[1];
          const double uc = std::clamp(u, lo[0] + hu, hi[0] - hu);
          const double vc = std::clamp(v, lo[1] + hv, hi[1] - hv);
          Surface_point up, um, vp, vm;
          piece.evaluate(uc + hu, vc, up, 2);
          piece.evaluate(uc - hu, vc, um, 2);
          piece.evaluate(uc, vc + hv, vp, 2);
          piece.evaluate(uc, vc - hv, vm, 2);
          const Vec3 fuuu = (up.duu - um.duu) / (2 * hu), fuuv = (vp.duu - vm.duu) / (2 * hv);
          const Vec3 fuvv = (up.dvv - um.dvv) / (2 * hu), fvvv = (vp.dvv - vm.dvv) / (2 * hv);
          const double slack3 = 1e-5 * (1.0 + fuuu.norm() + fuuv.norm() + fuvv.norm() + fvvv.norm());
          expect_in(e.ddd[0][0][0], fuuu, slack3, "f_uuu");
          expect_in(e.ddd[0][0][1], fuuv, slack3, "f_uuv");
          expect_in(e.ddd[1][0][0], fuuv, slack3, "f_uuv (symmetric)");
          expect_in(e.ddd[0][1][1], fuvv, slack3, "f_uvv");
          expect_in(e.ddd[1][1][1], fvvv, slack3, "f_vvv");
          ++checked;
        }
    }
  }
  EXPECT_EQ(checked, 3 * 24 * 49);
}

// ---- Every pair kind ------------------------------------------------------------------------

Body circle_body(double radius) {
  Body b;
  b.name = "circle";
  b.curves.push_back(make_circle(radius));
  return b;
}

struct Kind_case {
  const char* name;
  Body a, b;
  Rigid_pose_3 X_WA, X_WB;
  double truth;
};

std::vector<Kind_case> kind_cases() {
  std::vector<Kind_case> cases;
  const double q = std::sqrt(0.5);
  // Point-surface: a point 5 from the centre of a sphere of radius 2.
  cases.push_back({"point-surface", make_point_body(), make_sphere_body(2.0), translation(3, 4, 0),
                   Rigid_pose_3(), 3.0});
  // Point-curve: a point above a circle of radius 2, at (1, 0, 1): sqrt(1 + 1).
  cases.push_back({"point-curve", make_point_body(), circle_body(2.0), translation(1, 0, 1),
                   Rigid_pose_3(), std::sqrt(2.0)});
  // Curve-surface: a circle of radius 3 around a unit sphere at (1, 0, 1): the distance from the
  // centre to the circle, sqrt(2^2 + 1), less 1. (Centred on the axis, every point of the circle
  // would be nearest: see SphereOnTheAxisOfATorus for such continua.)
  cases.push_back({"curve-surface", circle_body(3.0), make_sphere_body(1.0), Rigid_pose_3(),
                   translation(1, 0, 1), std::sqrt(5.0) - 1.0});
  // Curve-curve: unit circle in z = 0, unit circle in the plane y = 0 centred at (3, 0, 0):
  // nearest points (1, 0, 0) and (2, 0, 0).
  cases.push_back({"curve-curve", circle_body(1.0), circle_body(1.0), Rigid_pose_3(),
                   Rigid_pose_3::from_quaternion(Vec3(3, 0, 0), q, q, 0, 0), 1.0});
  // Point-point.
  cases.push_back({"point-point", make_point_body(), make_point_body(), translation(1, 2, 3),
                   translation(1, 2, 5), 2.0});
  // Surface-surface, multi-face: a sphere above the top cap of a cylinder.
  cases.push_back({"sphere-cylinder cap", make_sphere_body(0.5), make_cylinder_body(1.0, 2.0),
                   translation(0.3, -0.2, 3.0), Rigid_pose_3(), 0.5});
  // Beside the cylinder's side.
  cases.push_back({"sphere-cylinder side", make_sphere_body(0.5), make_cylinder_body(1.0, 2.0),
                   translation(2.0, 1.0, 1.2), Rigid_pose_3(), std::sqrt(5.0) - 1.5});
  // Off the rim: nearest point on the edge circle of the top cap.
  cases.push_back({"sphere-cylinder rim", make_sphere_body(0.5), make_cylinder_body(1.0, 2.0),
                   translation(3.0, 0.0, 4.0), Rigid_pose_3(), std::sqrt(4.0 + 4.0) - 0.5});
  // Plane and sphere.
  cases.push_back({"plane-sphere", make_plane_body(4, 4), make_sphere_body(1.0), Rigid_pose_3(),
                   translation(0.5, 0.5, 2.5), 1.5});
  return cases;
}

TEST(GlobalDistance, EveryPairKindAgainstClosedForms) {
  auto rng = test::seeded_rng();
  for (auto& c : kind_cases()) {
    for (int placement = 0; placement < 4; ++placement) {
      SCOPED_TRACE(::testing::Message() << c.name << " placement " << placement);
      const Rigid_pose_3 X = placement == 0 ? Rigid_pose_3() : random_pose(rng, 10.0);
      const Rigid_pose_3 X_WA = X * c.X_WA, X_WB = X * c.X_WB;
      Distance_request req;
      req.absolute_tolerance = req.relative_tolerance = 1e-11;
      const Distance_result r = extremal_distance(c.a, X_WA, c.b, X_WB, req);
      expect_certified(r, c.truth, 1e-13, req, c.a, X_WA, c.b, X_WB);
      const Distance_result s = extremal_distance(c.b, X_WB, c.a, X_WA, req);
      EXPECT_NEAR(s.distance, r.distance, 2e-11);
      EXPECT_LE((s.normal + r.normal).norm(), 1e-6);
    }
  }
}

// ---- Intersections: exactly zero, with a common point ---------------------------------------

TEST(GlobalDistance, IntersectingBodiesReportZeroAndACommonPoint) {
  auto rng = test::seeded_rng();
  const Body s1 = make_sphere_body(1.0), s2 = make_ellipsoid_body(2.0, 1.0, 0.7);
  const Body torus = make_torus_body(3.0, 1.0), plane = make_plane_body(10, 10);
  const Body cyl = make_cylinder_body(1.0, 2.0);
  struct Case {
    const Body *a, *b;
    Rigid_pose_3 X_WA, X_WB;
  };
  std::vector<Case> cases = {
      {&s1, &s2, translation(0, 0, 0), translation(1.5, 0.2, 0.1)},
      {&s1, &torus, translation(3.0, 0.0, 1.2), Rigid_pose_3()},
      {&plane, &s1, Rigid_pose_3(), translation(0.1, 0.2, 0.3)},
      {&cyl, &s2, Rigid_pose_3(), translation(0.0, 0.0, 2.2)},
  };
  for (std::size_t k = 0; k < cases.size(); ++k) {
    for (int placement = 0; placement < 3; ++placement) {
      SCOPED_TRACE(::testing::Message() << "case " << k << " placement " << placement);
      const Rigid_pose_3 X = placement == 0 ? Rigid_pose_3() : random_pose(rng, 20.0);
      const Rigid_pose_3 X_WA = X * cases[k].X_WA, X_WB = X * cases[k].X_WB;
      const Distance_result r = extremal_distance(*cases[k].a, X_WA, *cases[k].b, X_WB);
      EXPECT_EQ(r.status, Distance_status::Intersecting) << to_string(r.status);
      EXPECT_EQ(r.distance, 0.0);
      EXPECT_EQ(r.lower_bound, 0.0);
      EXPECT_EQ(r.upper_bound, 0.0);
      EXPECT_EQ(r.point_a, r.point_b);
      const double scale = 1.0 + r.point_a.norm();
      EXPECT_LE((element_point(*cases[k].a, X_WA, r.kind_a, r.element_a, r.params_a) - r.point_a).norm(),
                1e-12 * scale);
      EXPECT_LE((element_point(*cases[k].b, X_WB, r.kind_b, r.element_b, r.params_b) - r.point_b).norm(),
                1e-12 * scale);
    }
  }
}

TEST(GlobalDistance, SphereRestingOnAPlaneIsAtZero) {
  const Body plane = make_plane_body(4, 4), s = make_sphere_body(1.0);
  const Distance_result r = extremal_distance(plane, Rigid_pose_3(), s, translation(0.25, 0.5, 1.0));
  EXPECT_TRUE(r.status == Distance_status::Touching || r.status == Distance_status::Intersecting)
      << to_string(r.status);
  EXPECT_EQ(r.distance, 0.0);
  EXPECT_NEAR(r.point_a.z(), 0.0, 1e-12);
}

// ---- Budget, invariance, reuse -------------------------------------------------------------

TEST(GlobalDistance, ExhaustedBudgetKeepsValidBounds) {
  const Vec3 axes_a(3, 2, 1.5), axes_b(2, 1.2, 1);
  const Rigid_pose_3 X_WA = Rigid_pose_3::from_quaternion(Vec3::Zero(), 0.9, 0.1, 0.3, 0.2);
  const Rigid_pose_3 X_WB = Rigid_pose_3::from_quaternion(Vec3(6.5, 1, 0.5), 0.7, 0.2, 0.1, 0.6);
  const auto truth = ellipsoid_distance({X_WA, axes_a}, {X_WB, axes_b});
  Distance_request req;
  req.absolute_tolerance = req.relative_tolerance = 1e-14;
  req.max_nodes = 60;
  req.newton_polish = false;
  const Distance_result r =
      extremal_distance(make_ellipsoid_body(3, 2, 1.5), X_WA, make_ellipsoid_body(2, 1.2, 1), X_WB, req);
  EXPECT_EQ(r.status, Distance_status::Budget_exhausted);
  EXPECT_FALSE(r.is_certified());
  EXPECT_LE(r.lower_bound, truth.upper_bound + 1e-14);
  EXPECT_GE(r.upper_bound, truth.lower_bound - 1e-14);
  EXPECT_LT(r.lower_bound, r.upper_bound);
}

TEST(GlobalDistance, SameMotionOfBothBodiesLeavesTheAnswer) {
  auto rng = test::seeded_rng();
  const Body A = make_torus_body(2.0, 0.5), B = make_cylinder_body(0.7, 1.5);
  const Distance_hierarchy ha(A), hb(B);
  const Rigid_pose_3 X_WA = random_pose(rng, 1.0), X_WB = random_pose(rng, 4.0);
  Distance_request req;
  req.absolute_tolerance = req.relative_tolerance = 1e-11;
  Distance_workspace ws;
  const Distance_result r0 = extremal_distance(ha, X_WA, hb, X_WB, req, ws);
  ASSERT_TRUE(r0.is_certified());
  for (int k = 0; k < 5; ++k) {
    const Rigid_pose_3 X = random_pose(rng, 50.0);
    const Distance_result r = extremal_distance(ha, X * X_WA, hb, X * X_WB, req, ws);
    EXPECT_NEAR(r.distance, r0.distance, 3e-11 * (1 + r0.distance)) << "motion " << k;
    EXPECT_EQ(r.face_a, r0.face_a);
  }
}

TEST(GlobalDistance, WarmWorkspaceQueriesDoNotAllocate) {
  auto rng = test::seeded_rng();
  const Distance_hierarchy ha(make_torus_body(2.0, 0.5)), hb(make_cylinder_body(0.7, 1.5));
  std::vector<std::pair<Rigid_pose_3, Rigid_pose_3>> poses;
  for (int k = 0; k < 10; ++k) poses.emplace_back(random_pose(rng, 1.0), random_pose(rng, 4.0));
  Distance_request req;
  req.absolute_tolerance = req.relative_tolerance = 1e-12;
  Distance_workspace ws;
  for (const auto& [X_WA, X_WB] : poses) (void)extremal_distance(ha, X_WA, hb, X_WB, req, ws);
  const long before = test::g_allocations;
  double sum = 0.0;
  for (const auto& [X_WA, X_WB] : poses) sum += extremal_distance(ha, X_WA, hb, X_WB, req, ws).distance;
  EXPECT_EQ(test::g_allocations - before, 0);
  EXPECT_TRUE(std::isfinite(sum));
}

TEST(GlobalDistance, RejectsEmptyBodiesAndBadRequests) {
  Body empty;
  empty.name = "nothing";
  EXPECT_THROW(Distance_hierarchy h(empty), Invalid_input);
  Distance_request bad;
  bad.absolute_tolerance = -1.0;
  const Body s = make_sphere_body(1.0);
  EXPECT_THROW((void)extremal_distance(s, Rigid_pose_3(), s, translation(3, 0, 0), bad),
               Precondition_violation);
  bad = Distance_request();
  bad.max_nodes = 0;
  EXPECT_THROW((void)extremal_distance(s, Rigid_pose_3(), s, translation(3, 0, 0), bad),
               Precondition_violation);
}

// ---- Trackers: start from the global pair, audits ------------------------------------------

TEST(GlobalDistance, TrackerStartsOnTheGlobalPair) {
  const Body A = make_ellipsoid_body(3, 2, 1.5), B = make_ellipsoid_body(2, 1.2, 1);
  const Rigid_pose_3 X_WA = Rigid_pose_3::from_quaternion(Vec3::Zero(), 0.9, 0.1, 0.3, 0.2);
  const Rigid_pose_3 X_WB = Rigid_pose_3::from_quaternion(Vec3(6.5, 1, 0.5), 0.7, 0.2, 0.1, 0.6);
  const Distance_result g = extremal_distance(A, X_WA, B, X_WB);
  ASSERT_TRUE(g.is_certified());
  const Tracker_seed seed = tracker_seed(A, B, g);
  Extremal_tracker tracker(seed.feature_a, seed.feature_b, seed.params);
  const Track_result& t = tracker.evaluate(0.0, X_WA, X_WB);
  EXPECT_NEAR(t.distance, g.distance, 1e-12);
  EXPECT_LE((t.point_a - g.point_a).norm(), 1e-9);
  const Audit_decision keep = audit_tracked_pair(g, t.distance, seed.kind_a, seed.element_a,
                                                 seed.kind_b, seed.element_b);
  EXPECT_FALSE(keep.reseed);
  EXPECT_TRUE(keep.same_elements);
}

TEST(GlobalDistance, AuditReseedsATrackerStuckOnAnotherFace) {
  // A sphere above the top cap of a cylinder: a tracker on the side face settles on the top rim
  // (a boundary minimum of that face, about 1.08 away), the global minimum is on the cap (1.0).
  const Body cyl = make_cylinder_body(1.0, 2.0), sphere = make_sphere_body(0.5);
  const Rigid_pose_3 X_WC, X_WS = translation(0.5, 0.0, 3.5);
  const Distance_result g = extremal_distance(cyl, X_WC, sphere, X_WS);
  ASSERT_TRUE(g.is_certified());
  EXPECT_EQ(g.face_a, 2);
  EXPECT_NEAR(g.distance, 1.0, 1e-9);
  const Feature side = Feature::surface(cyl.faces[0].surface);
  const Feature fs = Feature::surface(sphere.faces[0].surface);
  Extremal_tracker stuck(side, fs, Vec4(0.1, 0.9, 3.0, -1.0));
  Track_result t;
  for (int k = 0; k < 100; ++k) t = stuck.step(0.01 * k, X_WC, Twist_3(), X_WS, Twist_3(), 0.01);
  ASSERT_GT(t.distance, g.distance + 0.05);  // held on the side face, at or near its rim
  const Audit_decision d = audit_tracked_pair(g, t.distance, Element_kind::Face, 0,
                                              Element_kind::Face, 0);
  EXPECT_TRUE(d.reseed);
  EXPECT_FALSE(d.same_elements);
  EXPECT_NEAR(d.improvement, t.distance - g.distance, 1e-12);
  // The re-seeded tracker holds the global pair.
  const Tracker_seed seed = tracker_seed(cyl, sphere, g);
  Extremal_tracker fresh(seed.feature_a, seed.feature_b, seed.params);
  EXPECT_NEAR(fresh.evaluate(1.0, X_WC, X_WS).distance, 1.0, 1e-9);
}

// ---- The certificate gap never exceeds the tolerance: random shapes and placements ----------

TEST(GlobalDistance, RandomPlacementsKeepTheGapWithinTolerance) {
  auto rng = test::seeded_rng();
  std::vector<Body> bodies;
  bodies.push_back(make_sphere_body(0.8));
  bodies.push_back(make_ellipsoid_body(1.5, 0.7, 0.4));
  bodies.push_back(make_torus_body(1.5, 0.4));
  bodies.push_back(make_cylinder_body(0.6, 1.8));
  bodies.push_back(make_plane_body(2.0, 1.0));
  bodies.push_back(circle_body(1.2));
  bodies.push_back(make_point_body());
  std::vector<Distance_hierarchy> h;
  for (const Body& b : bodies) h.emplace_back(b);
  Distance_workspace ws;
  std::uniform_int_distribution<int> pick(0, static_cast<int>(bodies.size()) - 1);
  std::uniform_int_distribution<int> etol(3, 12);
  for (int trial = 0; trial < 150; ++trial) {
    const int i = pick(rng), j = pick(rng);
    const Rigid_pose_3 X_WA = random_pose(rng, 2.0), X_WB = random_pose(rng, 2.0);
    Distance_request req;
    req.absolute_tolerance = req.relative_tolerance = std::pow(10.0, -etol(rng));
    SCOPED_TRACE(::testing::Message() << "trial " << trial << ": " << i << " vs " << j
                                      << " tolerance " << req.absolute_tolerance);
    const Distance_result r = extremal_distance(h[i], X_WA, h[j], X_WB, req, ws);
    ASSERT_TRUE(r.is_certified()) << to_string(r.status);
    EXPECT_LE(r.lower_bound, r.upper_bound);
    EXPECT_LE(r.upper_bound - r.lower_bound, r.tolerance_used);
    EXPECT_LE(r.tolerance_used, std::max(req.absolute_tolerance,
                                         req.relative_tolerance * r.upper_bound) * (1 + 1e-12) +
                                    1e-13);
    if (r.status == Distance_status::Converged) {
      const double scale = 1.0 + r.point_a.norm();
      EXPECT_LE((element_point(bodies[i], X_WA, r.kind_a, r.element_a, r.params_a) - r.point_a).norm(),
                1e-12 * scale);
      EXPECT_LE((element_point(bodies[j], X_WB, r.kind_b, r.element_b, r.params_b) - r.point_b).norm(),
                1e-12 * scale);
      // Swapping the bodies gives the same distance within both tolerances.
      const Distance_result s = extremal_distance(h[j], X_WB, h[i], X_WA, req, ws);
      EXPECT_NEAR(s.distance, r.distance, r.tolerance_used + s.tolerance_used);
    } else {
      EXPECT_EQ(r.distance, 0.0);
    }
  }
}

}  // namespace
}  // namespace extremal
