// M against central differences of Phi in the parameters, b against differences in time at
// fixed parameters, for every pair kind and several poses and twists.
#include <gtest/gtest.h>

#include <cmath>
#include <Eigen/LU>
#include <Eigen/QR>
#include <memory>
#include <random>
#include <string>

#include "algorithms/pair/Pair_geometry.h"
#include "kernel/Shapes.h"
#include "support/Random.h"

namespace extremal {
namespace {

// Owns the geometry of one side.
struct Side {
  std::string name;
  std::shared_ptr<Nurbs_surface_3> surface;
  std::shared_ptr<Nurbs_curve_3> curve;
  Vec3 point = Vec3::Zero();
  Feature feature() const {
    if (surface) return Feature::surface(*surface);
    if (curve) return Feature::curve(*curve);
    return Feature::point(point);
  }
};

std::vector<Side> sides() {
  std::vector<Side> s;
  s.push_back({"point", nullptr, nullptr, Vec3(0.3, -0.2, 0.1)});
  // A rational cubic curve with an interior knot.
  std::vector<Point_3> cp = {{0, 0, 0}, {1, 2, 0.5}, {2, -1, 1}, {3, 1, -0.5}, {4, 0, 0.3}};
  s.push_back({"curve",
               nullptr,
               std::make_shared<Nurbs_curve_3>(3, cp, std::vector<double>{0, 0, 0, 0, 0.4, 1, 1, 1, 1},
                                               std::vector<double>{1, 0.7, 1.4, 0.9, 1}),
               Vec3::Zero()});
  s.push_back({"ellipsoid", std::make_shared<Nurbs_surface_3>(make_ellipsoid(3, 2, 1.5)), nullptr,
               Vec3::Zero()});
  std::vector<Point_3> grid;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 4; ++j)
      grid.emplace_back(i * 0.8, j * 0.9, 0.3 * std::sin(1.3 * i + 0.7 * j));
  std::vector<double> w;
  for (int k = 0; k < 20; ++k) w.push_back(0.6 + 0.05 * k);
  s.push_back({"freeform", std::make_shared<Nurbs_surface_3>(make_freeform(3, 2, 5, 4, grid, w)),
               nullptr, Vec3::Zero()});
  return s;
}

Rigid_pose_3 random_pose(std::mt19937_64& rng, double spread) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Rigid_pose_3::from_quaternion(Vec3(n(rng), n(rng), n(rng)) * spread, n(rng), n(rng),
                                       n(rng), n(rng));
}

Vec4 random_params(const Feature& a, const Feature& b, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.1, 0.9);
  Vec4 p = Vec4::Zero();
  int k = 0;
  for (const Feature* f : {&a, &b})
    for (int i = 0; i < f->dimension(); ++i, ++k)
      p[k] = f->lower(i) + u(rng) * (f->upper(i) - f->lower(i));
  return p;
}

const Formulation k_forms[3] = {Formulation::Projection, Formulation::Normal_of_a,
                                Formulation::Normal_of_b};

TEST(PairGeometry, JacobianMatchesCentralDifferences) {
  auto rng = test::seeded_rng();
  const auto all = sides();
  int checked = 0;
  for (const auto& sa : all)
    for (const auto& sb : all) {
      const Feature A = sa.feature(), B = sb.feature();
      const int n = A.dimension() + B.dimension();
      if (n == 0) continue;
      for (int trial = 0; trial < 15; ++trial) {
        const Formulation form = k_forms[trial % 3];
        const Rigid_pose_3 XA = random_pose(rng, 2.0), XB = random_pose(rng, 2.0);
        const Vec4 p = random_params(A, B, rng);
        Pair_system s, sp, sm;
        build_pair_system({&A, &XA, nullptr}, {&B, &XB, nullptr}, p, s, false, form);
        for (int k = 0; k < n; ++k) {
          const double h = 1e-6;
          Vec4 pp = p, pm = p;
          pp[k] += h;
          pm[k] -= h;
          build_pair_system({&A, &XA, nullptr}, {&B, &XB, nullptr}, pp, sp, false, form);
          build_pair_system({&A, &XA, nullptr}, {&B, &XB, nullptr}, pm, sm, false, form);
          const Vec4 fd = (sp.phi - sm.phi) / (2 * h);
          for (int r = 0; r < n; ++r) {
            const double scale = 1.0 + s.M.col(k).cwiseAbs().maxCoeff();
            EXPECT_NEAR(s.M(r, k), fd[r], 1e-6 * scale)
                << sa.name << "-" << sb.name << " form " << static_cast<int>(s.form) << " trial "
                << trial << " M(" << r << "," << k << ")";
          }
          ++checked;
        }
        // Padding: unused block is the identity, unused Phi entries zero.
        for (int r = n; r < 4; ++r) {
          EXPECT_EQ(s.phi[r], 0.0);
          EXPECT_EQ(s.M(r, r), 1.0);
        }
      }
    }
  EXPECT_GT(checked, 300);
}

TEST(PairGeometry, NormalFormStaysRegularAtTangentialContact) {
  // Two unit spheres touching at the origin: the projection form loses rank, the normal form
  // does not.
  const Nurbs_surface_3 sphere = make_sphere(1.0);
  const Feature A = Feature::surface(sphere), B = Feature::surface(sphere);
  const Rigid_pose_3 XA(Mat3::Identity(), Vec3(-1, 0, 0)), XB(Mat3::Identity(), Vec3(1, 0, 0));
  // A's point at longitude 0 (+x), B's at longitude pi (-x), both on the equator.
  const Vec4 p(0.0, 0.0, M_PI, 0.0);
  Pair_system proj, normal;
  build_pair_system({&A, &XA, nullptr}, {&B, &XB, nullptr}, p, proj, false);
  build_pair_system({&A, &XA, nullptr}, {&B, &XB, nullptr}, p, normal, false,
                    Formulation::Normal_of_a);
  ASSERT_NEAR(proj.d.norm(), 0.0, 1e-15);
  EXPECT_EQ(normal.form, Formulation::Normal_of_a);
  const double scale = proj.M.cwiseAbs().maxCoeff();
  EXPECT_LT(std::abs(proj.M.determinant()), 1e-12 * std::pow(scale, 4));
  EXPECT_GT(std::abs(normal.M.determinant()), 1e-3 * std::pow(normal.M.cwiseAbs().maxCoeff(), 4));
  EXPECT_NEAR(normal.phi.norm(), 0.0, 1e-15);
}

TEST(PairGeometry, MotionTermMatchesTimeDifferences) {
  auto rng = test::seeded_rng(7);
  std::normal_distribution<double> nd(0.0, 1.0);
  const auto all = sides();
  for (const auto& sa : all)
    for (const auto& sb : all) {
      const Feature A = sa.feature(), B = sb.feature();
      const int n = A.dimension() + B.dimension();
      if (n == 0) continue;
      for (int trial = 0; trial < 15; ++trial) {
        const Formulation form = k_forms[trial % 3];
        const Rigid_pose_3 XA = random_pose(rng, 2.0), XB = random_pose(rng, 2.0);
        Twist_3 VA, VB;
        VA.linear = Vec3(nd(rng), nd(rng), nd(rng));
        VA.angular = Vec3(nd(rng), nd(rng), nd(rng));
        VB.linear = Vec3(nd(rng), nd(rng), nd(rng));
        VB.angular = Vec3(nd(rng), nd(rng), nd(rng));
        if (trial == 0) VA = Twist_3{};  // one side static
        const Vec4 p = random_params(A, B, rng);
        Pair_system s, sp, sm;
        build_pair_system({&A, &XA, &VA}, {&B, &XB, &VB}, p, s, true, form);
        const double h = 1e-6;
        const Rigid_pose_3 XAp = advance(XA, VA, h), XAm = advance(XA, VA, -h);
        const Rigid_pose_3 XBp = advance(XB, VB, h), XBm = advance(XB, VB, -h);
        build_pair_system({&A, &XAp, nullptr}, {&B, &XBp, nullptr}, p, sp, false, form);
        build_pair_system({&A, &XAm, nullptr}, {&B, &XBm, nullptr}, p, sm, false, form);
        const Vec4 fd = (sp.phi - sm.phi) / (2 * h);
        for (int r = 0; r < n; ++r)
          EXPECT_NEAR(s.motion[r], fd[r], 1e-6 * (1.0 + std::abs(fd[r])))
              << sa.name << "-" << sb.name << " form " << static_cast<int>(s.form) << " trial "
              << trial << " b[" << r << "]";
      }
    }
}

TEST(PairGeometry, NewtonAtRestReachesStationaryPair) {
  // Point above a sphere: the closest point is along the ray from the centre.
  const Nurbs_surface_3 sphere = make_sphere(2.0);
  const Feature A = Feature::point(Vec3::Zero()), B = Feature::surface(sphere);
  const Rigid_pose_3 XA(Mat3::Identity(), Vec3(3.0, 1.0, 0.5)), XB;
  const Newton_result r = solve_pair_at_rest({&A, &XA, nullptr}, {&B, &XB, nullptr},
                                             Vec4(0.3, 0.2, 0, 0));
  ASSERT_TRUE(r.converged);
  Pair_system s;
  build_pair_system({&A, &XA, nullptr}, {&B, &XB, nullptr}, r.params, s, false);
  EXPECT_NEAR(s.d.norm(), Vec3(3.0, 1.0, 0.5).norm() - 2.0, 1e-14);
}

TEST(PairGeometry, ConstrainedSolveFreezesParametersPushedOutward) {
  Mat4 M = Mat4::Identity();
  M(0, 1) = 0.5;
  Vec4 x;
  // Parameter 0 on its lower bound with a solution pointing below: frozen.
  ASSERT_TRUE(solve_constrained(M, Vec4(-1.0, 2.0, 0, 0), 2, 0b01, 0b01, x));
  EXPECT_EQ(x[0], 0.0);
  EXPECT_DOUBLE_EQ(x[1], 2.0);
  // Pointing inside: left free.
  ASSERT_TRUE(solve_constrained(M, Vec4(1.0, 0.0, 0, 0), 2, 0b01, 0b01, x));
  EXPECT_DOUBLE_EQ(x[0], 1.0);
  // Singular: reported, x zero.
  EXPECT_FALSE(solve_constrained(Mat4::Zero(), Vec4(1, 1, 1, 1), 4, 0, 0, x));
  EXPECT_TRUE(x.isZero());
}

// Seeking a minimum between two surfaces, the system H x = S rhs (H = S M, S = +1 on A's rows
// and -1 on B's) is solved by 2 x 2 blocks: against a pivoted LU of M, on random positive
// definite H from well to badly conditioned, with S M exactly symmetric or not; an indefinite H
// gets a descent step (shifted), never a step uphill.
TEST(PairGeometry, TwoSurfacesMinimumSolveMatchesTheDirectSolve) {
  auto rng = test::seeded_rng();
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const Vec4 S(1.0, 1.0, -1.0, -1.0);
  for (int trial = 0; trial < 400; ++trial) {
    const Eigen::HouseholderQR<Mat4> qr(Mat4::NullaryExpr([&](Eigen::Index, Eigen::Index) { return unit(rng); }));
    const Mat4 Q = qr.householderQ();
    Vec4 eig;
    const double spread = std::pow(10.0, -(trial % 7));  // condition 1 to 1e6
    for (int k = 0; k < 4; ++k) eig[k] = spread + (1.0 - spread) * std::abs(unit(rng));
    const bool indefinite = trial % 5 == 4;
    if (indefinite) eig[trial % 4] = -eig[trial % 4];
    Mat4 H = Q * eig.asDiagonal() * Q.transpose();
    H = (0.5 * (H + H.transpose())).eval();
    const bool symmetric = trial % 2 == 0;
    Mat4 M = S.asDiagonal() * H;  // M = S H, so S M = H
    if (!symmetric) M += 1e-13 * Mat4::NullaryExpr([&](Eigen::Index, Eigen::Index) { return unit(rng); });
    const Vec4 rhs(unit(rng), unit(rng), unit(rng), unit(rng));
    Solve_mode mode;
    mode.minimum = true;
    mode.na = 2;
    mode.scale = 1.0;
    mode.symmetric = symmetric;
    mode.scaled_shift = true;
    mode.damp_when_b_held = false;
    Vec4 x;
    SCOPED_TRACE(::testing::Message() << "trial " << trial);
    ASSERT_TRUE(solve_constrained(M, rhs, 4, 0, 0, x, mode));
    const Vec4 r = S.cwiseProduct(rhs);  // H x = r
    if (indefinite) {
      EXPECT_GT(x.dot(r), 0.0);  // descent on |d|^2 / 2
      continue;
    }
    const Vec4 direct = M.partialPivLu().solve(rhs);
    EXPECT_LE((x - direct).norm(), 1e-12 / spread * direct.norm()) << x.transpose() << " / " << direct.transpose();
    // The block path itself answers (not the general one after it).
    Vec4 y;
    ASSERT_TRUE(internal::solve_minimum_pd(M, rhs, 2, 4, 1.0, symmetric, y));
    EXPECT_EQ(x, y);
  }
}

}  // namespace
}  // namespace extremal
