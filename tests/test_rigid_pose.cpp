// Rigid poses and twists: quaternion construction, inverse, composition, advance() against the
// closed-form rotation exponential, and transformed() patches, curves and boxes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "kernel/Error.h"
#include "kernel/Rigid_pose_3.h"
#include "kernel/Shapes.h"
#include "tests/support/Nurbs_test_support.h"

namespace extremal {
namespace {

using namespace extremal::test;

Mat3 skew(const Vec3& w) {
  Mat3 K;
  K << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return K;
}

// exp([w]x) by Rodrigues' formula, written out.
Mat3 rotation_exp(const Vec3& rotvec) {
  const double angle = rotvec.norm();
  if (angle == 0.0) return Mat3::Identity();
  const Mat3 K = skew(rotvec / angle);
  return Mat3::Identity() + std::sin(angle) * K + (1 - std::cos(angle)) * K * K;
}

// Rotation matrix of the unit quaternion (w, x, y, z), written out.
Mat3 quaternion_matrix(double w, double x, double y, double z) {
  Mat3 R;
  R << 1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),  //
      2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),   //
      2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y);
  return R;
}

Rigid_pose_3 random_pose(std::mt19937_64& rng) {
  const Vec3 axis = random_vec3(rng).normalized();
  const double angle = uniform(rng, -k_pi, k_pi);
  return Rigid_pose_3(Eigen::AngleAxisd(angle, axis).toRotationMatrix(), random_vec3(rng, -5, 5));
}

double pose_distance(const Rigid_pose_3& a, const Rigid_pose_3& b) {
  return (a.rotation() - b.rotation()).norm() + (a.translation() - b.translation()).norm();
}

double orthonormality_error(const Mat3& R) {
  return (R * R.transpose() - Mat3::Identity()).norm();
}

// ---------------------------------------------------------------------------------------------
// Construction.

TEST(RigidPose, QuaternionKnownRotations) {
  const double c = std::sqrt(0.5);
  // 90 degrees about z: x -> y, y -> -x.
  const Rigid_pose_3 X = Rigid_pose_3::from_quaternion(Vec3(1, 2, 3), c, 0, 0, c);
  EXPECT_LE((X.apply_vector(Vec3::UnitX()) - Vec3::UnitY()).norm(), 1e-15);
  EXPECT_LE((X.apply_vector(Vec3::UnitY()) + Vec3::UnitX()).norm(), 1e-15);
  EXPECT_LE((X.apply_point(Vec3(1, 0, 0)) - Vec3(1, 3, 3)).norm(), 1e-15);
  EXPECT_EQ(X.translation(), Vec3(1, 2, 3));
  // 180 degrees about x: y -> -y, z -> -z.
  const Rigid_pose_3 Y = Rigid_pose_3::from_quaternion(Vec3::Zero(), 0, 1, 0, 0);
  EXPECT_LE((Y.rotation() - Vec3(1, -1, -1).asDiagonal().toDenseMatrix()).norm(), 1e-15);
  // Identity.
  const Rigid_pose_3 I = Rigid_pose_3::from_quaternion(Vec3::Zero(), 1, 0, 0, 0);
  EXPECT_EQ(I.rotation(), Mat3::Identity());
}

TEST(RigidPose, QuaternionIsNormalisedAndMatchesTheClosedForm) {
  EXTREMAL_SEEDED_RNG(rng);
  for (int k = 0; k < 200; ++k) {
    const Eigen::Vector4d q = Eigen::Vector4d(uniform(rng, -1, 1), uniform(rng, -1, 1),
                                              uniform(rng, -1, 1), uniform(rng, -1, 1));
    if (q.norm() < 1e-3) continue;
    const double scale = std::exp(uniform(rng, -10, 10));  // any non-zero length
    const Vec3 t = random_vec3(rng, -10, 10);
    const Rigid_pose_3 X =
        Rigid_pose_3::from_quaternion(t, scale * q[0], scale * q[1], scale * q[2], scale * q[3]);
    const Eigen::Vector4d u = q.normalized();
    EXPECT_LE((X.rotation() - quaternion_matrix(u[0], u[1], u[2], u[3])).norm(), 1e-14);
    EXPECT_LE(orthonormality_error(X.rotation()), 1e-14);
    EXPECT_NEAR(X.rotation().determinant(), 1.0, 1e-14);
    // q and -q are the same rotation; quaternion() gives back +-q.
    const Rigid_pose_3 Y = Rigid_pose_3::from_quaternion(t, -q[0], -q[1], -q[2], -q[3]);
    EXPECT_LE(pose_distance(X, Y), 1e-14);
    const Eigen::Quaterniond back = X.quaternion();
    const Eigen::Vector4d b(back.w(), back.x(), back.y(), back.z());
    EXPECT_LE(std::min((b - u).norm(), (b + u).norm()), 1e-14);
  }
}

TEST(RigidPose, InvalidQuaternionsAndRotationsThrow) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  auto expect_invalid = [](auto make, const std::string& words) {
    try {
      make();
      ADD_FAILURE() << "no exception; expected one mentioning \"" << words << "\"";
    } catch (const Invalid_input& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  const std::string q_words = "quaternion must be finite and non-zero";
  expect_invalid([] { Rigid_pose_3::from_quaternion(Vec3::Zero(), 0, 0, 0, 0); }, q_words);
  expect_invalid([] { Rigid_pose_3::from_quaternion(Vec3::Zero(), 1e-13, 0, 0, 0); }, q_words);
  expect_invalid([&] { Rigid_pose_3::from_quaternion(Vec3::Zero(), nan, 0, 0, 1); }, q_words);
  expect_invalid([&] { Rigid_pose_3::from_quaternion(Vec3::Zero(), 1, inf, 0, 0); }, q_words);
  expect_invalid([&] { Rigid_pose_3::from_quaternion(Vec3(0, nan, 0), 1, 0, 0, 0); },
                 "not finite");
  expect_invalid([] { Rigid_pose_3(2.0 * Mat3::Identity(), Vec3::Zero()); },
                 "not a proper orthonormal matrix");
  expect_invalid([] { Rigid_pose_3(Vec3(1, 1, -1).asDiagonal().toDenseMatrix(), Vec3::Zero()); },
                 "not a proper orthonormal matrix");  // a reflection
  Mat3 sheared = Mat3::Identity();
  sheared(0, 1) = 1e-6;
  expect_invalid([&] { Rigid_pose_3(sheared, Vec3::Zero()); }, "not a proper orthonormal");
  Mat3 with_nan = Mat3::Identity();
  with_nan(2, 2) = nan;
  expect_invalid([&] { Rigid_pose_3(with_nan, Vec3::Zero()); }, "not finite");
  expect_invalid([&] { Rigid_pose_3(Mat3::Identity(), Vec3(inf, 0, 0)); }, "not finite");
}

// ---------------------------------------------------------------------------------------------
// Inverse and composition.

TEST(RigidPose, InverseAndComposition) {
  EXTREMAL_SEEDED_RNG(rng);
  const Rigid_pose_3 I;
  for (int k = 0; k < 100; ++k) {
    const Rigid_pose_3 A = random_pose(rng), B = random_pose(rng), C = random_pose(rng);
    EXPECT_LE(pose_distance(A * A.inverse(), I), 1e-13);
    EXPECT_LE(pose_distance(A.inverse() * A, I), 1e-13);
    EXPECT_LE(pose_distance(A.inverse().inverse(), A), 1e-13);
    EXPECT_LE(pose_distance((A * B) * C, A * (B * C)), 1e-13);
    EXPECT_LE(pose_distance((A * B).inverse(), B.inverse() * A.inverse()), 1e-13);
    EXPECT_LE(pose_distance(A * I, A), 0.0);
    const Vec3 p = random_vec3(rng, -3, 3), v = random_vec3(rng);
    // X_WA * X_AB maps B's frame to the world: apply B first, then A.
    EXPECT_LE(((A * B).apply_point(p) - A.apply_point(B.apply_point(p))).norm(), 1e-13);
    EXPECT_LE((A.inverse().apply_point(A.apply_point(p)) - p).norm(), 1e-13);
    // Vectors rotate and do not translate.
    EXPECT_LE((A.apply_vector(v) - A.rotation() * v).norm(), 0.0);
    EXPECT_LE((A.apply_point(p) - A.apply_point(Vec3::Zero()) - A.apply_vector(p)).norm(), 1e-13);
    // The CGAL overloads agree with the Eigen ones.
    EXPECT_LE((to_vec3(A(to_point(p))) - A.apply_point(p)).norm(), 0.0);
    EXPECT_LE((to_vec3(A(to_vector(v))) - A.apply_vector(v)).norm(), 0.0);
    // A composed pose is still a valid one (the constructor's check would throw).
    EXPECT_NO_THROW(Rigid_pose_3((A * B * C).rotation(), (A * B * C).translation()));
  }
}

// ---------------------------------------------------------------------------------------------
// Motion.

TEST(Advance, MatchesTheClosedFormRotationExponential) {
  EXTREMAL_SEEDED_RNG(rng);
  for (int k = 0; k < 200; ++k) {
    const Rigid_pose_3 X = random_pose(rng);
    Twist_3 tw;
    tw.linear = random_vec3(rng, -2, 2);
    tw.angular = random_vec3(rng, -3, 3);
    // Small, ordinary and large steps (angles beyond pi and several turns), and backwards.
    for (double dt : {1e-9, 1e-3, 0.1, 1.0, 2.5, 10.0, -0.7}) {
      const Rigid_pose_3 Y = advance(X, tw, dt);
      const Mat3 R = rotation_exp(tw.angular * dt) * X.rotation();
      EXPECT_LE((Y.rotation() - R).norm(), 1e-13) << "dt = " << dt;
      EXPECT_LE((Y.translation() - (X.translation() + tw.linear * dt)).norm(), 1e-13);
      EXPECT_LE(orthonormality_error(Y.rotation()), 1e-14);
    }
    // A constant twist: two steps make one.
    EXPECT_LE(pose_distance(advance(advance(X, tw, 0.3), tw, 0.45), advance(X, tw, 0.75)), 1e-13);
  }
  // No motion, no change.
  const Rigid_pose_3 X = random_pose(rng);
  const Twist_3 still;
  EXPECT_TRUE(still.is_zero());
  EXPECT_LE(pose_distance(advance(X, still, 5.0), X), 1e-14);
  // Pure rotation of a quarter turn about z at the origin.
  Twist_3 spin;
  spin.angular = Vec3(0, 0, k_pi / 2);
  EXPECT_FALSE(spin.is_zero());
  const Rigid_pose_3 Q = advance(Rigid_pose_3(), spin, 1.0);
  EXPECT_LE((Q.apply_vector(Vec3::UnitX()) - Vec3::UnitY()).norm(), 1e-15);
}

TEST(Advance, ManySmallStepsStayOnSO3) {
  Twist_3 tw;
  tw.linear = Vec3(0.1, -0.2, 0.3);
  tw.angular = Vec3(0.4, 1.3, -0.7);
  Rigid_pose_3 X;
  const int steps = 100000;
  const double dt = 1e-3;
  for (int i = 0; i < steps; ++i) X = advance(X, tw, dt);
  EXPECT_LE(orthonormality_error(X.rotation()), 1e-14);
  // The same rotation as one step of the whole time (round-off accumulates over 1e5 steps).
  EXPECT_LE((X.rotation() - rotation_exp(tw.angular * (steps * dt))).norm(), 1e-10);
  EXPECT_LE((X.translation() - tw.linear * (steps * dt)).norm(), 1e-9);
}

TEST(Twist, VelocityAtIsTheTimeDerivativeOfAdvance) {
  EXTREMAL_SEEDED_RNG(rng);
  for (int k = 0; k < 50; ++k) {
    const Rigid_pose_3 X_WA = random_pose(rng);
    Twist_3 tw;
    tw.linear = random_vec3(rng, -2, 2);
    tw.angular = random_vec3(rng, -3, 3);
    const Vec3 p_A = random_vec3(rng, -2, 2);
    const Vec3 p_W = X_WA.apply_point(p_A);
    const double h = 1e-4;
    const Vec3 fd = (advance(X_WA, tw, h).apply_point(p_A) - advance(X_WA, tw, -h).apply_point(p_A)) /
                    (2 * h);
    const Vec3 v = tw.velocity_at(p_W, X_WA);
    EXPECT_LE((fd - v).norm(), 1e-6 * (1 + v.norm()));
  }
}

// ---------------------------------------------------------------------------------------------
// Transformed patches, curves and boxes.

void expect_transformed_surface(const Nurbs_surface_3& s, const Rigid_pose_3& X) {
  const Nurbs_surface_3 t = transformed(s, X);
  EXPECT_EQ(t.knots_u(), s.knots_u());
  EXPECT_EQ(t.knots_v(), s.knots_v());
  EXPECT_EQ(t.weights(), s.weights());
  EXPECT_EQ(t.outward_sign(), s.outward_sign());
  EXPECT_EQ(t.is_closed_u(), s.is_closed_u());
  EXPECT_EQ(t.is_closed_v(), s.is_closed_v());
  const Bbox_3 box = s.hull_bbox(), moved_box = transformed(box, X), t_box = t.hull_bbox();
  const double reach = std::max({std::abs(box.xmin()), std::abs(box.xmax()), std::abs(box.ymin()),
                                 std::abs(box.ymax()), std::abs(box.zmin()), std::abs(box.zmax())});
  const double size = bbox_size(box) + reach + X.translation().norm();
  const double slack = 8 * k_eps * size;
  // The hull box of the transformed patch lies in the transformed hull box.
  EXPECT_TRUE(t_box.xmin() >= moved_box.xmin() - slack && t_box.xmax() <= moved_box.xmax() + slack &&
              t_box.ymin() >= moved_box.ymin() - slack && t_box.ymax() <= moved_box.ymax() + slack &&
              t_box.zmin() >= moved_box.zmin() - slack && t_box.zmax() <= moved_box.zmax() + slack)
      << t_box << " not inside " << moved_box;
  Surface_point a, b;
  const int grid = 24;
  for (int i = 0; i <= grid; ++i)
    for (int j = 0; j <= grid; ++j) {
      const double u = std::min(s.u_max(), s.u_min() + (s.u_max() - s.u_min()) * i / grid);
      const double v = std::min(s.v_max(), s.v_min() + (s.v_max() - s.v_min()) * j / grid);
      s.evaluate(u, v, a, 2);
      t.evaluate(u, v, b, 2);
      ASSERT_LE((b.p - X.apply_point(a.p)).norm(), 1e-14 * size) << "u = " << u << ", v = " << v;
      const double d = 1e-13 * (size + a.du.norm() + a.dv.norm() + a.duu.norm() + a.dvv.norm());
      EXPECT_LE((b.du - X.apply_vector(a.du)).norm(), d);
      EXPECT_LE((b.dv - X.apply_vector(a.dv)).norm(), d);
      EXPECT_LE((b.duu - X.apply_vector(a.duu)).norm(), d);
      EXPECT_LE((b.duv - X.apply_vector(a.duv)).norm(), d);
      EXPECT_LE((b.dvv - X.apply_vector(a.dvv)).norm(), d);
      const Vec3 n = s.outward_normal(a);
      if (n != Vec3::Zero()) {
        EXPECT_LE((t.outward_normal(b) - X.apply_vector(n)).norm(), 1e-9)
            << "u = " << u << ", v = " << v;
      }
      ASSERT_TRUE(box_contains(moved_box, b.p, slack));
      ASSERT_TRUE(box_contains(t_box, b.p, slack));
    }
}

TEST(Transformed, PatchesMoveRigidly) {
  EXTREMAL_SEEDED_RNG(rng);
  std::vector<Point_3> poles;
  for (int k = 0; k < 20; ++k) poles.push_back(to_point(random_vec3(rng)));
  std::vector<double> weights;
  for (int k = 0; k < 20; ++k) weights.push_back(uniform(rng, 0.2, 5.0));
  const std::vector<Nurbs_surface_3> shapes = {
      make_sphere(1.0),          make_ellipsoid(3, 2, 1.5),  make_torus(3, 1),
      make_cylinder_side(1, 2),  make_disk(1, 0.5, false),   make_plane(2, 1),
      make_freeform(3, 2, 5, 4, poles, weights)};
  for (int k = 0; k < 10; ++k) {
    const Rigid_pose_3 X = random_pose(rng);
    for (const auto& s : shapes) {
      expect_transformed_surface(s, X);
      if (HasFailure()) return;
    }
  }
}

TEST(Transformed, CurvesMoveRigidly) {
  EXTREMAL_SEEDED_RNG(rng);
  const Nurbs_curve_3 c = make_circle(2.0);
  for (int k = 0; k < 10; ++k) {
    const Rigid_pose_3 X = random_pose(rng);
    const Nurbs_curve_3 t = transformed(c, X);
    EXPECT_EQ(t.knots(), c.knots());
    EXPECT_EQ(t.weights(), c.weights());
    EXPECT_EQ(t.is_closed(), c.is_closed());
    Curve_point a, b;
    for (int i = 0; i <= 100; ++i) {
      const double s = std::min(c.domain_max(), c.domain_max() * i / 100);
      c.evaluate(s, a, 2);
      t.evaluate(s, b, 2);
      EXPECT_LE((b.p - X.apply_point(a.p)).norm(), 1e-14 * 10);
      EXPECT_LE((b.d1 - X.apply_vector(a.d1)).norm(), 1e-13 * 10);
      EXPECT_LE((b.d2 - X.apply_vector(a.d2)).norm(), 1e-13 * 10);
      // Still a circle of radius 2 about the moved centre.
      EXPECT_NEAR((b.p - X.translation()).norm(), 2.0, 1e-14 * 10);
    }
  }
}

TEST(Transformed, Boxes) {
  EXTREMAL_SEEDED_RNG(rng);
  const Bbox_3 box(-1, -2, -3, 4, 5, 6);
  EXPECT_EQ(transformed(box, Rigid_pose_3()), box);
  // A quarter turn about z maps the box onto a box exactly (up to rounding of sin/cos).
  const double c = std::sqrt(0.5);
  const Bbox_3 q = transformed(box, Rigid_pose_3::from_quaternion(Vec3(10, 0, 0), c, 0, 0, c));
  const Bbox_3 want(10 - 5, -1, -3, 10 + 2, 4, 6);
  EXPECT_NEAR(q.xmin(), want.xmin(), 1e-14 * 10);
  EXPECT_NEAR(q.xmax(), want.xmax(), 1e-14 * 10);
  EXPECT_NEAR(q.ymin(), want.ymin(), 1e-14 * 10);
  EXPECT_NEAR(q.ymax(), want.ymax(), 1e-14 * 10);
  EXPECT_NEAR(q.zmin(), want.zmin(), 1e-14 * 10);
  EXPECT_NEAR(q.zmax(), want.zmax(), 1e-14 * 10);
  // Any point of the box, moved, lies in the moved box, and so do the eight moved corners.
  for (int k = 0; k < 50; ++k) {
    const Rigid_pose_3 X = random_pose(rng);
    const Bbox_3 m = transformed(box, X);
    const double slack = 1e-14 * 20;
    for (int i = 0; i < 200; ++i) {
      const Vec3 p(uniform(rng, box.xmin(), box.xmax()), uniform(rng, box.ymin(), box.ymax()),
                   uniform(rng, box.zmin(), box.zmax()));
      ASSERT_TRUE(box_contains(m, X.apply_point(p), slack));
    }
    for (int corner = 0; corner < 8; ++corner) {
      const Vec3 p((corner & 1) ? box.xmax() : box.xmin(), (corner & 2) ? box.ymax() : box.ymin(),
                   (corner & 4) ? box.zmax() : box.zmin());
      ASSERT_TRUE(box_contains(m, X.apply_point(p), 0.0));
    }
  }
}

}  // namespace
}  // namespace extremal
