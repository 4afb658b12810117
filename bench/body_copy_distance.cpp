// The certified distance between one body of a file and its own copy moved by a pose, with a
// node budget: the bounds, the work and the wall time. For cases one body of a multi-body file
// shows (`extremal distance` measures the union of a file's bodies), such as two sheets running
// parallel at a small clearance (bench/RESULTS.md).
//   body_copy_distance FILE BODY_INDEX POSE [MAX_NODES] [TOLERANCE]
// e.g. ./build/bench/body_copy_distance ../shared/data/step/OCC22459-TEST2.stp 2 3,1,-2 4000000
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "algorithms/distance/Global_distance.h"
#include "io/Model_reader.h"
#include "io/Shape_spec.h"

int main(int argc, char** argv) {
  using namespace extremal;
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s FILE BODY_INDEX POSE [MAX_NODES] [TOLERANCE]\n", argv[0]);
    return 2;
  }
  try {
    io::Read_options read;
    read.trim_tolerance = 1e-9;  // as `extremal distance` reads files
    io::Model model = io::read_model(argv[1], read);
    std::vector<const Body*> bodies;
    for (const Body& b : model.bodies)
      if (!b.is_empty()) bodies.push_back(&b);
    const int index = std::atoi(argv[2]);
    if (index < 0 || index >= static_cast<int>(bodies.size())) {
      std::fprintf(stderr, "%s: body index %d outside 0..%zu\n", argv[1], index, bodies.size() - 1);
      return 2;
    }
    const Body& body = *bodies[static_cast<std::size_t>(index)];
    Distance_request request;
    request.absolute_tolerance = argc > 5 ? std::atof(argv[5]) : 1e-9;
    request.relative_tolerance = 0.0;
    if (argc > 4) request.max_nodes = std::atoi(argv[4]);
    const Distance_hierarchy h(body);
    const Rigid_pose_3 moved = io::parse_pose(argv[3]) * body.placement;
    const auto start = std::chrono::steady_clock::now();
    const Distance_result r = extremal_distance(h, body.placement, h, moved, request);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("body %d '%s' (%zu faces): d = %.12g in [%.12g, %.12g], %s; %ld pairs, %ld nodes, "
                "%.2f s\n",
                index, body.name.c_str(), body.faces.size(), r.distance, r.lower_bound,
                r.upper_bound, to_string(r.status), r.pairs_processed, r.nodes_created, seconds);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
}
