// Our triangle meshes and poses as FCL's, for the programs in bench/ that measure FCL (FCL
// types appear only there).
#pragma once

#include <memory>
#include <vector>

#include "kernel/Body.h"
#include "kernel/Rigid_pose_3.h"

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/math/bv/OBBRSS.h>

namespace extremal::bench {

// FCL's distance hierarchy (BVHModel<OBBRSS>) over the mesh's triangles, in the mesh's frame.
std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> fcl_model(const Triangle_mesh& m);
// The same over FCL's own vertices and triangles.
std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> fcl_model(const std::vector<fcl::Vector3d>& vertices,
                                                       const std::vector<fcl::Triangle>& triangles);

fcl::Transform3d fcl_pose(const Rigid_pose_3& X);

}  // namespace extremal::bench
