// The C++ API in one program: import a CAD part, move a sphere past it, print the distances.
//
//   extremal_example PART_FILE [CLEARANCE]
//
// The sphere (radius a tenth of the part's size) crosses the part's bounding box along x,
// CLEARANCE (default 2, in mm) above the box's top, from half a box length before it to half a
// box length after it, in one second. Over a flat top the distance is exactly CLEARANCE.
#include <Extremal.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3) {
    std::fprintf(stderr, "usage: %s PART_FILE [CLEARANCE]\n", argv[0]);
    return 2;
  }
  const double clearance = argc == 3 ? std::atof(argv[2]) : 2.0;
  try {
    // 1. Import. Lengths come in millimetres whatever the file's unit.
    const extremal::io::Model model = extremal::io::read_model(argv[1]);
    for (const extremal::io::Skipped_entity& s : model.skipped)
      std::printf("skipped %s: %s\n", s.entity.c_str(), s.reason.c_str());
    const extremal::Body& part = model.bodies.at(0);
    std::printf("%s: %s, body '%s', %zu faces\n", argv[1], model.format_name.c_str(),
                part.name.c_str(), part.faces.size());

    // Where the part is (its file placement included), to aim the sphere.
    const extremal::Bbox_3 box = part.trimmed_bbox(part.placement);
    const double length = box.xmax() - box.xmin();
    const double size = std::max({length, box.ymax() - box.ymin(), box.zmax() - box.zmin()});
    const double radius = 0.1 * size;
    const extremal::Body ball = extremal::make_sphere_body(radius, "ball");

    // 2. The scene: the part at rest, the ball at constant velocity; watch the pair (part, ball).
    const extremal::Motion part_motion = extremal::Motion::still(extremal::Rigid_pose_3());
    const extremal::Vec3 start(box.xmin() - 0.5 * length, 0.5 * (box.ymin() + box.ymax()),
                               box.zmax() + radius + clearance);
    extremal::Twist_3 velocity;
    velocity.linear = extremal::Vec3(2.0 * length, 0.0, 0.0);  // box length + 2 halves in 1 s
    const extremal::Motion ball_motion = extremal::Motion::twist(
        extremal::Rigid_pose_3(extremal::Mat3::Identity(), start), velocity, 0.0);
    extremal::Scene_stepper scene({{&part, &part_motion}, {&ball, &ball_motion}}, {{0, 1}},
                                  extremal::Body_pair_options());

    // 3. Step it; 4. read the reports (one per watched pair).
    const int steps = 100;
    const double dt = 1.0 / steps;
    double closest = 0.0, closest_t = -1.0;
    for (int k = 0; k <= steps; ++k) {
      const double t = k * dt;
      const extremal::Pair_report& r = scene.step(t, dt).at(0);
      // The first time it comes closest: along a flat stretch the distance is the same to
      // rounding, so only a nanometre's gain counts as closer.
      if (closest_t < 0.0 || r.distance < closest - 1e-6) {
        closest = r.distance;
        closest_t = t;
      }
      if (k % 10 == 0)
        std::printf("t %.2f  distance %.6f mm  face %d  status %s  on part (%.3f, %.3f, %.3f)\n",
                    t, r.distance, r.feature_a, extremal::to_string(r.status), r.point_a.x(),
                    r.point_a.y(), r.point_a.z());
    }
    std::printf("closest %.6f mm at t %.2f\n", closest, closest_t);
    return 0;
  } catch (const std::exception& e) {  // Invalid_input names the file and the reason
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
