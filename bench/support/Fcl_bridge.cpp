#include "support/Fcl_bridge.h"

#include <vector>

namespace extremal::bench {

std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> fcl_model(const Triangle_mesh& m) {
  std::vector<fcl::Vector3d> v;
  std::vector<fcl::Triangle> t;
  for (const Point_3& p : m.vertices) v.emplace_back(p.x(), p.y(), p.z());
  for (const auto& f : m.triangles) t.emplace_back(f[0], f[1], f[2]);
  return fcl_model(v, t);
}

std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> fcl_model(const std::vector<fcl::Vector3d>& vertices,
                                                       const std::vector<fcl::Triangle>& triangles) {
  auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  model->beginModel(static_cast<int>(triangles.size()), static_cast<int>(vertices.size()));
  model->addSubModel(vertices, triangles);
  model->endModel();
  return model;
}

fcl::Transform3d fcl_pose(const Rigid_pose_3& X) {
  fcl::Transform3d T = fcl::Transform3d::Identity();
  T.linear() = X.rotation();
  T.translation() = X.translation();
  return T;
}

}  // namespace extremal::bench
