// Lower bounds of the branch and bound (boxes, projections on axes, ranges about symmetries), the
// bounds it keeps as proofs, and those proofs re-checked after motion (Global_distance.h).
#include "algorithms/distance/internal/Distance_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "kernel/Error.h"

namespace extremal {

namespace internal {


// Projection interval of a net on the witness axis, cached per node until the axis changes.
void Distance_solver::project_on_axis(Live_node& n, int side) {
  if (n.axis_stamp == m_axis_stamp) return;
  const Vec3* c = m_side[side].cart(n);
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (int k = 0; k < n.count(); ++k) {
    const double s = m_axis.dot(c[k]);
    lo = std::min(lo, s);
    hi = std::max(hi, s);
  }
  n.axis_lo = lo;
  n.axis_hi = hi;
  n.axis_stamp = m_axis_stamp;
}

double Distance_solver::lower_bound(Live_node& a, Live_node& b, double cutoff, double parent,
                           Normal_gap* normal) {
  double L = internal::box_distance(a.bmin, a.bmax, b.bmin, b.bmax);
  if (L >= cutoff) return L;
  const double centres = (a.centre - b.centre).norm();
  L = std::max(L, centres - a.radius - b.radius);
  if (L >= cutoff || !a.is_net() || !b.is_net()) return L;
  if (!m_scratch.regions.empty()) {
    L = std::max(L, region_bound(a, b));
    if (L >= cutoff) return L;
  }
  const Vec3* ca = m_side[0].cart(a);
  const Vec3* cb = m_side[1].cart(b);
  if (m_have_axis) {
    project_on_axis(a, 0);
    project_on_axis(b, 1);
    L = std::max({L, b.axis_lo - a.axis_hi, a.axis_lo - b.axis_hi});
    if (L >= cutoff) return L;
  }
  // From the centroid axis, a few support-point steps towards the hulls' separating axis.
  internal::separating_axis_steps(ca, a.count(), cb, b.count(), b.centre - a.centre, 2,
                                  [&](const Vec3&, const internal::Axis_extents& x) {
                                    L = std::max(L, x.gap());
                                    return L >= cutoff;
                                  });
  // Along each sub-patch's own normal, when the bounds above gained nothing on the parent
  // pair's. Where two sheets run nearly parallel (a part against its offset copy, mating faces
  // at a small clearance) the gap along the local normal is close to their distance, while the
  // witness axis (from where the faces are flat) and the centroid axis see the pieces' tilt
  // wherever the sheets bend, the same after every halving along them: such pairs stalled
  // (OCC22459-TEST2.stp's third sheet against its copy moved by (3, 1, -2): [1.65, 2.72]
  // after 200k nodes, now within 5e-7 of 2.70469). Only where the normal turns far enough
  // from the witness axis for the gap to reach the cutoff (turning an axis by |dn| moves a
  // gap by at most (the nets' diameters + their centres' distance) |dn|): without that
  // filter the projections cost 2 to 8% of a query's time for 0 to 4% fewer nodes.
  if (L >= cutoff) return L;
  // About a centre or axis of symmetry: exact where the elements are concentric spheres or
  // coaxial cylinders, whose continuum of minima no bound above closes. Not gated on the
  // parent's bound: about a sphere's centre the hull bounds gain at every split, too little
  // to close.
  if (m_req.symmetry_bounds) {
    L = std::max(L, symmetry_bound(a, b));
    if (L >= cutoff) return L;
  }
  if (L > parent) return L;
  const double reach = a.size + b.size + centres, short_of = cutoff - L;
  for (Live_node* n : {&a, &b}) {
    if (n->normal_state == 0)
      n->normal_state = net_normal(*n, n == &a ? ca : cb, n->normal) ? 1 : 2;
    if (n->normal_state != 1) continue;
    const Vec3& axis = n->normal;
    // |axis -+ m_axis|^2 = 2 - 2 |axis . m_axis| for unit axes.
    if (m_have_axis &&
        2.0 * (1.0 - std::abs(axis.dot(m_axis))) * reach * reach < short_of * short_of)
      continue;
    const internal::Axis_extents x = internal::axis_extents(ca, a.count(), cb, b.count(), axis);
    if (x.gap() > L) {
      L = x.gap();
      if (normal != nullptr) *normal = {x.separation() > 0.0 ? axis : Vec3(-axis), L};
    }
    if (L >= cutoff) return L;
  }
  return L;
}

double Distance_solver::symmetry_bound(Live_node& a, Live_node& b, Bound_proof* keep) {
  double L = -HUGE_VAL;
  Live_node* nodes[2] = {&a, &b};
  for (int owner = 0; owner < 2; ++owner) {
    const int id = m_side[owner].h->elements()[nodes[owner]->element].symmetry;
    if (id < 0) continue;
    const int other = 1 - owner;
    const Distance_hierarchy::Element& e = m_side[other].h->elements()[nodes[other]->element];
    const int other_id = e.kind == Element_kind::Point ? -2 : e.symmetry;
    if (!m_scratch.along_motion[owner][id]) {
      if (other_id == -1) continue;
      Live_node& own = *nodes[owner];
      if (own.near_of != other_id) {  // a node meets many nodes of one other element in a row
        own.near_of = other_id;
        own.near = other_id == -2 ||
                   near_symmetry(m_scratch.placed[owner][id], m_scratch.placed[other][other_id],
                                 k_near_symmetry * m_size[owner]);
      }
      if (!own.near) continue;
    }
    double lo[2], hi[2];
    if (!range_about(*nodes[owner], owner, owner, id, lo[owner], hi[owner])) continue;
    // The other sub-patch's range (the costly part) holds the distances of its points: of its
    // corners, and within its ball's radius of its centre's. When those leave no gap above L,
    // its range cannot either.
    const Live_node& n = *nodes[other];
    const Symmetry& placed = m_scratch.placed[owner][id];
    auto radial = [&](const Vec3& x) { return placed.offset(x).squaredNorm(); };
    const double centre = std::sqrt(radial(n.centre));
    if (!(std::max(lo[owner] - (centre - n.radius), centre + n.radius - hi[owner]) > L)) continue;
    const Vec3* cart = m_side[other].cart(n);
    double corner_lo = HUGE_VAL, corner_hi = 0.0;
    for (int k = 0; k < corner_count(n); ++k) {
      double q[2];
      const double r2 = radial(cart[corner(n, k, q)]);
      corner_lo = std::min(corner_lo, r2);
      corner_hi = std::max(corner_hi, r2);
    }
    if (!(std::max(lo[owner] - std::sqrt(corner_hi), std::sqrt(corner_lo) - hi[owner]) > L))
      continue;
    if (!range_about(*nodes[other], other, owner, id, lo[other], hi[other])) continue;
    const double gap = std::max(lo[1] - hi[0], lo[0] - hi[1]);
    if (!(gap > L)) continue;
    L = gap;
    if (keep != nullptr) {
      keep->symmetry_side = owner;
      keep->symmetry = placed;
      keep->a_range = {lo[0], hi[0]};
      keep->b_range = {lo[1], hi[1]};
    }
  }
  return L;
}

bool Distance_solver::range_about(Live_node& n, int side, int owner, int id, double& lo, double& hi) {
  const int slot = side == owner ? 0 : 1;
  if (slot == 1 && n.range_symmetry != id) {
    n.range_symmetry = id;
    n.range_state[1] = 0;
  }
  if (n.range_state[slot] == 0)
    n.range_state[slot] = radial_range(m_side[side].hom(n), n.nu, n.nv, m_scratch.placed[owner][id],
                                       n.range_lo[slot], n.range_hi[slot])
                              ? 1
                              : 2;
  lo = n.range_lo[slot];
  hi = n.range_hi[slot];
  return n.range_state[slot] == 1;
}


void Distance_solver::keep_bound(Live_node& a, Live_node& b, double L, const Normal_gap* normal) {
  if (!m_proof.keep_proofs) return;
  Bound_proof& p = m_scratch.bounds.emplace_back();
  p.lower = L;
  p.a_min = a.bmin;
  p.a_max = a.bmax;
  p.b_min = b.bmin;
  p.b_max = b.bmax;
  p.a_centre = a.centre;
  p.b_centre = b.centre;
  p.a_radius = a.radius;
  p.b_radius = b.radius;
  if (!a.is_net() || !b.is_net()) return;
  p.a_element = a.element;
  p.b_element = b.element;
  for (int j = 0; j < 2; ++j) {
    p.a_lo[j] = a.lo[j];
    p.a_hi[j] = a.hi[j];
    p.b_lo[j] = b.lo[j];
    p.b_hi[j] = b.hi[j];
  }
  // A separating axis of the two control nets, found as lower_bound finds its own.
  internal::separating_axis_steps(m_side[0].cart(a), a.count(), m_side[1].cart(b), b.count(),
                                  b.centre - a.centre, 2,
                                  [&](const Vec3& n, const internal::Axis_extents& x) {
                                    if (x.separation() > p.gap) {
                                      p.gap = x.separation();
                                      p.axis = n;
                                    }
                                    return false;
                                  });
  // Or the net normal lower_bound just bounded this pair along.
  if (normal != nullptr && normal->gap > p.gap) {
    p.gap = normal->gap;
    p.axis = normal->axis;
  }
  // And the ranges about a shared symmetry, which outlast turns about it.
  if (m_req.symmetry_bounds) symmetry_bound(a, b, &p);
}

}  // namespace internal

namespace {
// Rounding of a rigid motion applied to points of about this size, composed from translations
// of up to `length` (a few ulps of the lengths involved, generously).
double motion_rounding(const Vec3& c, double h, const Rigid_pose_3& motion, double length) {
  return 64.0 * std::numeric_limits<double>::epsilon() *
         (c.cwiseAbs().maxCoeff() + h + motion.translation().cwiseAbs().maxCoeff() + length);
}


// How much a rigid motion M of a centre or axis s changes the distance to it of any point of
// the ball (c, r): |d(x, M s) - d(x, s)|. A centre: its displacement. An axis L (y0 the foot
// of c, e its direction, D(y) = M y - y, k = |(R - I) e|): d(x, M L) <= d(x, L) + |D(p)| at p
// the foot of x, and d(x, L) <= d(x, M L) + |D(p')| at p' = M^-1 of x's foot on M L; both lie
// on L within r + (|c - y0| + r) k + |D(y0)| of y0 along it, and along L, D is affine:
// |D(y0 + s e)| <= |D(y0)| + |s| k. A turn about L itself moves nothing.
double symmetry_shift(const Symmetry& s, const Rigid_pose_3& M, const Vec3& c, double r) {
  const Vec3 y0 = c - s.offset(c);  // the centre, or c's foot on the axis
  const double d0 = (M.apply_point(y0) - y0).norm();
  if (s.kind != Symmetry::Kind::Axis) return d0;
  const double k = (M.apply_vector(s.direction) - s.direction).norm();
  const double reach = r + ((c - y0).norm() + r) * k + d0;
  return d0 + reach * k;
}
}  // namespace

double bound_after_motion(const Bound_proof& p, const Rigid_pose_3& motion, double length) {
  const Vec3 c = motion.apply_point(p.b_centre);
  const Vec3 bc = 0.5 * (p.b_min + p.b_max), bh = 0.5 * (p.b_max - p.b_min);
  const double rounding = motion_rounding(bc, bh.cwiseAbs().maxCoeff() + p.b_radius, motion, length) +
                          motion_rounding(p.a_centre, p.a_radius, Rigid_pose_3(), 0.0);
  const double spin = (motion.rotation() - Mat3::Identity()).norm();  // >= the spectral norm
  // The bound less how far B's ball can have moved; the gap along the axis less how far it
  // can have moved along it; the balls' distance now; the boxes'.
  const Vec3 shift = c - p.b_centre;
  const double decayed = p.lower - (shift.norm() + spin * p.b_radius);
  // Along the axis a point p of B's ball moves by axis . (shift + (R - I)(p - c)), and
  // axis . (R - I) v = ((R^T - I) axis) . v: a turn about the axis costs nothing.
  const Vec3 tilt = motion.rotation().transpose() * p.axis - p.axis;
  const double along = p.gap + p.axis.dot(shift) - tilt.norm() * p.b_radius;
  const double balls = (p.a_centre - c).norm() - p.a_radius - p.b_radius;
  const Vec3 moved_c = motion.apply_point(bc);
  const Vec3 moved_h = motion.rotation().cwiseAbs() * bh;
  const double boxes = internal::box_distance(p.a_min, p.a_max, moved_c - moved_h, moved_c + moved_h);
  // About the symmetry: the side it does not move with sees it moved (B's by `motion`; with
  // A's, B's points moved is A's symmetry moved back), which shifts those distances by at
  // most symmetry_shift.
  double radial = -HUGE_VAL;
  if (p.symmetry_side == 1) {
    const double w = symmetry_shift(p.symmetry, motion, p.a_centre, p.a_radius);
    radial = std::max(p.b_range[0] - (p.a_range[1] + w), (p.a_range[0] - w) - p.b_range[1]);
  } else if (p.symmetry_side == 0) {
    const double w = symmetry_shift(p.symmetry, motion.inverse(), p.b_centre, p.b_radius);
    radial = std::max((p.b_range[0] - w) - p.a_range[1], p.a_range[0] - (p.b_range[1] + w));
  }
  return std::max({decayed, along, balls, boxes, radial}) - rounding;
}

bool gradient_proof_holds(const Gradient_proof& p, const Rigid_pose_3& motion, double length,
                          double& reach) {
  // The other box moved: centre mapped, half extents through |R|, widened by the rounding of
  // the pose products and of the map (a few ulps of the lengths involved).
  const Vec3 c = 0.5 * (p.other_min + p.other_max), h = 0.5 * (p.other_max - p.other_min);
  const Vec3 moved_c = motion.apply_point(c);
  const Vec3 moved_h = motion.rotation().cwiseAbs() * h +
                       Vec3::Constant(motion_rounding(c, h.cwiseAbs().maxCoeff(), motion, length));
  // (p_side - p_other) . d over the boxes, as holds_no_minimum takes it.
  internal::Interval g{0.0, 0.0};
  double rmax = 0.0, dmax = 0.0, d2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const internal::Interval r{p.own_min[k] - (moved_c[k] + moved_h[k]),
                               p.own_max[k] - (moved_c[k] - moved_h[k])};
    g = g + r * internal::Interval{p.derivative_min[k], p.derivative_max[k]};
    rmax = std::max({rmax, std::abs(r.lo), std::abs(r.hi)});
    const double m = std::max(std::abs(p.derivative_min[k]), std::abs(p.derivative_max[k]));
    dmax = std::max(dmax, m);
    d2 += m * m;
  }
  const double margin = 1e-12 * rmax * dmax;  // as holds_no_minimum's: far above rounding
  const double clearance = g.lo > margin ? g.lo - margin : (g.hi < -margin ? -g.hi - margin : 0.0);
  if (!(clearance > 0.0)) return false;
  reach = clearance / std::sqrt(d2);
  return true;
}

}  // namespace extremal
