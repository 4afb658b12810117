// Trim loops of a face and the point-in-trimmed-face test in parameter space.
//
// A CAD face is a NURBS patch restricted to the region its trim loops bound in the patch's
// (u, v) parameter space: one outer loop and any number of holes. Trim_region answers "is (u, v)
// inside the face?" in O(segments in one slab) with no heap allocation, so the global solver and
// the trackers can treat the trim boundary like a patch boundary.
//
// Method: every loop is flattened once into a closed polyline whose distance to the true curve
// is at most tolerance / 2 (adaptive subdivision of each Bezier span), the polylines are bucketed
// into horizontal slabs, and a query counts crossings of the ray from (u, v) towards +u (even-odd
// rule, so the orientation of the loops does not matter and inconsistent files still classify).
// Points closer than `tolerance` to a polyline are reported On_boundary: since the polyline is
// within tolerance / 2 of the exact curve, Inside and Outside answers are exact, and the exact
// boundary always lies in the On_boundary band.
#pragma once

#include <vector>

#include "kernel/Nurbs_curve_3.h"

namespace extremal {

// One piece of a trim loop: the edge's curve in the face's parameter space, as a NURBS curve with
// points (u, v, 0), over the edge's own parameter range.
struct Trim_curve {
  Nurbs_curve_3 uv;
  int edge = -1;          // index into Body::edges, or -1 when the face is not part of a B-rep
  bool reversed = false;  // the loop runs this curve from its domain_max to its domain_min
};

// A closed loop of trim curves, in loop order.
struct Trim_loop {
  std::vector<Trim_curve> curves;
  bool is_outer = true;  // false for a hole
};

enum class Trim_location { Inside, On_boundary, Outside };

class Trim_region {
 public:
  // No trim: every parameter of the patch domain is inside the face.
  Trim_region() = default;

  // Flattens the loops. `tolerance` is the On_boundary band half-width in parameter units;
  // 0 picks 1e-5 of the loops' parameter extent. Loops that do not close are closed by a
  // straight segment (is_closed() tells). Loops with no curve are ignored.
  explicit Trim_region(const std::vector<Trim_loop>& loops, double tolerance = 0.0);

  bool is_trimmed() const { return !m_seg.empty(); }
  double tolerance() const { return m_tol; }
  // False when some loop's end did not meet its start (gap larger than the tolerance).
  bool is_closed() const { return m_closed; }
  std::size_t number_of_segments() const { return m_seg.size(); }
  // Parameter box of the loops: [u_min, u_max] x [v_min, v_max]. Meaningless when untrimmed.
  double u_min() const { return m_umin; }
  double u_max() const { return m_umax; }
  double v_min() const { return m_vmin; }
  double v_max() const { return m_vmax; }

  // Where (u, v) lies. Untrimmed regions answer Inside everywhere (the caller checks the patch
  // domain). Non-finite input answers Outside. No heap allocation.
  Trim_location locate(double u, double v) const;
  // Inside or On_boundary.
  bool contains(double u, double v) const { return locate(u, v) != Trim_location::Outside; }
  // True when every point of the box [u0, u1] x [v0, v1] is Outside (no point of the box is
  // within the tolerance of a loop, and its centre is Outside): a certified "the box holds no
  // point of the face", for pruning. False for untrimmed regions. No heap allocation.
  bool box_outside(double u0, double v0, double u1, double v1) const;
  // At a point of the On_boundary band: the direction (du, dv) of the nearest boundary segment
  // and the one across it that leaves the face (the side where a point a few bands away is
  // Outside). False off the band, or where neither side is Outside (a sliver thinner than the
  // band). No heap allocation.
  bool boundary_directions(double u, double v, double along[2], double out[2]) const;

 private:
  struct Segment {
    double u0, v0, u1, v1;
  };
  // The slab holding v (clamped to the first and last).
  int slab_of(double v) const;
  std::vector<Segment> m_seg;
  std::vector<int> m_slab_start;  // CSR: segments of slab k are m_slab_seg[start[k] .. start[k+1])
  std::vector<int> m_slab_seg;
  double m_tol = 0.0;
  double m_umin = 0.0, m_umax = 0.0, m_vmin = 0.0, m_vmax = 0.0;
  double m_slab_h = 1.0;
  int m_slabs = 0;
  bool m_closed = true;
};

}  // namespace extremal
