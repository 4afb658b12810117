// Extremal: the C++ API in one header.
//
// Build against the installed package:
//   find_package(Extremal 0.1 REQUIRED)                 # CMakeLists.txt
//   target_link_libraries(app PRIVATE Extremal::Extremal)
//   #include <Extremal.h>                               // this file
// (in the source tree, link extremal::algorithms and extremal::io instead).
//
// The four steps (tests/package/example.cpp is the whole program):
//
//   // 1. Import: STEP, IGES, .brep, free-form OBJ, meshes; lengths in millimetres.
//   //    Throws extremal::Invalid_input naming the file and the reason if it cannot be read;
//   //    Model::skipped names entities it could not use.
//   extremal::io::Model part = extremal::io::read_model("bracket.step");
//   extremal::Body ball = extremal::make_sphere_body(5.0);      // or a generated shape
//
//   // 2. A scene: each body with a motion (still, constant twist, keyframes), and the pairs
//   //    to watch. Bodies and motions must outlive the stepper.
//   extremal::Motion fixed = extremal::Motion::still(extremal::Rigid_pose_3());
//   extremal::Twist_3 v;  v.linear = extremal::Vec3(10, 0, 0);          // mm/s
//   extremal::Motion passing = extremal::Motion::twist(start_pose, v, 0.0);
//   extremal::Scene_stepper scene({{&part.bodies[0], &fixed}, {&ball, &passing}},
//                                 {{0, 1}}, extremal::Body_pair_options());
//
//   // 3. Step it, and 4. read the results: one Pair_report per watched pair, for time t,
//   //    then the trackers advance to t + dt.
//   for (int k = 0; k <= 100; ++k) {
//     const extremal::Pair_report& r = scene.step(0.01 * k, 0.01)[0];
//     // r.distance (signed: < 0 penetrating), r.point_a / r.point_b (world), r.normal (A to B),
//     // r.feature_a / r.feature_b (face indices), extremal::to_string(r.status)
//   }
//
// One-off certified distance between two posed bodies: extremal::extremal_distance
// (algorithms/Global_distance.h), with bounds lower <= distance <= upper; signed (penetration
// depth while the bodies overlap, with bounds too): extremal::signed_distance
// (algorithms/Penetration_depth.h); between two sets of bodies (an assembly, a multi-solid
// file), nearest pairs first: extremal::set_distance, extremal::signed_set_distance
// (algorithms/Set_distance.h). Scene files as the command line reads them:
// extremal::io::read_scene (io/Scene.h) with extremal::io::load_bodies as the file loader.
//
// Headers by layer, each usable on its own: kernel/ (geometry: NURBS, bodies, shapes, poses,
// motions), io/ (files), algorithms/ (distances, trackers, scenes). This header sits above all
// three because it is the only one that needs both io/ and algorithms/.
#pragma once

#include "kernel/Body.h"
#include "kernel/Error.h"
#include "kernel/Motion.h"
#include "kernel/Nurbs_curve_3.h"
#include "kernel/Nurbs_surface_3.h"
#include "kernel/Rigid_pose_3.h"
#include "kernel/Shapes.h"
#include "kernel/Types.h"

#include "io/Model_reader.h"
#include "io/Scene.h"

#include "algorithms/Body_pair_tracker.h"
#include "algorithms/Global_distance.h"
#include "algorithms/Penetration_depth.h"
#include "algorithms/Scene_stepper.h"
#include "algorithms/Set_distance.h"
