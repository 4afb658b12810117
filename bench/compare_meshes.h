// bench/compare scenario (e), meshes against FCL (compare_meshes.cpp).
#pragma once

#include <string>

namespace extremal::bench {

// Prints the scenario's table: the shared meshes under `data`/mesh, and `large_mesh` (a mesh
// file of 10^5 triangles or more, left out when empty) against the Spider.
int run_mesh_scenario(bool quick, const std::string& data, const std::string& large_mesh);

}  // namespace extremal::bench
