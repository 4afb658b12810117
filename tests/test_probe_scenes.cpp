// Wrong rows found by random probe scenes (scripts/probe-scenes.py, checked row by row by
// bench/verify_report against the certified signed distance), each kept as the motion that
// showed it. Every row is checked the way verify_report checks it: where the reference finds
// the bodies apart, the reading agrees with it; where it finds them overlapping, the reading
// is not apart.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "algorithms/body_pair/Body_pair_tracker.h"
#include "algorithms/distance/Penetration_depth.h"
#include "io/Model_reader.h"
#include "kernel/Motion.h"
#include "kernel/Shapes.h"

namespace extremal {
namespace {

std::string shared_data(const std::string& rel) { return std::string(EXTREMAL_SHARED_DATA) + "/" + rel; }

// pr2ct's box: a 200 mm cube from a STEP file, [0, 200]^3.
const Body& box() {
  static const io::Model m = io::read_model(shared_data("step/pr2ct.stp"));
  return m.bodies.at(0);
}

// A motion through rows {t, x, y, z, qw, qx, qy, qz}, as a scene's keyframes (or, `type`
// Table, its pose table) give them.
Motion keyframes_of(const std::vector<std::array<double, 8>>& rows,
                    Motion::Type type = Motion::Type::Keyframes) {
  std::vector<Keyframe> frames;
  for (const auto& r : rows)
    frames.push_back({r[0], Rigid_pose_3::from_quaternion(Vec3(r[1], r[2], r[3]), r[4], r[5], r[6], r[7])});
  return Motion::keyframes(frames, type);
}

struct Probe_run {
  int apart_rows = 0, overlapping_rows = 0;
  int read_apart_while_overlapping = 0;
  double worst_apart = 0.0;  // |reported - reference| over the rows the reference finds apart
};

// A (static at X_WA) against B moving by `motion`, at steps of dt from t0 to t1, each row
// against signed_distance at the same poses.
Probe_run run_probe(const Body& a, const Rigid_pose_3& X_WA, const Body& b, const Motion& motion,
                    double t0, double t1, double dt) {
  Body_pair_tracker tracker(a, b);
  Probe_run run;
  const int steps = static_cast<int>(std::lround((t1 - t0) / dt));
  for (int i = 0; i <= steps; ++i) {
    const double t = t0 + i * dt;
    const Rigid_pose_3 X_WB = motion.pose_at(t);
    const Pair_report& r = tracker.step(t, X_WA, Twist_3{}, X_WB, motion.twist_at(t), dt);
    EXPECT_TRUE(std::isfinite(r.distance)) << "t = " << t;
    const Signed_distance_result ref = signed_distance(a, X_WA, b, X_WB);
    if (!ref.is_certified()) continue;
    if (ref.overlap == Overlap_kind::None) {
      ++run.apart_rows;
      run.worst_apart = std::max(run.worst_apart, std::abs(r.distance - ref.distance));
    } else {
      ++run.overlapping_rows;
      if (r.distance > 1e-9) {
        ++run.read_apart_while_overlapping;
        ADD_FAILURE() << "t = " << t << ": read " << r.distance << " apart, the reference "
                      << ref.distance << " (" << to_string(ref.overlap) << ")";
      }
    }
  }
  return run;
}

// A box (tilted 0.6 rad about x) started across a plane's border and slid along it: the first
// row read +21, the hulls' depth with the sheet's sign, where the bodies overlap by 21 (the
// start's trackers all read apart; the solver's answer is the row now).
TEST(ProbeScenes, ABoxStartedAcrossASheetsBorderIsNotApart) {
  const Body plane = make_plane_body(260.0, 154.0);
  const Rigid_pose_3 start = Rigid_pose_3::from_quaternion(
      Vec3(-300.0, 120.0, -100.0), std::cos(0.3), std::sin(0.3), 0.0, 0.0);
  Twist_3 v;
  v.linear = Vec3(300.0, 0.0, 0.0);
  const Probe_run run = run_probe(plane, Rigid_pose_3(), box(), Motion::twist(start, v, 0.0), 0.0,
                                  0.6, 0.04);
  EXPECT_EQ(run.read_apart_while_overlapping, 0);
  EXPECT_GT(run.overlapping_rows, 5);
  EXPECT_LE(run.worst_apart, 1e-8);
}

// scripts/probe-scenes.py --seed 2, scene 8: a turning box clipping a plane's border and
// leaving past it (its poses from t = 1.16 to 1.52, the table rows). Out of the plane's reach
// its tracker, in the normal form's band, read -10, -19 and -28 while 2, 10 and 18 apart. The
// sheet's witness lay outside the box's box: the deep check's certified solve runs there.
TEST(ProbeScenes, ABoxLeavingPastASheetsBorderIsApart) {
  const Body plane = make_plane_body(259.7262790649645, 153.75553834888387);
  const Rigid_pose_3 X_WA = Rigid_pose_3::from_quaternion(
      Vec3::Zero(), 0.9723639018842275, 0.011918892800132485, -0.15044956393674852,
      -0.1781328465447669);
  const std::vector<std::array<double, 8>> rows = {
      {1.16, 127.29992439956686, 178.4805782617081, -64.08620227056056, 0.393530607272596,
       0.19712005305921718, -0.8187492977907426, -0.3686826998772245},
      {1.2, 114.79207335881827, 186.47196170238527, -78.59249347252216, 0.3962426542391616,
       0.19706341796166682, -0.8191726996890991, -0.36484771665291127},
      {1.24, 102.2840402379282, 194.46335851219388, -93.09908694093268, 0.39894588687831356,
       0.1970023992333575, -0.8195778792777015, -0.3610046174744061},
      {1.28, 89.77582418413641, 202.45476549495987, -107.60598228511594, 0.40164024505725887,
       0.1969369982316368, -0.8199648275434223, -0.35715348783057327},
      {1.32, 77.26742436095952, 210.4461794536041, -122.1131790875352, 0.4043256688406146,
       0.19686721641133512, -0.8203335358786855, -0.35329441338891265},
      {1.36, 64.758839948266, 218.43759719042671, -136.6206769038302, 0.4070020984917416,
       0.19679305532473315, -0.8206839960816584, -0.3494274799936545},
      {1.4, 52.25007014234839, 226.42901550739174, -151.12847526285714, 0.40966947447407315,
       0.19671451662152725, -0.8210162003564339, -0.34555277366384973},
      {1.44, 39.741114155995945, 234.42043120641134, -165.63657366673027, 0.41232773745243917,
       0.19663160204879304, -0.8213301413132038, -0.3416703805914565},
      {1.48, 27.231971218563018, 242.41184108963114, -180.14497159086613, 0.4149768282943864,
       0.19654431345094625, -0.8216258119684225, -0.33778038713942243},
      {1.52, 14.722640576039566, 250.4032419597138, -194.6536684840307, 0.41761668807149366,
       0.19645265276970186, -0.8219032057449647, -0.3338828798397643}};
  const Motion motion = keyframes_of(rows, Motion::Type::Table);
  const Probe_run run = run_probe(plane, X_WA, box(), motion, 1.16, 1.52, 0.04);
  EXPECT_EQ(run.read_apart_while_overlapping, 0);
  EXPECT_GE(run.apart_rows, 5);
  EXPECT_GE(run.overlapping_rows, 2);
  EXPECT_LE(run.worst_apart, 1e-6);
}

// scripts/probe-scenes.py --seed 4 --files-only, scene 22: OCC26308-Face.stp's sheet (A,
// static) with linkrods.step (B) passing through it and leaving it behind (poses from t = 1.08
// to 1.28, the table rows). Once out, the pair holding the minimum read minus its distance
// (the sheet's normal points towards the rods) and held nothing; another, 0.16 farther, was
// reported. A sheet has no inside: the solid's normal says apart.
TEST(ProbeScenes, ASolidLeftBehindASheetIsApart) {
  const io::Model sheet = io::read_model(shared_data("step/OCC26308-Face.stp"));
  const io::Model rods = io::read_model(shared_data("step/linkrods.step"));
  const Rigid_pose_3 X_WA =
      Rigid_pose_3::from_quaternion(Vec3(1661.6288744351295, -789.5754570618766, 735.2243418565573),
                                    0.21512292210556952, -0.07840289961895039,
                                    0.40138812975291893, 0.8868273129587043) *
      sheet.bodies.at(0).placement;
  const std::vector<std::array<double, 8>> rows = {
      {1.08, 2.833413791339971, -3.140800725326649, -8.95685422692118, 0.6378428463913881,
       0.43606266360134627, 0.5473529552847413, 0.32157518415028763},
      {1.12, 3.6361233308745375, -0.31293144637548576, -9.556354210515696, 0.6292393697316897,
       0.44263014313658855, 0.5557336307554902, 0.31511347735993395},
      {1.16, 4.4403125211061445, 2.5148568292679627, -10.15483908980724, 0.6204917085498878,
       0.4490961979696796, 0.563986964880764, 0.30857956516043533},
      {1.2, 5.246010892032923, 5.342556837646892, -10.752353944879296, 0.6116018672935861,
       0.45545934646251673, 0.5721110664835424, 0.3019749447387977},
      {1.24, 6.053246590471685, 8.170161395702376, -11.348944744853599, 0.6025718829896695,
       0.4617181305570559, 0.58010407399927, 0.29530112948417775},
      {1.28, 6.862046354261065, 10.997663407856802, -11.944658305758887, 0.5934038247775372,
       0.4678711161094134, 0.5879641559024195, 0.2885596486411037}};
  std::vector<Keyframe> frames;
  for (const auto& r : rows)
    frames.push_back({r[0], Rigid_pose_3::from_quaternion(Vec3(r[1], r[2], r[3]), r[4], r[5],
                                                          r[6], r[7]) *
                                rods.bodies.at(0).placement});
  const Motion motion = Motion::keyframes(frames, Motion::Type::Table);
  const Probe_run run =
      run_probe(sheet.bodies.at(0), X_WA, rods.bodies.at(0), motion, 1.08, 1.28, 0.04);
  EXPECT_EQ(run.read_apart_while_overlapping, 0);
  EXPECT_GE(run.apart_rows, 3);
  EXPECT_GE(run.overlapping_rows, 1);
  EXPECT_LE(run.worst_apart, 1e-8);
}

// screw.step (B, tilted 1.2 rad about x) pushed down through a plane (A) and out below it.
// Inside, a shallower pair (the tip's) took over from the deepest, whose level then held the
// deep check back: once out, the tip's stale pair read -16 to -20 while 0.7 to 4.3 apart. The
// step after the check's solve, its trackers read the pair behind the plane and held nothing,
// and that solve's 0.68 was reported again where the screw was 1.88 apart.
TEST(ProbeScenes, AScrewPushedThroughAPlaneIsApartOnceOut) {
  static const io::Model screw = io::read_model(shared_data("step/screw.step"));
  const Body plane = make_plane_body(100.0, 100.0);
  const Rigid_pose_3 start = Rigid_pose_3::from_quaternion(
      Vec3(17.9, -12.199437548379493, 65.60122517876121), std::cos(0.6), std::sin(0.6), 0.0, 0.0);
  Twist_3 v;
  v.linear = Vec3(0.0, 0.0, -60.0);
  const Probe_run run = run_probe(plane, Rigid_pose_3(), screw.bodies.at(0),
                                  Motion::twist(start * screw.bodies.at(0).placement, v, 0.0),
                                  0.0, 2.0, 0.02);
  EXPECT_EQ(run.read_apart_while_overlapping, 0);
  EXPECT_GE(run.apart_rows, 70);
  EXPECT_GE(run.overlapping_rows, 20);
  EXPECT_LE(run.worst_apart, 1e-8);
}

// screw.step (B, tilted 1.2 or 2 rad about x) through a plane (A) and out past its border while
// below it (moving at 40 across and 60 down). Past the border, at t = 1.1 and 1.22 to 1.24,
// the pair the certified solve found apart was read behind the plane (the screw's witness on
// an edge, the sign the sheet's) and held nothing, and a farther pair was reported: 9.49 and
// 6.12 to 7.56, uncertified, where the screw was 0.33 and 0.25 to 1.45 away.
TEST(ProbeScenes, ASolidThroughASheetAndOutPastItsBorderIsApart) {
  static const io::Model screw = io::read_model(shared_data("step/screw.step"));
  const Body plane = make_plane_body(100.0, 100.0);
  for (const double turn : {0.6, 1.0}) {
    const Rigid_pose_3 start = Rigid_pose_3::from_quaternion(
        Vec3(17.9, -12.5, 55.15), std::cos(turn), std::sin(turn), 0.0, 0.0);
    Twist_3 v;
    v.linear = Vec3(40.0, 0.0, -60.0);
    const Probe_run run = run_probe(plane, Rigid_pose_3(), screw.bodies.at(0),
                                    Motion::twist(start * screw.bodies.at(0).placement, v, 0.0),
                                    0.0, 2.0, 0.02);
    EXPECT_EQ(run.read_apart_while_overlapping, 0);
    EXPECT_GE(run.apart_rows, 70);
    EXPECT_GE(run.overlapping_rows, 20);
    EXPECT_LE(run.worst_apart, 1e-8) << "turned " << turn;
  }
}

TEST(ProbeScenes, ASheetInsideASolidStandingStillReadsPenetrating) {
  // (Hunt seed 2014, scene 5.) bug28414's one torus face, an open sheet, wholly inside pr2ct.stp
  // (closed), 80.41 from its surface. The start found A inside B and the hulls' depth, but a
  // tracker on the sheet's edge and B's face 5 read 157.70 apart, `uncertified`, at every step.
  const io::Model sheet_file = io::read_model(shared_data("step/bug28414_bug_toroidal_surface.stp"));
  const io::Model solid_file = io::read_model(shared_data("step/pr2ct.stp"));
  const Body& a = sheet_file.bodies.at(0);
  const Body& b = solid_file.bodies.at(0);
  const Rigid_pose_3 X_A0 =
      Rigid_pose_3::from_quaternion(Vec3(-39.351766852098955, 5.406855846876347, 108.96225963823504),
                                    0.036794117227691645, -0.10407422698116323, 0.9923691352126386,
                                    -0.05493858109769465) * a.placement;
  const Rigid_pose_3 X_WB =
      Rigid_pose_3::from_quaternion(Vec3(-67.81034415902802, 2.5264398140784596, -175.27419482044664),
                                    0.248805470310454, -0.4454209893475563, -0.2911309888268482,
                                    -0.8092828476725176) * b.placement;
  // Standing still, then moved 1 mm a step along x (still inside).
  Body_pair_tracker tracker(a, b);
  Twist_3 v;
  v.linear = Vec3(10.0, 0.0, 0.0);
  for (int k = 0; k <= 3; ++k) {
    const double t = 0.1 * k;
    const Rigid_pose_3 X_WA = Rigid_pose_3(Mat3::Identity(), Vec3(1.0 * k, 0.0, 0.0)) * X_A0;
    const Pair_report& r = tracker.step(t, X_WA, v, X_WB, Twist_3{}, 0.1);
    const Signed_distance_result ref = signed_distance(a, X_WA, b, X_WB);
    ASSERT_TRUE(ref.is_certified()) << "t = " << t;
    ASSERT_EQ(ref.overlap, Overlap_kind::A_inside_B) << "t = " << t;
    EXPECT_EQ(r.status, Pair_status::Penetrating) << "t = " << t << ": " << r.distance;
    EXPECT_LT(r.distance, 0.0) << "t = " << t;
    if (r.lower_bound) {
      EXPECT_LE(*r.lower_bound, r.distance) << "t = " << t;
    }
  }
}

TEST(ProbeScenes, TwoFacesOfAPartThatCrossReadPenetratingAtEveryStep) {
  // (Hunt seed 1002, scene 4.) Faces 2 and 4 of BUC50025.igs cross by a few 1e-4; each step is
  // solved. At t = 1.2 the step's solve spent its 50,000 nodes with its bound at 0 and its
  // witness 1.35e-6 apart: the row read that, `uncertified`, while the surfaces meet.
  const io::Model part = io::read_model(shared_data("iges/BUC50025.igs"));
  ASSERT_GE(part.bodies.size(), 4u);
  const Body& a = part.bodies[1];
  const Body& b = part.bodies[3];
  const Motion motion = keyframes_of({
      {0.0, 32.05141900334135, 53.1663480512009, 35.3972742604882, 0.9124653935674379, 0.13219437662009537, 0.3222337673232726, -0.21470200634483128},
      {0.001276499672955289, 41.55132614264923, 47.698400664704614, 39.96298241249419, 0.9125212029465471, 0.19364022960074798, 0.14497159244258986, -0.3298359486742098},
      {0.7301134325836227, -2.8134366794885457, 14.224155447631379, -23.26471149157482, 0.9101591619272534, -0.37171700939501295, -0.09592238672417353, 0.15567806721386845},
      {1.8632025700629733, -10.032850481551735, -76.3593639428014, -45.134562892306306, -0.0400877228216176, -0.5545314754445916, -0.08430696809398347, 0.8269100025704259},
      {2.0, -14.234223895660788, -80.78608035829973, -52.946116195112424, 0.07383615673080354, -0.7678794780072051, -0.1342640610482025, 0.6219987870771545}});
  Body_pair_tracker tracker(a, b);
  int meeting = 0;
  for (int k = 0; k <= 5; ++k) {
    const double t = 0.4 * k;
    const Rigid_pose_3 X_W = motion.pose_at(t);
    const Rigid_pose_3 X_WA = X_W * a.placement, X_WB = X_W * b.placement;
    const Pair_report& r = tracker.step(t, X_WA, motion.twist_at(t), X_WB, motion.twist_at(t), 0.4);
    const Signed_distance_result ref = signed_distance(a, X_WA, b, X_WB);
    ASSERT_TRUE(ref.is_certified()) << "t = " << t;
    if (ref.overlap != Overlap_kind::Surfaces_meet) continue;
    ++meeting;
    EXPECT_EQ(r.status, Pair_status::Penetrating) << "t = " << t << ": " << r.distance;
  }
  EXPECT_EQ(meeting, 6);
}

TEST(ProbeScenes, ASheetFarFromATorusPassingByReadsAFiniteDistanceAtEveryStep) {
  // (Hunt seed 3021, scene 5.) The second sheet of OCC22459-TEST2.stp flies past the toroidal
  // part of bug28414 some 1,500 mm away. At t = 2.57 the step's solve spent its nodes without
  // a witness: the row read no distance at all (NaN in the report, `uncertified`).
  const io::Model torus = io::read_model(shared_data("step/bug28414_bug_toroidal_surface.stp"));
  const io::Model sheets = io::read_model(shared_data("step/OCC22459-TEST2.stp"));
  ASSERT_EQ(torus.bodies.size(), 1u);
  ASSERT_EQ(sheets.bodies.size(), 3u);
  const Body& a = torus.bodies[0];
  const Body& b = sheets.bodies[1];
  const Motion motion_a = keyframes_of({
      {1.5, 30.066662189795213, -95.31966671110283, -81.04718487008597, 0.8674134833230069, -0.45417923712316194, -0.1628527648260309, -0.12163077942769099},
      {1.8703097269307214, 11.946346254317747, -101.03799571859629, -82.05060272460139, 0.8731744308823001, -0.4431496815032084, -0.08063385021281841, -0.18623360394094596},
      {2.0325906879236477, 30.88634677582695, -88.06919840659162, -89.88990245532054, 0.9122390246260472, -0.38670875026865204, -0.09989479884754421, -0.0910897007250754},
      {3.5, -1.2367085413752505, -43.74727900485429, -100.03370711340804, 0.943207474032876, -0.0980005327588157, 0.11626043159484208, -0.29536260520399504}});
  Twist_3 twist_b;
  twist_b.linear = Vec3(-69.41705780394075, 1515.6266687881564, 1886.6916630305461);
  twist_b.angular = Vec3(0.19859888309516727, 0.15088571467474668, -0.017087560985787443);
  const Motion motion_b = Motion::twist(
      Rigid_pose_3::from_quaternion(Vec3(-1300.6781551398342, -1416.8809805233034, -1092.4438789666685),
                                    0.1540265559319571, -0.979101181704233, -0.12580299795282493,
                                    -0.04254764105324071),
      twist_b, 1.5);
  Body_pair_options options;
  options.tracker.substeps = 2;
  Body_pair_tracker tracker(a, b, options);
  const double dt = 2.0 / 30.0;
  for (int k = 0; k <= 30; ++k) {
    const double t = 1.5 + k * dt;
    const Rigid_pose_3 X_WA = motion_a.pose_at(t) * a.placement;
    const Rigid_pose_3 X_WB = motion_b.pose_at(t) * b.placement;
    const Pair_report& r =
        tracker.step(t, X_WA, motion_a.twist_at(t), X_WB, motion_b.twist_at(t), dt);
    ASSERT_TRUE(std::isfinite(r.distance)) << "t = " << t << ": " << to_string(r.status);
    ASSERT_TRUE(r.lower_bound.has_value()) << "t = " << t;
    EXPECT_LE(*r.lower_bound, r.distance) << "t = " << t;
    EXPECT_NEAR((r.point_b - r.point_a).norm(), r.distance, 1e-9 * r.distance) << "t = " << t;
  }
}

TEST(ProbeScenes, APartCarriedIntoAnotherBetweenStepsReadsItsDepthNotTheGap) {
  // (Hunt seed 1006, scene 5.) Between t = 2.7 and 3.1 linkrods goes inside the cornetta
  // (closed); its held pair reads the surfaces' gap, +22.77 with a bound of 5.07, where the
  // depth is -7.39.
  const io::Model cornetta = io::read_model(shared_data("step/bug27693_cornetta-step.stp"));
  const io::Model linkrods = io::read_model(shared_data("step/linkrods.step"));
  ASSERT_EQ(cornetta.bodies.size(), 1u);
  ASSERT_EQ(linkrods.bodies.size(), 1u);
  const Body& a = linkrods.bodies[0];
  const Body& b = cornetta.bodies[0];
  const Motion motion_a = keyframes_of({
      {1.5, -17.712554372429906, 14.296785428083375, 27.025269781991053, 0.8512609614163847, 0.18832015795606505, -0.0743552299347248, -0.4841090718600607},
      {2.498827144159443, 6.463417728321, -6.06157439288565, 27.18941832459065, 0.8709352141379346, -0.2432410906092347, 0.28717826316340195, -0.3159656148700225},
      {3.5, 36.18286365636259, -21.634146879535294, 24.159011549662893, 0.4767561489953678, -0.6514533994895686, 0.5734576329775443, -0.13949331836465542}});
  const Motion motion_b = keyframes_of({
      {1.5, 192.25000873482222, -137.59403709064594, -387.81336704969493, 0.47145578554641254, -0.8701089720697915, -0.13579753886373686, -0.04689186962595547},
      {2.66794549003882, 46.78228427028837, -25.00157906357851, -56.29218876958992, 0.8451569580404041, -0.07886700553789866, -0.3913630035848069, 0.3554218776868608},
      {3.467750449217122, -53.91510836667962, 52.09290347177168, 171.54535644037728, 0.5718601670540935, 0.318657935820473, -0.3220468378047936, 0.6838997759434},
      {3.5, -57.78394396179927, 55.33842313916792, 181.1689802339472, 0.6255949644870813, 0.5279806673113118, -0.4238920296126996, 0.3875343889059857}});
  Body_pair_tracker tracker(a, b);
  int nested = 0;
  for (int k = 0; k <= 5; ++k) {
    const double t = 1.5 + 0.4 * k;
    const Rigid_pose_3 X_WA = motion_a.pose_at(t) * a.placement;
    const Rigid_pose_3 X_WB = motion_b.pose_at(t) * b.placement;
    const Pair_report& r = tracker.step(t, X_WA, motion_a.twist_at(t), X_WB, motion_b.twist_at(t), 0.4);
    const Signed_distance_result ref = signed_distance(a, X_WA, b, X_WB);
    ASSERT_TRUE(ref.is_certified()) << "t = " << t;
    if (ref.overlap == Overlap_kind::A_inside_B) {
      ++nested;
      EXPECT_EQ(r.status, Pair_status::Penetrating) << "t = " << t << ": " << r.distance;
      EXPECT_FALSE(r.lower_bound.has_value()) << "t = " << t;
    } else if (ref.overlap == Overlap_kind::None && r.lower_bound) {
      EXPECT_LE(*r.lower_bound, ref.upper_bound * (1.0 + 1e-12)) << "t = " << t;
    }
  }
  EXPECT_GE(nested, 1);
}

TEST(ProbeScenes, ASheetThroughAPlaneAndOutReadsItsDistanceNotADepth) {
  // (Hunt seed 1009, scene 2.) At t = 11/6 the step's first tracked reading is apart; a later
  // stage seeds a pair behind the plane, which read -155.53 while the sheet is 155.53 away.
  const io::Model sheets = io::read_model(shared_data("step/OCC22459-TEST2.stp"));
  const Body& sheet = sheets.bodies.at(0);
  const Body plane = make_plane_body(2608.1730657186877, 2280.9191049702085);
  Twist_3 plane_twist;
  plane_twist.linear = Vec3(3925.145289098882, -1531.2764073145672, -2279.248467204183);
  plane_twist.angular = Vec3(0.017822345600710006, 0.012718827785036404, 0.0013147387862830187);
  const Motion plane_motion = Motion::twist(
      Rigid_pose_3::from_quaternion(Vec3(-6121.048435278145, 1332.9684312740633, 2372.7768428477125),
                                    0.4982181190510355, 0.12141666406942986, -0.7927413089827957,
                                    -0.3295419799778823),
      plane_twist, 0.0);
  const std::vector<std::array<double, 8>> rows = {
      {0.0, -5910.184808394254, 3038.4538627996662, -878.2725326890968, 0.8556950106158357, -0.19695600881998676, 0.37837468214046893, 0.2929624196240283},
      {0.16666666666666666, -5508.297590108268, 2428.670228038335, -976.7671568529738, 0.9011585610160255, -0.2030455866043533, 0.2754478058136594, 0.2661094585700799},
      {0.3333333333333333, -5038.32157844466, 1838.1566280539823, -1115.256899632572, 0.9345294279544103, -0.20641048738586848, 0.16882468415328963, 0.23568556384486714},
      {0.5, -4492.626224131792, 1266.4276584829868, -1276.5665097651956, 0.9553598064073362, -0.20700555742379076, 0.059936097174915215, 0.20209899493179595},
      {0.6666666666666666, -3867.631666847835, 711.9930106376983, -1442.2999622559887, 0.9633701726772897, -0.2048228114490259, -0.049756774734465346, 0.16580045136811095},
      {0.8333333333333333, -3164.0002437592702, 172.43719719765863, -1593.8245738305966, 0.9584530353327895, -0.19989153981877877, -0.15878195845558082, 0.12727702478943426},
      {1.0, -2386.601057070644, -355.4512286575316, -1713.2677786810236, 0.9406743776402854, -0.19227791546805606, -0.26567644060417417, 0.0870456626272531},
      {1.1666666666666665, -1544.2494960831914, -875.5078733924181, -1784.473240897275, 0.9102727721320173, -0.182084105932354, -0.3690057997672374, 0.04564623117026588},
      {1.3333333333333333, -649.2356483143545, -1391.9873131579127, -1793.86515530583, 0.8676561791914804, -0.16944690235733526, -0.4673834550624218, 0.003634271076648876},
      {1.5, 283.33317215948375, -1909.3354905924516, -1731.1744999974194, 0.8133964726164106, -0.15453588389286974, -0.5594892727234141, -0.03842645744867981},
      {1.6666666666666665, 1236.3406069725445, -2431.9518742638706, -1589.9883888718077, 0.7482217656209832, -0.1375511421035105, -0.6440872810287572, -0.07997153977522908},
      {1.8333333333333333, 2191.5769117581062, -2963.9541042924457, -1368.0931359850683, 0.6730066402549132, -0.11872059593163264, -0.7200422558567574, -0.12044348074986728}};
  const Motion sheet_motion = keyframes_of(rows, Motion::Type::Table);
  Body_pair_tracker tracker(sheet, plane);
  int apart = 0;
  for (const auto& row : rows) {
    const double t = row[0];
    const Rigid_pose_3 X_WA = sheet_motion.pose_at(t) * sheet.placement;
    const Rigid_pose_3 X_WB = plane_motion.pose_at(t);
    const Pair_report& r = tracker.step(t, X_WA, sheet_motion.twist_at(t), X_WB,
                                        plane_motion.twist_at(t), 1.0 / 6.0);
    const Signed_distance_result ref = signed_distance(sheet, X_WA, plane, X_WB);
    ASSERT_TRUE(ref.is_certified()) << "t = " << t;
    if (ref.overlap != Overlap_kind::None) continue;
    ++apart;
    // Apart: the distance, never a depth.
    EXPECT_NEAR(r.distance, ref.distance, 1e-6 * std::max(1.0, ref.distance)) << "t = " << t;
    if (r.lower_bound) { EXPECT_LE(*r.lower_bound, ref.upper_bound * (1.0 + 1e-12)) << "t = " << t; }
  }
  EXPECT_GE(apart, 7);
}

// scripts/probe-scenes.py --seed 777 --heavy, scene 10: OCC22459-TEST2.stp's third sheet (A,
// static) against a plane (B) turning as it passes (its poses from t = 0.42 to 0.5, the table
// rows). The tracker on A's straight edge 5 against the plane started on the plane's corner;
// the pair's minimum then moved along the plane's side, and the tracker stayed held on the
// corner, converged along its one free parameter. As a flat pair it has one basin, so its
// reading was taken for the pair's minimum: rows read 658.5 to 474.9 with that as their
// certified lower bound, where the bodies were 656.5 to 397.1 apart.
TEST(ProbeScenes, ASheetsEdgeHeldOnAPlanesCornerIsNoCertificate) {
  const io::Model sheets = io::read_model(shared_data("step/OCC22459-TEST2.stp"));
  const Body& sheet = sheets.bodies.at(2);
  const Body plane = make_plane_body(2210.651106678419, 2352.2853334211404);
  const Rigid_pose_3 X_WA =
      Rigid_pose_3::from_quaternion(Vec3(-1383.9104202129984, 1207.4237999398642, 995.0969790987162),
                                    0.5284815938253967, 0.7066412794567927, 0.24635699865379063,
                                    -0.40084103628462464) *
      sheet.placement;
  const std::vector<std::array<double, 8>> rows = {
      {0.42, -2319.112112264441, 2244.934959246747, 1444.3560652270899, 0.5524567472391922,
       0.6828419048595745, -0.45264602448097685, 0.15372069450534653},
      {0.44, -2264.2633453164453, 2159.8074646057958, 1382.831798504608, 0.5520609566599682,
       0.6817458625679313, -0.4546022422160806, 0.154233849641705},
      {0.46, -2209.41457836845, 2074.6799699648445, 1321.3075317821265, 0.5516621584112983,
       0.68064610607376, -0.456555983244115, 0.15474616450049714},
      {0.48, -2154.5658114204543, 1989.5524753238933, 1259.783265059645, 0.5512603546658649,
       0.6795426413686164, -0.4585072369209526, 0.15525763629059328},
      {0.5, -2099.717044472459, 1904.424980682942, 1198.2589983371631, 0.550855547612725,
       0.6784354744642591, -0.46045599261601733, 0.15576826222545673}};
  const Motion motion = keyframes_of(rows, Motion::Type::Table);
  Body_pair_tracker tracker(sheet, plane);
  double worst = 0.0;
  for (const auto& row : rows) {
    const double t = row[0];
    const Rigid_pose_3 X_WB = motion.pose_at(t);
    const Pair_report& r = tracker.step(t, X_WA, Twist_3{}, X_WB, motion.twist_at(t), 0.02);
    const Signed_distance_result ref = signed_distance(sheet, X_WA, plane, X_WB);
    ASSERT_TRUE(ref.is_certified() && ref.overlap == Overlap_kind::None) << "t = " << t;
    ASSERT_TRUE(r.lower_bound.has_value()) << "t = " << t;
    // The row's certified bound holds, and a certified row is the distance.
    EXPECT_LE(*r.lower_bound, ref.upper_bound * (1.0 + 1e-12)) << "t = " << t;
    if (r.status != Pair_status::Uncertified) worst = std::max(worst, std::abs(r.distance - ref.distance));
  }
  EXPECT_LE(worst, 1e-6);
}

}  // namespace
}  // namespace extremal
