// Every tuning number of the mesh hierarchy and its front (Mesh_bvh.h, Mesh_front.h), named
// once: what it bounds and what set it. Not API.
#pragma once

#include <cstddef>

namespace extremal::internal {

// Median splits keep a tree's depth near log2 of its leaves; this many levels hold 2^40 leaves
// with room to spare (the query stacks are sized by it).
constexpr int k_max_depth = 60;
// A box's frame from its points' covariance is used when its determinant is +-1 within this.
constexpr double k_frame_check = 1e-6;
// Two boxes' axes are parallel, and their cross product no separating axis, past this
// (1 - cos^2 of their angle); the face axes bound those.
constexpr double k_parallel_axes = 1e-12;
// Boxes are inflated, and their bounds lowered, by this many ulps of the lengths involved (the
// rounding of the projections and transforms). Shown by MeshBvh.BoxBoundsNeverExceedTheDistance.
constexpr double k_box_rounding = 64.0 * 2.220446049250313e-16;

// A front's keys (bound + the motion's running sum) are compared to this many ulps of the
// lengths involved; the certificate's tolerance is at least that.
constexpr double k_key_rounding = 16.0 * 2.220446049250313e-16;
// A mesh pair's front certifies its distance d to this fraction of d: no two points of the
// bodies are closer than d (1 - this), beyond the rounding of its keys. Small enough that the
// readings equal FCL's to 1e-12 (bench compare (e)), large enough that equal-distance ties do
// not all open.
constexpr double k_front_relative_tolerance = 1e-13;
// A front is made anew from the roots once it holds more than this many times its entries after
// the last rebuild, plus this floor (pairs split about an old minimum would pile up otherwise).
// Not tuned: a bound on the front's memory.
constexpr std::size_t k_front_growth = 4;
constexpr std::size_t k_front_floor = 4096;
// A carried step that opened more than this fraction of the entries the last traversal from
// the roots opened sends the next step back to the roots. Set by bench compare (e): 0.25 and
// 1.0 were no better at 100 Hz and 1 kHz.
constexpr double k_carried_cost_ratio = 0.5;

}  // namespace extremal::internal
