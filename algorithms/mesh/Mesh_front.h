// A certified front between two mesh hierarchies (Mesh_bvh.h), or a mesh and a point, carried
// across steps. The front is the set of node pairs the certificate rests on, each with a lower
// bound on the distance of its triangles, made at some earlier relative pose. The relative
// motion since can bring any two points of the bodies at most `closer` nearer per step
// (approach_bound of the bodies' boxes), so a bound made when the motion's running sum was S0
// still holds as bound - (S - S0): the front is a heap keyed by bound + S0, and a step opens only
// the pairs whose key falls below the tracked minimum plus S. An opened pair is bounded again at
// the current pose (its boxes' separating axes), kept if it still clears, and split otherwise;
// a pair of leaves is measured exactly (triangle against triangle, or against the point). When
// the front has grown past a multiple of its size after the last rebuild, or a step opened
// more entries than the last traversal from the roots did, the next is made anew from the roots
// (one full traversal, pruned against the best pair), so that pairs split near an old minimum do
// not pile up and a fast motion costs about what a cold query costs.
#pragma once

#include <cstdint>
#include <vector>

#include "algorithms/mesh/Mesh_bvh.h"
#include "kernel/Rigid_pose_3.h"

namespace extremal {

struct Mesh_closest {
  double distance = HUGE_VAL;
  int triangle_a = -1, triangle_b = -1;  // mesh triangles (-1 on B: the point)
  Vec3 point_a = Vec3::Zero(), point_b = Vec3::Zero();  // A's frame
  double uv_a[2] = {0, 0}, uv_b[2] = {0, 0};
  // Certified: no two points of the bodies are closer (at most `distance`).
  double lower_bound = -HUGE_VAL;
};

struct Mesh_front_statistics {
  long steps = 0;
  long opened = 0;       // entries taken from the front
  long box_bounds = 0;   // box pairs bounded
  long triangle_pairs = 0;
  long rebuilds = 0;       // made anew from the roots after growing
  long cost_restarts = 0;  // steps whose carried front cost more than the roots' traversal
  long traversals = 0;     // steps that traversed from the roots (the first ones included)
};

class Mesh_front {
 public:
  // b null: B is a point, its frame's origin. The hierarchies must outlive the front.
  Mesh_front(const Mesh_bvh& a, const Mesh_bvh* b);

  // The closest pair at relative pose X_AB (B's frame in A's), certified: no two points of the
  // bodies are closer than distance - tolerance. `closer`: how much nearer any two points of the
  // bodies can have come since the last call (ignored by the first, and after reset()).
  const Mesh_closest& update(const Rigid_pose_3& X_AB, double closer, double tolerance);
  // Starts again from the roots at the next update.
  void reset() { m_started = false; }

  const Mesh_closest& closest() const { return m_best; }
  std::size_t size() const { return m_heap.size(); }
  const Mesh_front_statistics& statistics() const { return m_stats; }

 private:
  struct Entry {
    double key;  // lower bound + the motion's running sum when it was made
    int a, b;    // node references (Mesh_bvh::Node; b unused for the point)
  };
  struct Item {  // a node pair bounded at this step's pose, on the way down
    double lower;
    int a, b;
  };
  struct Later {
    bool operator()(const Entry& x, const Entry& y) const { return x.key > y.key; }
  };
  double box_bound(int a, int b, double enough = HUGE_VAL) const;
  // A lower bound on node pair (a, b) at this pose: exact (and the best pair updated) for two
  // leaves, else box_bound.
  double bound(int a, int b, double enough = HUGE_VAL);
  // Measures leaf pair (a, b) (references) exactly, the best pair updated; returns its distance.
  double measure(int a, int b);
  // Measures one triangle pair (slots), the best pair updated if closer.
  double measure_triangles(int slot_a, int slot_b);
  void push(double lower, int a, int b);
  template <class Slack>
  void descend(double lower, int a, int b, const Slack& slack);
  void sift_down();
  void restart();

  const Mesh_bvh& m_a;
  const Mesh_bvh* m_b;
  std::vector<Entry> m_heap;
  std::vector<Item> m_stack;  // descend's (kept: no allocation once grown)
  Mat3 m_R = Mat3::Identity();
  Vec3 m_t = Vec3::Zero();
  Vec3 m_corners_b[3];
  double m_sum = 0.0;      // the motion's running sum since the last rebuild
  double m_length = 0.0;   // the bodies' size, for the rounding of keys
  std::size_t m_rebuilt_size = 0;
  long m_cold_cost = 0;  // entries the last traversal from the roots opened
  bool m_started = false;
  bool m_restart = false;
  bool m_restart_pending = false;  // the heap was emptied: descend from the roots
  Mesh_closest m_best;
  Mesh_front_statistics m_stats;
};

}  // namespace extremal
