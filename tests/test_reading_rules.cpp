// Each reading rule of the body-pair tracker (algorithms/body_pair/internal/Reading_rules.h) on
// synthetic readings: a tracker's reading evaluated at chosen parameters (or with its distance
// set by hand), once where the rule must reject it and once where it must let it hold.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include "algorithms/body_pair/internal/Reading_rules.h"
#include "io/Model_reader.h"
#include "kernel/Shapes.h"

namespace extremal::internal {
namespace {

Rigid_pose_3 at(double x, double y, double z) { return Rigid_pose_3(Mat3::Identity(), Vec3(x, y, z)); }

// The parameters of feature f (posed by X) nearest the world point p: the best of a grid,
// polished by Newton against p.
void params_near(const Feature& f, const Rigid_pose_3& X, const Vec3& p, double* out) {
  const Feature target = Feature::point(p);
  const Rigid_pose_3 identity;
  double best = std::numeric_limits<double>::infinity();
  Vec4 start = Vec4::Zero();
  constexpr int n = 24;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < (f.dimension() == 2 ? n : 1); ++j) {
      double q[2] = {f.lower(0) + (f.upper(0) - f.lower(0)) * (i + 0.5) / n, 0.0};
      if (f.dimension() == 2) q[1] = f.lower(1) + (f.upper(1) - f.lower(1)) * (j + 0.5) / n;
      Feature_point fp;
      evaluate_feature(f, X, q, fp, 0);
      const double d = (fp.p - p).norm();
      if (d < best) best = d, start = Vec4(q[0], q[1], 0.0, 0.0);
    }
  const Newton_result r = solve_pair_at_rest({&f, &X, nullptr}, {&target, &identity, nullptr}, start);
  for (int k = 0; k < f.dimension(); ++k) out[k] = r.params[k];
}

// Two bodies at fixed poses, and readings of their primitive pairs.
struct Pair_at_rest {
  // (The bodies are kept: the models refer to them.)
  Pair_at_rest(Body a, Body b, const Rigid_pose_3& xa, const Rigid_pose_3& xb)
      : body_a(std::move(a)), body_b(std::move(b)), X_WA(xa), X_WB(xb),
        context(std::make_shared<const Tracking_model>(body_a),
                std::make_shared<const Tracking_model>(body_b), Body_pair_options()) {
    context.now.X_WA = &X_WA;
    context.now.X_WB = &X_WB;
    context.now.V_A = context.now.V_B = &still;
    context.now.relative = X_WA.inverse() * X_WB;
    context.now.steps = 1;
  }
  // The first face primitive of a body (side 0 A, 1 B).
  int face(int side) const {
    const auto& p = context.model(side).primitives();
    for (std::size_t k = 0; k < p.size(); ++k)
      if (p[k].kind == Primitive_kind::Face || p[k].kind == Primitive_kind::Triangle)
        return static_cast<int>(k);
    return -1;
  }
  // The reading of pair (pa, pb) with A's witness nearest p_a and B's nearest p_b (world).
  Live reading_near(int pa, int pb, const Vec3& p_a, const Vec3& p_b) {
    const Feature& fa = context.primitive(0, pa).feature;
    const Feature& fb = context.primitive(1, pb).feature;
    Vec4 q = Vec4::Zero();
    params_near(fa, X_WA, p_a, q.data());
    params_near(fb, X_WB, p_b, q.data() + fa.dimension());
    return reading(pa, pb, q);
  }
  Live reading(int pa, int pb, const Vec4& params) {
    Live L;
    L.pa = pa;
    L.pb = pb;
    L.alive = true;
    L.tracker = Extremal_tracker(context.primitive(0, pa).feature, context.primitive(1, pb).feature,
                                 params, context.options.tracker);
    L.result = L.tracker.evaluate(0.0, X_WA, X_WB);
    set_distance(L, L.result.distance);
    return L;
  }
  void set_distance(Live& L, double d) {
    L.result.distance = d;
    L.regime = regime_of(d, context.options.contact_tolerance, L.result.normal_form);
  }
  bool rejects(Reading_rule r, const Live& L) { return rule_rejects(r, L, context); }

  Body body_a, body_b;
  Rigid_pose_3 X_WA, X_WB;
  Twist_3 still;
  Pair_context context;
};

TEST(ReadingRules, TheTableHoldsEveryRuleOnceInOrder) {
  ASSERT_EQ(k_reading_rules.size(), 9u);
  for (std::size_t k = 0; k < k_reading_rules.size(); ++k) {
    EXPECT_EQ(static_cast<int>(k_reading_rules[k].rule), static_cast<int>(k) + 1);
    EXPECT_NE(std::string(to_string(k_reading_rules[k].rule)), "unknown");
  }
  EXPECT_EQ(std::string(to_string(Reading_rule::Depth_not_reached_through_contact)),
            "depth_not_reached_through_contact");
}

TEST(ReadingRules, AWitnessPastItsTriangleIsOffTheFace) {
  Body tri;
  tri.name = "triangle";
  tri.mesh.vertices = {Point_3(0, 0, 0), Point_3(1, 0, 0), Point_3(0, 1, 0)};
  tri.mesh.triangles = {{0, 1, 2}};
  Pair_at_rest p(tri, make_sphere_body(0.2), Rigid_pose_3(), at(0.3, 0.3, 1.0));
  const int pa = p.face(0), pb = p.face(1);
  const Live inside = p.reading(pa, pb, Vec4(0.2, 0.2, 0.5, 0.5));
  const Live past = p.reading(pa, pb, Vec4(0.7, 0.6, 0.5, 0.5));  // u + v > 1
  EXPECT_FALSE(p.rejects(Reading_rule::Witness_off_face, inside));
  EXPECT_TRUE(p.rejects(Reading_rule::Witness_off_face, past));
}

TEST(ReadingRules, ANormalFormReadingAcrossTheOtherFaceIsUnsolved) {
  // Two unit balls 0.01 deep, read in the normal form (set by hand: evaluate() is the
  // projection form) with their normals 30 degrees apart: off contact the reading holds only
  // with d along the reference normal and the other witness its foot; at d = 0 two faces'
  // interior points are a crossing, not a contact.
  Pair_at_rest p(make_sphere_body(1.0), make_sphere_body(1.0), Rigid_pose_3(), at(1.99, 0, 0));
  Live L = p.reading_near(p.face(0), p.face(1), Vec3(1, 0, 0), Vec3(0.99, 0, 0));
  L.result.normal_form = true;
  L.result.alignment_error = 0.5;
  p.set_distance(L, -0.01);
  L.result.reference_error = L.result.other_error = 0.0;
  EXPECT_FALSE(p.rejects(Reading_rule::Normal_form_unsolved, L));
  L.result.reference_error = 0.3;
  EXPECT_TRUE(p.rejects(Reading_rule::Normal_form_unsolved, L));
  L.result.reference_error = 0.0;
  L.result.other_error = 0.3;
  EXPECT_TRUE(p.rejects(Reading_rule::Normal_form_unsolved, L));
  p.set_distance(L, 0.0);  // regular, interior points: a crossing
  L.result.degeneracy = Degeneracy::None;
  L.result.on_edge = 0u;
  EXPECT_TRUE(p.rejects(Reading_rule::Normal_form_unsolved, L));
  L.result.alignment_error = 0.0;  // normals parallel: the conditions hold
  EXPECT_FALSE(p.rejects(Reading_rule::Normal_form_unsolved, L));
}

TEST(ReadingRules, ADeepReadingOffItsPairIsWandering) {
  // Two unit balls 1 deep (past the normal form's band): the facing poles hold; a pair of
  // points off them is no stationary point.
  Pair_at_rest p(make_sphere_body(1.0), make_sphere_body(1.0), Rigid_pose_3(), at(1.0, 0, 0));
  const int pa = p.face(0), pb = p.face(1);
  const Live pair = p.reading_near(pa, pb, Vec3(1, 0, 0), Vec3(0, 0, 0));
  const Live off = p.reading_near(pa, pb, Vec3(std::cos(0.5), std::sin(0.5), 0), Vec3(0, 0, 0));
  ASSERT_EQ(static_cast<int>(pair.regime), static_cast<int>(Regime::Deep));
  ASSERT_EQ(static_cast<int>(off.regime), static_cast<int>(Regime::Deep));
  EXPECT_FALSE(p.rejects(Reading_rule::Wandering_inside, pair));
  EXPECT_TRUE(p.rejects(Reading_rule::Wandering_inside, off));
}

TEST(ReadingRules, FacesTouchingFromWithinHaveTheirNormalsAlike) {
  // A unit ball inside a ball of radius 2, touching it at (2, 0, 0) from within; two unit
  // balls touching from outside have their normals opposed.
  Pair_at_rest within(make_sphere_body(2.0), make_sphere_body(1.0), Rigid_pose_3(), at(1, 0, 0));
  const Live in = within.reading_near(within.face(0), within.face(1), Vec3(2, 0, 0), Vec3(2, 0, 0));
  Pair_at_rest outside(make_sphere_body(1.0), make_sphere_body(1.0), Rigid_pose_3(), at(2, 0, 0));
  const Live out =
      outside.reading_near(outside.face(0), outside.face(1), Vec3(1, 0, 0), Vec3(1, 0, 0));
  ASSERT_LE(std::abs(in.result.distance), 1e-9);
  ASSERT_LE(std::abs(out.result.distance), 1e-9);
  EXPECT_TRUE(within.rejects(Reading_rule::Normals_alike_in_contact, in));
  EXPECT_FALSE(outside.rejects(Reading_rule::Normals_alike_in_contact, out));
}

TEST(ReadingRules, ADepthWhoseNormalsAreAlikeIsNoDepth) {
  // A unit ball at (1.5, 0, 0) half out of a ball of radius 2: the pair (2, 0, 0) on A and
  // (0.5, 0, 0) on B faces each other (normals +x and -x); (-2, 0, 0) with (0.5, 0, 0) has both
  // normals along -x.
  Pair_at_rest p(make_sphere_body(2.0), make_sphere_body(1.0), Rigid_pose_3(), at(1.5, 0, 0));
  const int pa = p.face(0), pb = p.face(1);
  const Live opposed = p.reading_near(pa, pb, Vec3(2, 0, 0), Vec3(0.5, 0, 0));
  const Live alike = p.reading_near(pa, pb, Vec3(-2, 0, 0), Vec3(0.5, 0, 0));
  ASSERT_LT(opposed.result.distance, 0.0);
  ASSERT_LT(alike.result.distance, 0.0);
  EXPECT_FALSE(p.rejects(Reading_rule::Depth_normals_not_opposed, opposed));
  EXPECT_TRUE(p.rejects(Reading_rule::Depth_normals_not_opposed, alike));
}

TEST(ReadingRules, ApartWithAsWitnessInsideBIsNoDistance) {
  // A unit ball inside a ball of radius 3: the pair (1, 0, 0), (3, 0, 0) reads 2 apart along
  // A's normal, but B's normal there points along the gap. Two balls apart: against it.
  Pair_at_rest nested(make_sphere_body(1.0), make_sphere_body(3.0), Rigid_pose_3(), Rigid_pose_3());
  const Live in = nested.reading_near(nested.face(0), nested.face(1), Vec3(1, 0, 0), Vec3(3, 0, 0));
  Pair_at_rest apart(make_sphere_body(1.0), make_sphere_body(1.0), Rigid_pose_3(), at(3, 0, 0));
  const Live out = apart.reading_near(apart.face(0), apart.face(1), Vec3(1, 0, 0), Vec3(2, 0, 0));
  ASSERT_GT(in.result.distance, 1.0);
  ASSERT_GT(out.result.distance, 0.5);
  EXPECT_TRUE(nested.rejects(Reading_rule::Apart_witness_inside, in));
  EXPECT_FALSE(apart.rejects(Reading_rule::Apart_witness_inside, out));
}

TEST(ReadingRules, ADepthBeyondTheBoxesOverlapIsNoDepth) {
  // Two unit balls 0.1 deep along x: their boxes overlap by 0.1 along x, which bounds the depth.
  Pair_at_rest p(make_sphere_body(1.0), make_sphere_body(1.0), Rigid_pose_3(), at(1.9, 0, 0));
  Live L = p.reading_near(p.face(0), p.face(1), Vec3(1, 0, 0), Vec3(0.9, 0, 0));
  p.set_distance(L, -0.09);
  EXPECT_FALSE(p.rejects(Reading_rule::Deeper_than_boxes, L));
  p.set_distance(L, -0.5);
  EXPECT_TRUE(p.rejects(Reading_rule::Deeper_than_boxes, L));
}

TEST(ReadingRules, AnEdgesDepthAgainstAFaceLiesInTheEdgesWedge) {
  // pr2ct's box, [0, 200]^3, and a ball of radius 10 over its top edge along x at y = 0: a
  // depth whose direction is minus the ball's normal lies between the top's normal (+z) and the
  // side's (-y); the ball's witness on its -y side (minus its normal +y) is outside.
  const io::Model box = io::read_model(std::string(EXTREMAL_SHARED_DATA) + "/step/pr2ct.stp");
  Pair_at_rest p(box.bodies.at(0), make_sphere_body(10.0), box.bodies.at(0).placement,
                 at(100, 5, 205));
  int edge = -1;
  double t = 0.0;
  const auto& prims = p.context.model(0).primitives();
  for (std::size_t k = 0; k < prims.size() && edge < 0; ++k) {
    if (prims[k].kind != Primitive_kind::Edge) continue;
    const Feature& f = prims[k].feature;
    double q[1];
    params_near(f, p.X_WA, Vec3(100, 0, 200), q);
    Feature_point fp;
    evaluate_feature(f, p.X_WA, q, fp, 0);
    if ((fp.p - Vec3(100, 0, 200)).norm() < 1e-6) edge = static_cast<int>(k), t = q[0];
  }
  ASSERT_GE(edge, 0) << "no edge of the box through (100, 0, 200)";
  const int ball = p.face(1);
  auto reading = [&](const Vec3& on_ball) {
    Vec4 q(t, 0.0, 0.0, 0.0);
    params_near(p.context.primitive(1, ball).feature, p.X_WB, on_ball, q.data() + 1);
    Live L = p.reading(edge, ball, q);
    p.set_distance(L, -5.0);
    return L;
  };
  const Live down = reading(Vec3(100, 5, 195));  // the ball's bottom: normal -z
  const Live side = reading(Vec3(100, -5, 205));  // its -y side: normal -y, minus it +y
  EXPECT_FALSE(p.rejects(Reading_rule::Edge_outside_wedge, down));
  EXPECT_TRUE(p.rejects(Reading_rule::Edge_outside_wedge, side));
}

TEST(ReadingRules, ADepthCountsOnlyThroughContact) {
  Pair_at_rest p(make_sphere_body(1.0), make_sphere_body(1.0), Rigid_pose_3(), at(1.0, 0, 0));
  Live L = p.reading_near(p.face(0), p.face(1), Vec3(1, 0, 0), Vec3(0, 0, 0));
  L.provenance = Provenance::Unreached;
  EXPECT_TRUE(p.rejects(Reading_rule::Depth_not_reached_through_contact, L));
  L.provenance = Provenance::Through_contact;
  EXPECT_FALSE(p.rejects(Reading_rule::Depth_not_reached_through_contact, L));
  // judge: rejected by this rule alone, the reading would hold but for it.
  L.provenance = Provenance::Unreached;
  judge(L, false, p.context);
  EXPECT_FALSE(L.valid);
  EXPECT_EQ(static_cast<int>(L.rejected_by),
            static_cast<int>(Reading_rule::Depth_not_reached_through_contact));
  EXPECT_TRUE(holds_unreached(L));
  // Behind an open sheet it would not hold even so: not a depth the monitor may take.
  L.provenance = Provenance::Behind_sheet;
  EXPECT_FALSE(holds_unreached(L));
}

TEST(ReadingRules, JudgeNamesTheFirstRuleThatRejects) {
  // Deep and off its pair: wandering (the third rule) rejects it before the last one would.
  Pair_at_rest p(make_sphere_body(1.0), make_sphere_body(1.0), Rigid_pose_3(), at(1.0, 0, 0));
  Live L = p.reading_near(p.face(0), p.face(1), Vec3(std::cos(0.5), std::sin(0.5), 0), Vec3(0, 0, 0));
  judge(L, false, p.context);
  EXPECT_FALSE(L.valid);
  EXPECT_EQ(static_cast<int>(L.rejected_by), static_cast<int>(Reading_rule::Wandering_inside));
  EXPECT_FALSE(holds_unreached(L));
}

}  // namespace
}  // namespace extremal::internal
