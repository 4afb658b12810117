// The body-pair tracker's engine for two bodies each a triangle mesh or a point (at least one a
// mesh): the certified front of Mesh_front.h carried across steps in place of the trackers and
// their candidate stage (docs/design.md, "Meshes"). The reading:
//   - apart: the front's closest triangle pair (or triangle and point), exact;
//   - a point against a closed mesh: minus its distance when the point is inside (the closest
//     feature's angle-weighted pseudo-normal), the point's own depth;
//   - two closed meshes whose surfaces cross, or one inside the other (a vertex of each tested
//     against the other while their boxes overlap): minus the depth of their convex hulls
//     (hull_signed_distance, the minimum translation distance when both are convex, its
//     support points a vertex-face or edge-edge pair), the same definition as `extremal
//     distance --signed`;
//   - a closed mesh and an open one (a sheet): the depth of the side the closed one entered
//     by while the surfaces meet, the hulls' depth while the open one lies inside;
//   - two open (or inconsistently oriented) meshes, or an open one and a point: the distance
//     has no sign.
#pragma once

#include <memory>

#include "algorithms/body_pair/Body_pair_options.h"
#include "algorithms/body_pair/Tracking_model.h"
#include "algorithms/body_pair/internal/Pair_engine.h"
#include "algorithms/mesh/Mesh_front.h"

namespace extremal::internal {

class Mesh_pair_stage final : public Pair_engine {
 public:
  // Whether the pair of models is one this engine takes.
  static bool takes(const Tracking_model& a, const Tracking_model& b);

  // The models must outlive it.
  Mesh_pair_stage(std::shared_ptr<const Tracking_model> a, std::shared_ptr<const Tracking_model> b,
                  const Body_pair_options& options);

  // (The first step makes the front from the roots.)
  void start(const Rigid_pose_3&, const Rigid_pose_3&) override {
    m_started = false;
    m_entry_side = Vec3::Zero();
  }
  const Pair_answer& step(const Pair_step& step) override;
  double box_bound(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) const override {
    return boxes_apart(m_a, X_WA, m_b, X_WB);
  }
  // The next step starts the front again from the roots.
  void farther(double, const Rigid_pose_3&) override { m_started = false; }
  void add_statistics(Pair_statistics& s) const override;

  const Mesh_front_statistics& front_statistics() const { return m_front.statistics(); }

 private:
  // Whether the bodies overlap though their surfaces are apart: one body wholly inside the
  // other, closed, one (or the point inside the closed mesh).
  bool nested(const Rigid_pose_3& X_MO, const Mesh_closest& c) const;
  // The answer becomes the hulls' depth (kept on the side entered by, `entry_side` in A's
  // frame, zero: none; keep_entry_side), unless the hulls barely meet.
  void read_depth(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB, const Vec3& entry_side);

  std::shared_ptr<const Tracking_model> m_models[2];
  const Tracking_model& m_a;
  const Tracking_model& m_b;
  const Body_pair_options m_options;
  // The front runs from the mesh side M (A, unless A is the point) to the other side O.
  bool m_swapped;
  const Mesh_bvh& m_mesh;
  const Mesh_bvh* m_other;  // null: the other side is a point
  Mesh_front m_front;
  bool m_started = false;
  Rigid_pose_3 m_last;  // X_MO of the last step
  // A closed mesh against an open one: the normal of the last step that read them apart, in
  // A's frame (zero: none since the start).
  Vec3 m_entry_side = Vec3::Zero();
  Pair_answer m_answer;
};

}  // namespace extremal::internal
