// A 3D snapshot of a scene at one time as binary glTF 2.0 (.glb) through assimp's exporter
// (format "glb2"), for `extremal report --snapshot OUT.glb --at T` and for looking at a scene in
// any glTF viewer.
//
// Content: one node and one mesh per body, named as the body, holding its faces tessellated (a
// grid over each patch; trimmed faces by a constrained Delaunay triangulation of the trim loops
// and the grid points inside them, so holes and trimmed-away parts stay empty) or its mesh as it
// is, posed in the world, with outward vertex normals; one node and one mesh per witness
// segment, named as given, holding a single line primitive from the point on A to the point on
// B. Point bodies get an empty node (their origin as its translation).
// Coordinates: vertices are world coordinates in the scene unit (z up). The root node "scene"
// carries the map to glTF's convention (y up, metres): (x, y, z) -> s (x, z, -y), s the scene
// unit in metres, so viewers show the scene upright and at its real size.
#pragma once

#include <string>
#include <vector>

#include "kernel/Body.h"
#include "kernel/Rigid_pose_3.h"

namespace extremal::io {

struct Snapshot_body {
  std::string name;
  const Body* body = nullptr;  // must outlive the call
  Rigid_pose_3 pose;           // body frame in the world (motion pose times Body::placement)
};

struct Snapshot_segment {
  std::string name;  // e.g. "A - bracket"
  Vec3 a = Vec3::Zero(), b = Vec3::Zero();  // world coordinates
};

struct Snapshot_options {
  // Grid cells per Bezier span of a patch, per direction (clamped to [8, 96] per face and
  // direction).
  int cells_per_span = 8;
  // Length of one scene unit in metres (mm: 0.001), for the root node's scale.
  double unit_in_metres = 0.001;
};

// Writes the snapshot. Throws Invalid_input naming the path when assimp cannot write it, or a
// body that has no name or is null.
void write_snapshot_glb(const std::string& path, const std::vector<Snapshot_body>& bodies,
                        const std::vector<Snapshot_segment>& segments,
                        const Snapshot_options& options = {});

// The same snapshot as the bytes of a .glb file (to embed it: `extremal report -o OUT.html`).
// Throws Invalid_input on a body without a name or null, or when assimp cannot make it.
std::string snapshot_glb(const std::vector<Snapshot_body>& bodies,
                         const std::vector<Snapshot_segment>& segments,
                         const Snapshot_options& options = {});

}  // namespace extremal::io
