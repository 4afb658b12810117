#include "algorithms/Global_distance.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "algorithms/internal/Bezier_net.h"
#include "kernel/Error.h"
#include "kernel/Nurbs_refinement.h"

namespace extremal {

const char* to_string(Distance_status s) {
  switch (s) {
    case Distance_status::Converged: return "converged";
    case Distance_status::Intersecting: return "intersecting";
    case Distance_status::Touching: return "touching";
    case Distance_status::Budget_exhausted: return "budget_exhausted";
    case Distance_status::Resolution_limit: return "resolution_limit";
  }
  return "?";
}

// ---- Workspace ------------------------------------------------------------------------------

namespace internal {

// A node of one side's search tree during a query: a group of the hierarchy's tree, or a Bezier
// sub-piece with its control net placed in the world.
struct Live_node {
  int tree = -1;  // >= 0: a group node of the hierarchy (no net)
  int element = -1;
  int dim = 0, nu = 1, nv = 1;
  int offset = -1;  // first pole in the side's pools
  double lo[2] = {0, 0}, hi[2] = {0, 0};
  Vec3 bmin = Vec3::Zero(), bmax = Vec3::Zero(), centre = Vec3::Zero();
  double radius = 0.0;
  double size = 0.0;  // box diagonal
  int split_dir = 0;  // the direction it is halved in (Side::split_direction)
  // A sub-patch's unit normal, its net's diagonals crossed, made on first use by
  // Solver::lower_bound (normal_state 0: not yet, 1: made, 2: none, a curve or collapsed net).
  Vec3 normal = Vec3::Zero();
  int normal_state = 0;
  // The range of its points' distances to its own element's centre or axis of symmetry ([0])
  // and to the other side's symmetry `range_symmetry` ([1]), made on first use by
  // Solver::symmetry_bound (range_state 0: not yet, 1: made, 2: none).
  double range_lo[2] = {0, 0}, range_hi[2] = {0, 0};
  int range_state[2] = {0, 0};
  int range_symmetry = -1;
  // Whether its element's symmetry is near that of the other side's `near_of` (-2: the point
  // element; -1: not known yet), see near_symmetry.
  int near_of = -1;
  bool near = false;
  int child[2] = {-1, -1};
  int depth = 0;
  int axis_stamp = -1;  // the witness axis axis_lo/hi were computed for
  double axis_lo = 0.0, axis_hi = 0.0;
  bool is_net() const { return tree < 0; }
  int count() const { return nu * nv; }
};

struct Pair_entry {
  double lower;
  int a, b;
};

struct Known_solution {
  int ea, eb;
  Vec4 params;
  double distance = HUGE_VAL;
  double tried = HUGE_VAL;  // size of the last region tried around it (see try_certify)
  bool certified = false;
  bool given = false;  // Distance_request::stationary: certified whatever its distance
};

// A box of parameters [A's..., B's...] of an element pair over which |f_A - f_B|^2 is proven
// convex, with the lower bound on the distance over the box that convexity gives.
struct Convex_region {
  int ea = -1, eb = -1;
  double lo[4] = {0, 0, 0, 0}, hi[4] = {0, 0, 0, 0};
  double lower = 0.0;
};

// A node's enclosure of its first derivatives (holds_no_minimum), made once per node: a node
// meets many nodes of the other side.
struct Gradient_enclosure {
  signed char state = 0;  // 0 not made yet, 1 made, -1 the enclosure failed
  Interval3 d[2];
};

struct Side_pools {
  std::vector<Live_node> nodes;
  std::vector<Hom, Eigen::aligned_allocator<Hom>> hom;
  std::vector<Vec3> cart;
  std::vector<Gradient_enclosure> gradients;  // by node, grown on demand
  void clear() {
    nodes.clear();
    hom.clear();
    cart.clear();
    gradients.clear();
  }
};

struct Distance_scratch {
  Side_pools side[2];
  std::vector<Pair_entry> heap;
  std::vector<Known_solution> solutions;
  std::vector<Convex_region> regions;
  std::vector<Hom, Eigen::aligned_allocator<Hom>> region_net;
  std::vector<Gradient_proof> proofs;  // Distance_workspace::gradient_proofs
  std::vector<Bound_proof> bounds;     // Distance_workspace::bound_proofs
  std::vector<int> sub_patches[2];     // Side::sub_patch's tables
  std::vector<Symmetry> placed[2];     // each side's Distance_hierarchy::symmetries(), world
  std::vector<char> along_motion[2];   // of those, the ones along Distance_request::motion_axis
};

}  // namespace internal

Distance_workspace::Distance_workspace() : m_scratch(std::make_unique<internal::Distance_scratch>()) {}
Distance_workspace::~Distance_workspace() = default;
Distance_workspace::Distance_workspace(Distance_workspace&&) noexcept = default;
Distance_workspace& Distance_workspace::operator=(Distance_workspace&&) noexcept = default;
const std::vector<Gradient_proof>& Distance_workspace::gradient_proofs() const {
  return m_scratch->proofs;
}
const std::vector<Bound_proof>& Distance_workspace::bound_proofs() const {
  return m_scratch->bounds;
}

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

// ---- The branch and bound -------------------------------------------------------------------

namespace {

using internal::Hom;
using internal::Live_node;
using internal::Pair_entry;
using internal::Side_pools;

constexpr double k_prune = 0.999;

struct Heap_order {
  bool operator()(const Pair_entry& x, const Pair_entry& y) const { return x.lower > y.lower; }
};

// The unit normal of a sub-patch's net, its diagonals crossed; false for curves and collapsed
// nets (a pole).
bool net_normal(const Live_node& n, const Vec3* cart, Vec3& axis) {
  if (n.dim != 2) return false;
  const int last = n.count() - 1, nv = n.nv;
  axis = (cart[last] - cart[0]).cross(cart[nv - 1] - cart[last - (nv - 1)]);
  const double length = axis.norm();
  if (!(length > 1e-12 * n.size * n.size)) return false;
  axis /= length;
  return true;
}

// Whether symmetry s (world) nearly holds r: the same centre, an axis along r's, or a centre on
// r's axis or r's centre on s's axis, within `offset` (and axes within 0.05 rad). Then the
// distances to r of an element symmetric about s vary little or not at all along its turns
// about s, so r's bound closes on a continuum of minima that the two share (a shaft in its
// bore, nested spheres, a sphere at a torus' centre).
constexpr double k_near_symmetry = 0.01;  // of the body's size
bool near_symmetry(const Symmetry& r, const Symmetry& s, double offset) {
  if (r.kind == Symmetry::Kind::Centre) return s.offset(r.point).norm() <= offset;
  if (s.kind == Symmetry::Kind::Centre) return r.offset(s.point).norm() <= offset;
  // s's line where it passes nearest r's point.
  const Vec3 nearest = s.point + (r.point - s.point).dot(s.direction) * s.direction;
  return r.direction.cross(s.direction).norm() <= 0.05 && r.offset(nearest).norm() <= offset;
}

// One side of the query: a hierarchy placed by a pose, with its live nodes.
struct Side {
  const Distance_hierarchy* h;
  const Rigid_pose_3* X;
  Side_pools* pools;

  int new_node() {
    pools->nodes.emplace_back();
    return static_cast<int>(pools->nodes.size()) - 1;
  }

  void finish_net(int index) {
    Live_node& n = pools->nodes[index];
    internal::net_bounds(pools->hom.data() + n.offset, n.count(), pools->cart.data() + n.offset,
                         n.bmin, n.bmax, n.centre, n.radius);
    n.size = (n.bmax - n.bmin).norm();
    n.split_dir = split_direction(n);
  }

  int make_from_tree(int tree_index, int depth) {
    const Distance_hierarchy::Tree_node& tn = h->tree()[tree_index];
    const int index = new_node();
    if (tn.piece < 0) {
      Live_node& n = pools->nodes[index];
      n.tree = tree_index;
      n.depth = depth;
      const Bbox_3 wb = transformed(tn.box, *X);
      n.bmin = Vec3(wb.xmin(), wb.ymin(), wb.zmin());
      n.bmax = Vec3(wb.xmax(), wb.ymax(), wb.zmax());
      n.centre = X->apply_point(tn.centre);
      n.radius = tn.radius;
      n.size = (n.bmax - n.bmin).norm();
      return index;
    }
    place_piece(index, h->pieces()[tn.piece], depth);
    finish_net(index);
    return index;
  }

  // Node `index` becomes piece p placed in the world.
  void place_piece(int index, const Distance_hierarchy::Piece& p, int depth) {
    const int count = p.nu * p.nv;
    const int offset = static_cast<int>(pools->hom.size());
    pools->hom.resize(offset + count);
    pools->cart.resize(offset + count);
    const Mat3& R = X->rotation();
    const Vec3& t = X->translation();
    const Eigen::Vector4d* src = h->poles() + p.offset;
    for (int k = 0; k < count; ++k) {
      Hom& q = pools->hom[offset + k];
      q.head<3>() = R * src[k].head<3>() + src[k][3] * t;
      q[3] = src[k][3];
    }
    Live_node& n = pools->nodes[index];
    n.element = p.element;
    n.dim = p.dimension;
    n.nu = p.nu;
    n.nv = p.nv;
    n.offset = offset;
    n.lo[0] = p.lo[0];
    n.lo[1] = p.lo[1];
    n.hi[0] = p.hi[0];
    n.hi[1] = p.hi[1];
    n.depth = depth;
  }

  // The node of element e's sub-patch over parameter box [lo, hi]: the one already made for
  // the same box (found through `table`, an open-addressed hash of node indices, -1 free,
  // its size a power of two above the number of boxes), or a new one, its piece's net
  // restricted to the box.
  int sub_patch(int e, const double* lo, const double* hi, std::vector<int>& table) {
    const int dim = h->elements()[e].feature.dimension();
    const double key[4] = {lo[0], hi[0], dim < 2 ? 0.0 : lo[1], dim < 2 ? 0.0 : hi[1]};
    std::uint64_t hash = 0x9e3779b97f4a7c15ull;
    for (const double x : key) {
      std::uint64_t bits;
      std::memcpy(&bits, &x, sizeof bits);
      hash = (hash ^ bits) * 0xff51afd7ed558ccdull;
      hash ^= hash >> 29;
    }
    const std::size_t mask = table.size() - 1;
    std::size_t slot = hash & mask;
    for (; table[slot] >= 0; slot = (slot + 1) & mask) {
      const Live_node& n = pools->nodes[table[slot]];
      if (n.lo[0] == key[0] && n.hi[0] == key[1] && (dim < 2 || (n.lo[1] == key[2] && n.hi[1] == key[3])))
        return table[slot];
    }
    table[slot] = make_sub_patch(e, dim, lo, hi);
    return table[slot];
  }

  int make_sub_patch(int e, int dim, const double* lo, const double* hi) {
    const Distance_hierarchy::Element& el = h->elements()[e];
    for (int q = el.first_piece; q < el.first_piece + el.piece_count; ++q) {
      const Distance_hierarchy::Piece& p = h->pieces()[q];
      double s0[2] = {0.0, 0.0}, s1[2] = {1.0, 1.0};
      bool inside = true;
      for (int k = 0; k < dim && inside; ++k) {
        const double span = p.hi[k] - p.lo[k];
        inside = p.lo[k] <= lo[k] && lo[k] < hi[k] && hi[k] <= p.hi[k] && span > 0.0;
        s0[k] = (lo[k] - p.lo[k]) / span;
        s1[k] = (hi[k] - p.lo[k]) / span;
      }
      if (!inside) continue;
      const int index = new_node();
      place_piece(index, p, 1);
      Live_node& n = pools->nodes[index];
      internal::restrict_net(pools->hom.data() + n.offset, n.nu, n.nv, s0[0], s1[0], s0[1], s1[1]);
      for (int k = 0; k < dim; ++k) {
        n.lo[k] = lo[k];
        n.hi[k] = hi[k];
      }
      finish_net(index);
      return index;
    }
    EXTREMAL_PRECONDITION_MSG(false, "sub-patch [" << lo[0] << ", " << hi[0] << "] x [" << lo[1]
                                                   << ", " << hi[1] << "] lies in no piece of element "
                                                   << e << " of '" << h->name() << "'");
    return -1;
  }

  // Direction a net is halved in: the one whose control polygon is longer.
  int split_direction(const Live_node& n) const {
    if (n.dim < 2) return 0;
    const Vec3* c = pools->cart.data() + n.offset;
    double eu = 0.0, ev = 0.0;
    for (int j = 0; j < n.nv; ++j) eu = std::max(eu, (c[(n.nu - 1) * n.nv + j] - c[j]).squaredNorm());
    for (int i = 0; i < n.nu; ++i)
      ev = std::max(ev, (c[i * n.nv + n.nv - 1] - c[i * n.nv]).squaredNorm());
    if (eu == ev) return (n.hi[0] - n.lo[0]) >= (n.hi[1] - n.lo[1]) ? 0 : 1;
    return eu > ev ? 0 : 1;
  }

  bool splittable(const Live_node& n, double resolution) const {
    if (!n.is_net()) return true;
    if (n.dim == 0 || n.size <= resolution) return false;
    const int dir = n.split_dir;
    const double lo = n.lo[dir], hi = n.hi[dir];
    const double mid = 0.5 * (lo + hi);
    return mid > lo && mid < hi;
  }

  // Children of node `index`, made on first use.
  void children(int index, int& c0, int& c1) {
    if (pools->nodes[index].child[0] >= 0) {
      c0 = pools->nodes[index].child[0];
      c1 = pools->nodes[index].child[1];
      return;
    }
    const Live_node parent = pools->nodes[index];  // copy: the vectors grow below
    if (!parent.is_net()) {
      const Distance_hierarchy::Tree_node& tn = h->tree()[parent.tree];
      c0 = make_from_tree(tn.left, parent.depth + 1);
      c1 = make_from_tree(tn.right, parent.depth + 1);
    } else {
      const int dir = parent.split_dir;
      const int count = parent.count();
      const int off0 = static_cast<int>(pools->hom.size());
      pools->hom.resize(off0 + 2 * count);
      pools->cart.resize(off0 + 2 * count);
      internal::split_net_half(pools->hom.data() + parent.offset, parent.nu, parent.nv, dir,
                               pools->hom.data() + off0, pools->hom.data() + off0 + count);
      const double mid = 0.5 * (parent.lo[dir] + parent.hi[dir]);
      for (int half = 0; half < 2; ++half) {
        const int ci = new_node();
        Live_node& c = pools->nodes[ci];
        c = parent;
        c.child[0] = c.child[1] = -1;
        c.axis_stamp = -1;
        c.normal_state = 0;
        c.range_state[0] = c.range_state[1] = 0;  // its own ranges are tighter than the parent's
        c.depth = parent.depth + 1;
        c.offset = off0 + half * count;
        if (half == 0)
          c.hi[dir] = mid;
        else
          c.lo[dir] = mid;
        finish_net(ci);
        (half == 0 ? c0 : c1) = ci;
      }
    }
    pools->nodes[index].child[0] = c0;
    pools->nodes[index].child[1] = c1;
  }

  const Vec3* cart(const Live_node& n) const { return pools->cart.data() + n.offset; }
  const Hom* hom(const Live_node& n) const { return pools->hom.data() + n.offset; }
};

struct Witness {
  double distance = HUGE_VAL;
  Vec3 pa = Vec3::Zero(), pb = Vec3::Zero();
  int ea = -1, eb = -1;
  double qa[2] = {0, 0}, qb[2] = {0, 0};
};

// Whether the second derivatives of f along parameter `dir` are continuous on the open interval
// (lo, hi): no knot there whose multiplicity exceeds the degree less 2.
bool second_derivatives_continuous(const Feature& f, int dir, double lo, double hi) {
  const std::vector<double>* knots = nullptr;
  int degree = 0;
  if (f.surface()) {
    knots = dir == 0 ? &f.surface()->knots_u() : &f.surface()->knots_v();
    degree = dir == 0 ? f.surface()->degree_u() : f.surface()->degree_v();
  } else if (f.curve()) {
    knots = &f.curve()->knots();
    degree = f.curve()->degree();
  } else {
    return true;
  }
  for (std::size_t k = 0; k < knots->size();) {
    std::size_t m = 1;
    while (k + m < knots->size() && (*knots)[k + m] == (*knots)[k]) ++m;
    const double t = (*knots)[k];
    if (t > lo && t < hi && degree - static_cast<int>(m) < 2) return false;
    k += m;
  }
  return true;
}

int corner_count(const Live_node& n) { return n.dim == 0 ? 1 : n.dim == 1 ? 2 : 4; }

// Corner k of a net: its pole index and parameters (corners of a Bezier net lie on the piece).
int corner(const Live_node& n, int k, double q[2]) {
  const int iu = (k & 1) ? n.nu - 1 : 0;
  const int iv = (k & 2) ? n.nv - 1 : 0;
  q[0] = (k & 1) ? n.hi[0] : n.lo[0];
  q[1] = (k & 2) ? n.hi[1] : n.lo[1];
  return iu * n.nv + iv;
}

class Solver {
 public:
  Solver(const Distance_hierarchy& A, const Rigid_pose_3& X_WA, const Distance_hierarchy& B,
         const Rigid_pose_3& X_WB, const Distance_request& request,
         internal::Distance_scratch& scratch)
      : m_req(request), m_scratch(scratch) {
    m_side[0] = Side{&A, &X_WA, &scratch.side[0]};
    m_side[1] = Side{&B, &X_WB, &scratch.side[1]};
  }

  // Only element ea of A against element eb of B (both >= 0), or everything (both -1).
  void restrict_to(int ea, int eb) {
    m_only[0] = ea;
    m_only[1] = eb;
  }
  // With restrict_to: only these sub-patch pairs of the two elements.
  void start_from(const std::vector<Sub_patch_pair>& starts) { m_starts = &starts; }
  Distance_result run();

 private:
  int m_only[2] = {-1, -1};
  const std::vector<Sub_patch_pair>* m_starts = nullptr;
  // A net normal along which lower_bound bounded a pair: B lies `gap` beyond A along `axis`
  // (gap -infinity: the bound came from elsewhere).
  struct Normal_gap {
    Vec3 axis = Vec3::Zero();
    double gap = -HUGE_VAL;
  };
  // `parent`: the bound of the pair this one was split from (-infinity: none); `normal`, if
  // given, receives the net normal the bound was taken along.
  double lower_bound(Live_node& a, Live_node& b, double cutoff, double parent = -HUGE_VAL,
                     Normal_gap* normal = nullptr);
  void project_on_axis(Live_node& n, int side);
  // The bound from both nets' distance ranges to a centre or axis of symmetry of either
  // element (Symmetry.h) that the other element nearly shares (near_symmetry), or against a
  // point, or that lies along Distance_request::motion_axis (against any element: kept, it
  // outlasts that turn); -infinity when there is none. Elsewhere it is one bound among others,
  // worth less than it costs (bench_global_distance's cylinder against torus: 13 to 19% more
  // instructions for 3% fewer nodes). `keep`, if given, records the symmetry and ranges of
  // the bound returned.
  double symmetry_bound(Live_node& a, Live_node& b, Bound_proof* keep = nullptr);
  // Node n of `side`: its range about symmetry `id` of side `owner`.
  bool range_about(Live_node& n, int side, int owner, int id, double& lo, double& hi);
  void corner_candidates(const Live_node& a, const Live_node& b);
  void polish(const Live_node& a, const Live_node& b);
  bool try_intersection(int ea, int eb, Vec4 x);
  bool try_intersection(const Live_node& a, const Live_node& b);
  void offer(double dist, const Vec3& pa, const Vec3& pb, int ea, const double* qa, int eb,
             const double* qb);
  double tolerance() const {
    const double rel = std::isfinite(m_best.distance) ? m_req.relative_tolerance * m_best.distance
                                                      : 0.0;
    return std::max({m_req.absolute_tolerance, rel, m_resolution});
  }
  const Feature& feature(int side, int element) const {
    return m_side[side].h->elements()[element].feature;
  }
  bool inside_known_solution(const Live_node& a, const Live_node& b) const;
  // Whether pairs are pruned against the cutoff while every witness lies at or above the floor
  // (Distance_request::cutoff_floor), and the level they are pruned against.
  bool proving() const {
    return m_req.cutoff < HUGE_VAL && m_req.cutoff_floor > -HUGE_VAL &&
           m_best.distance >= m_req.cutoff_floor;
  }
  double prune_level() const { return proving() ? m_req.cutoff : m_best.distance; }
  // Local convexity certificates around Newton solutions (see certify_region).
  void try_certify(const Live_node& a, const Live_node& b);
  bool certify_region(internal::Known_solution& sol, const double* rho);
  bool enclose_element(int side, int e, const double* lo, const double* hi, const Vec3& origin,
                       internal::Derivative_enclosure& out, int order);
  double region_bound(const Live_node& a, const Live_node& b) const;
  bool holds_no_minimum(int ia, int ib, int side);
  // Distance_request::keep_proofs: the pair (a, b) bounded by L.
  // `normal`: the net normal lower_bound bounded this pair along, if any.
  void keep_bound(Live_node& a, Live_node& b, double L, const Normal_gap* normal = nullptr);
  void classify_meeting();
  // A's outward unit normal at its witness (side 0), or minus B's (side 1); zero where that
  // side is no surface or has no normal there (a pole).
  Vec3 surface_normal(int side) const;
  void fill(Distance_result& r) const;

  const Distance_request& m_req;
  internal::Distance_scratch& m_scratch;
  Side m_side[2];
  Witness m_best;
  Vec3 m_axis = Vec3::Zero();
  bool m_have_axis = false;
  int m_axis_stamp = 0;
  double m_resolution = 0.0;
  double m_size[2] = {0.0, 0.0};  // each side's box diagonal
  bool m_met = false;  // a common point was found
  bool m_transversal = false;
  Vec3 m_meet_normal = Vec3::Zero();
  int m_newton_runs = 0;
  int m_intersection_attempts = 0;
  double m_reach[2] = {HUGE_VAL, HUGE_VAL};  // Distance_result::carried_reach
};

// Projection interval of a net on the witness axis, cached per node until the axis changes.
void Solver::project_on_axis(Live_node& n, int side) {
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

double Solver::lower_bound(Live_node& a, Live_node& b, double cutoff, double parent,
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

double Solver::symmetry_bound(Live_node& a, Live_node& b, Bound_proof* keep) {
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

bool Solver::range_about(Live_node& n, int side, int owner, int id, double& lo, double& hi) {
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

void Solver::offer(double dist, const Vec3& pa, const Vec3& pb, int ea, const double* qa, int eb,
                   const double* qb) {
  if (!(dist < m_best.distance)) return;
  m_best.distance = dist;
  m_best.pa = pa;
  m_best.pb = pb;
  m_best.ea = ea;
  m_best.eb = eb;
  m_best.qa[0] = qa[0];
  m_best.qa[1] = qa[1];
  m_best.qb[0] = qb[0];
  m_best.qb[1] = qb[1];
  if (dist > m_resolution) {
    m_axis = (pb - pa) / dist;
    m_have_axis = true;
    ++m_axis_stamp;
  }
}

void Solver::corner_candidates(const Live_node& a, const Live_node& b) {
  const Vec3* ca = m_side[0].cart(a);
  const Vec3* cb = m_side[1].cart(b);
  const Distance_hierarchy& ha = *m_side[0].h;
  const Distance_hierarchy& hb = *m_side[1].h;
  // Only pairs that can beat the best witness (offer takes nothing else) are asked whether
  // their corners lie on the body (inside the trim: a point location each), once per corner.
  const double limit2 = m_best.distance < HUGE_VAL
                            ? m_best.distance * m_best.distance * (1.0 + 1e-12)
                            : HUGE_VAL;
  double best = HUGE_VAL;
  int bi = -1, bj = -1;
  int on_b[4] = {-1, -1, -1, -1};  // unknown, no, yes
  for (int i = 0; i < corner_count(a); ++i) {
    double qa[2], qb[2];
    const Vec3& p = ca[corner(a, i, qa)];
    int on_a = -1;
    for (int j = 0; j < corner_count(b); ++j) {
      const double d2 = (cb[corner(b, j, qb)] - p).squaredNorm();
      if (!(d2 < best && d2 < limit2)) continue;
      if (on_a < 0) on_a = ha.on_body(a.element, qa) ? 1 : 0;
      if (!on_a) break;  // outside the trim: not on the body
      if (on_b[j] < 0) on_b[j] = hb.on_body(b.element, qb) ? 1 : 0;
      if (on_b[j]) {
        best = d2;
        bi = i;
        bj = j;
      }
    }
  }
  if (bi < 0) return;
  double qa[2], qb[2];
  const Vec3 pa = ca[corner(a, bi, qa)];
  const Vec3 pb = cb[corner(b, bj, qb)];
  offer(std::sqrt(best), pa, pb, a.element, qa, b.element, qb);
}

bool Solver::inside_known_solution(const Live_node& a, const Live_node& b) const {
  for (const auto& s : m_scratch.solutions) {
    if (s.ea != a.element || s.eb != b.element) continue;
    bool inside = true;
    for (int k = 0; k < a.dim; ++k) inside = inside && s.params[k] >= a.lo[k] && s.params[k] <= a.hi[k];
    for (int k = 0; k < b.dim; ++k)
      inside = inside && s.params[a.dim + k] >= b.lo[k] && s.params[a.dim + k] <= b.hi[k];
    if (inside) return true;
  }
  return false;
}

void Solver::polish(const Live_node& a, const Live_node& b) {
  if (!m_req.newton_polish || inside_known_solution(a, b)) return;
  const Feature& fa = feature(0, a.element);
  const Feature& fb = feature(1, b.element);
  Vec4 start = Vec4::Zero();
  for (int k = 0; k < a.dim; ++k) start[k] = 0.5 * (a.lo[k] + a.hi[k]);
  for (int k = 0; k < b.dim; ++k) start[a.dim + k] = 0.5 * (b.lo[k] + b.hi[k]);
  const Posed_feature pa{&fa, m_side[0].X, nullptr}, pb{&fb, m_side[1].X, nullptr};
  Newton_options opt;
  opt.max_iterations = 30;
  ++m_newton_runs;
  const Newton_result r = solve_pair_at_rest(pa, pb, start, opt);
  if (!r.params.allFinite()) return;
  Feature_point xa, xb;
  evaluate_feature(fa, *m_side[0].X, r.params.data(), xa, 0);
  evaluate_feature(fb, *m_side[1].X, r.params.data() + a.dim, xb, 0);
  const double d = (xb.p - xa.p).norm();
  if (r.converged) {
    m_scratch.solutions.push_back({a.element, b.element, r.params});
    m_scratch.solutions.back().distance = d;
  }
  if (!std::isfinite(d)) return;
  double qa[2] = {0, 0}, qb[2] = {0, 0};
  for (int k = 0; k < a.dim; ++k) qa[k] = r.params[k];
  for (int k = 0; k < b.dim; ++k) qb[k] = r.params[a.dim + k];
  if (!m_side[0].h->on_body(a.element, qa) || !m_side[1].h->on_body(b.element, qb)) return;
  offer(d, xa.p, xb.p, a.element, qa, b.element, qb);
}

// Hull bounds approach a minimum only quadratically in the sub-patch size, so certifying a
// smooth minimum to 1e-12 by subdivision alone takes sub-patches of 1e-6. Instead, around a
// Newton solution x* of an element pair: if the Hessian of D = |f_A - f_B|^2, enclosed by
// interval arithmetic on the hodographs of the sub-nets over a parameter box R about x*, is
// positive definite throughout R, then D is convex on R and
//   D(x) >= D(x*) + grad D(x*) . (x - x*)   for every x in R,
// whose minimum over R is D(x*) up to the Newton residual (and exact at a minimum on a domain
// edge, where the gradient points out of R). Every node pair inside R gets that bound.
// Enclosures of element e of `side` over the parameter box [lo, hi], with points relative to
// `origin` (a point near the box: interval arithmetic on the quotient rule loses |f| times the
// weight derivative's width, so f must be small).
bool Solver::enclose_element(int side, int e, const double* lo, const double* hi,
                             const Vec3& origin, internal::Derivative_enclosure& out, int order) {
  const Distance_hierarchy& h = *m_side[side].h;
  const int dim = feature(side, e).dimension();
  const Mat3& R = m_side[side].X->rotation();
  const Vec3& t = m_side[side].X->translation();
  auto& net = m_scratch.region_net;
  bool first = true;
  for (const Distance_hierarchy::Piece& piece : h.pieces()) {
    if (piece.element != e) continue;
    double s0[2] = {0.0, 0.0}, s1[2] = {1.0, 1.0}, width[2] = {1.0, 1.0};
    bool overlap = true;
    for (int k = 0; k < dim && overlap; ++k) {
      const double a = std::max(lo[k], piece.lo[k]), b = std::min(hi[k], piece.hi[k]);
      const double span = piece.hi[k] - piece.lo[k];
      overlap = a < b && span > 0.0;
      s0[k] = (a - piece.lo[k]) / span;
      s1[k] = (b - piece.lo[k]) / span;
      width[k] = b - a;
    }
    if (!overlap) continue;
    const int count = piece.nu * piece.nv;
    net.resize(count);
    const Eigen::Vector4d* src = h.poles() + piece.offset;
    for (int k = 0; k < count; ++k) {
      net[k].head<3>() = R * src[k].head<3>() + src[k][3] * (t - origin);
      net[k][3] = src[k][3];
    }
    if (dim >= 1) internal::restrict_net(net.data(), piece.nu, piece.nv, s0[0], s1[0], s0[1], s1[1]);
    internal::Derivative_enclosure enc;
    if (!internal::enclose_piece(net.data(), piece.nu, piece.nv, dim, width, enc, order))
      return false;
    internal::hull_into(out, enc, first);
    first = false;
  }
  return !first;
}

bool Solver::certify_region(internal::Known_solution& sol, const double* rho) {
  using internal::Interval;
  const Feature& fa = feature(0, sol.ea);
  const Feature& fb = feature(1, sol.eb);
  const int na = fa.dimension(), nb = fb.dimension(), n = na + nb;
  if (n == 0) return false;
  internal::Convex_region reg;
  reg.ea = sol.ea;
  reg.eb = sol.eb;
  for (int k = 0; k < n; ++k) {
    const Feature& f = k < na ? fa : fb;
    const int i = k < na ? k : k - na;
    reg.lo[k] = std::max(f.lower(i), sol.params[k] - rho[k]);
    reg.hi[k] = std::min(f.upper(i), sol.params[k] + rho[k]);
  }
  Feature_point xa, xb;
  evaluate_feature(fa, *m_side[0].X, sol.params.data(), xa, 2);
  evaluate_feature(fb, *m_side[1].X, sol.params.data() + na, xb, 2);
  internal::Derivative_enclosure A, B;
  if (!enclose_element(0, sol.ea, reg.lo, reg.hi, xa.p, A, 3) ||
      !enclose_element(1, sol.eb, reg.lo + na, reg.hi + na, xb.p, B, 3))
    return false;
  // The Hessian of D over R as intervals: A's rows, then B's.
  Interval H[4][4];
  internal::Interval3 r;
  for (int c = 0; c < 3; ++c) r[c] = Interval{xa.p[c] - xb.p[c], xa.p[c] - xb.p[c]} + (A.p[c] - B.p[c]);
  for (int k = 0; k < na; ++k)
    for (int l = 0; l < na; ++l)
      H[k][l] = 2.0 * ((k == l ? self_dot(A.d[k]) : dot(A.d[k], A.d[l])) + dot(r, A.dd[k][l]));
  for (int k = 0; k < na; ++k)
    for (int l = 0; l < nb; ++l) H[k][na + l] = H[na + l][k] = -2.0 * dot(A.d[k], B.d[l]);
  for (int k = 0; k < nb; ++k)
    for (int l = 0; l < nb; ++l)
      H[na + k][na + l] =
          2.0 * ((k == l ? self_dot(B.d[k]) : dot(B.d[k], B.d[l])) - dot(r, B.dd[k][l]));
  // A second enclosure, much tighter on small regions: the mean-value form about x*,
  // H(x) = H(x*) + sum_k dH/dx_k (eta) (x_k - x*_k), with the third derivatives enclosed over R.
  // The first-order variation of r . r_ij along the tangents (nearly orthogonal to r_ij at a
  // minimum) cancels here, where the plain enclosure counts every component's range in full.
  // H lies in both enclosures, so in their intersection. The form needs H continuous on R: no
  // knot inside R where a second derivative may jump (the plain enclosure, a hull over the
  // pieces, needs only the C1 continuity of D).
  bool smooth = true;
  for (int k = 0; k < n; ++k)
    smooth = smooth && second_derivatives_continuous(k < na ? fa : fb, k < na ? k : k - na,
                                                     reg.lo[k], reg.hi[k]);
  if (smooth) {
    // Derivatives of r = f_A - f_B along all n parameters (zero across the sides): at x*, and
    // enclosed over R.
    auto side_of = [&](int k) { return k < na ? 0 : 1; };
    auto local = [&](int k) { return k < na ? k : k - na; };
    const Vec3 r0 = xa.p - xb.p;
    Vec3 r1[4], r2[4][4];
    internal::Interval3 R1[4], R2[4][4], R3[4][4][4];
    const internal::Interval3 zero{};
    auto negate = [](const internal::Interval3& v) {
      internal::Interval3 m;
      for (int c = 0; c < 3; ++c) m[c] = Interval{-v[c].hi, -v[c].lo};
      return m;
    };
    for (int k = 0; k < n; ++k) {
      const int sk = side_of(k), ik = local(k);
      r1[k] = sk == 0 ? xa.d[ik] : Vec3(-xb.d[ik]);
      R1[k] = sk == 0 ? A.d[ik] : negate(B.d[ik]);
      for (int l = 0; l < n; ++l) {
        const bool same = side_of(l) == sk;
        const int il = local(l);
        r2[k][l] = !same ? Vec3::Zero() : sk == 0 ? xa.dd[ik][il] : Vec3(-xb.dd[ik][il]);
        R2[k][l] = !same ? zero : sk == 0 ? A.dd[ik][il] : negate(B.dd[ik][il]);
        for (int m = 0; m < n; ++m) {
          const bool all = same && side_of(m) == sk;
          R3[k][l][m] = !all ? zero : sk == 0 ? A.ddd[ik][il][local(m)]
                                              : negate(B.ddd[ik][il][local(m)]);
        }
      }
    }
    for (int i = 0; i < n; ++i)
      for (int j = i; j < n; ++j) {
        const double h0 = 2.0 * (r1[i].dot(r1[j]) + r0.dot(r2[i][j]));
        Interval delta{0.0, 0.0};
        for (int k = 0; k < n; ++k) {
          const Interval dH =
              2.0 * (dot(R2[i][k], R1[j]) + dot(R1[i], R2[j][k]) + dot(R1[k], R2[i][j]) +
                     dot(r, R3[i][j][k]));
          delta = delta + dH * Interval{reg.lo[k] - sol.params[k], reg.hi[k] - sol.params[k]};
        }
        const Interval mv{h0 + delta.lo, h0 + delta.hi};
        const Interval both{std::max(H[i][j].lo, mv.lo), std::min(H[i][j].hi, mv.hi)};
        if (!(both.lo <= both.hi)) return false;  // only by rounding: no certificate
        H[i][j] = H[j][i] = both;
      }
  }
  // Positive definite on all of R: after Jacobi scaling (centre C, radius Rad >= 0), for every
  // symmetric H the intervals hold and every unit x, with z = sign(x) and T = diag(z),
  //   x' H x >= x' C x - |x|' Rad |x| = x' (C - T Rad T) x,
  // so it suffices that the 2^(n-1) vertex matrices C - T Rad T (z and -z give the same) are
  // positive definite (Hertz 1992: their smallest eigenvalue is exactly that of the interval
  // matrix; Rohn's lambda_min(C) - rho(Rad) is never larger). Checked by Cholesky with a margin
  // of 1e-6, far above rounding.
  using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 4, 4>;
  Small C(n, n), Rad(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      C(i, j) = 0.5 * (H[i][j].lo + H[i][j].hi);
      Rad(i, j) = 0.5 * (H[i][j].hi - H[i][j].lo);
    }
  double S[4];
  for (int i = 0; i < n; ++i) {
    if (!(C(i, i) > 0.0)) return false;
    S[i] = 1.0 / std::sqrt(C(i, i));
  }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      C(i, j) *= S[i] * S[j];
      Rad(i, j) *= S[i] * S[j];
    }
  if (!C.allFinite() || !Rad.allFinite()) return false;
  for (int z = 0; z < (1 << (n - 1)); ++z) {
    double M[4][4];
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const bool flip = (((z >> i) ^ (z >> j)) & 1) != 0;
        M[i][j] = C(i, j) - (flip ? -Rad(i, j) : Rad(i, j)) - (i == j ? 1e-6 : 0.0);
      }
    if (!internal::cholesky_succeeds(M, n)) return false;
  }
  const Vec3 d = xa.p - xb.p;
  double D = d.squaredNorm();
  for (int k = 0; k < n; ++k) {
    const double g = k < na ? 2.0 * d.dot(xa.d[k]) : -2.0 * d.dot(xb.d[k - na]);
    D += std::min(g * (reg.lo[k] - sol.params[k]), g * (reg.hi[k] - sol.params[k]));
  }
  // Rounding in D(x*) is a few ulps of the coordinates: m_resolution covers it.
  reg.lower = std::sqrt(std::max(0.0, D)) - m_resolution;
  if (!std::isfinite(reg.lower)) return false;
  m_scratch.regions.push_back(reg);
  return true;
}

// Called for a popped pair of sub-patches: certifies a region about each uncertified solution
// inside the pair that could be the global minimum, with half-widths the pair's parameter
// widths, again each time the pairs around it have halved.
void Solver::try_certify(const Live_node& a, const Live_node& b) {
  for (internal::Known_solution& s : m_scratch.solutions) {
    if (s.certified || s.ea != a.element || s.eb != b.element) continue;
    if (!s.given && s.distance > m_best.distance + 1e-6 * (1.0 + m_best.distance)) continue;
    bool inside = true;
    for (int k = 0; k < a.dim; ++k) inside = inside && s.params[k] >= a.lo[k] && s.params[k] <= a.hi[k];
    for (int k = 0; k < b.dim; ++k)
      inside = inside && s.params[a.dim + k] >= b.lo[k] && s.params[a.dim + k] <= b.hi[k];
    if (!inside) continue;
    double rho[4] = {0, 0, 0, 0};
    double size = 0.0;  // largest half-width relative to its element's domain
    for (int k = 0; k < a.dim + b.dim; ++k) {
      const Live_node& n = k < a.dim ? a : b;
      const int i = k < a.dim ? k : k - a.dim;
      const Feature& f = feature(k < a.dim ? 0 : 1, n.element);
      rho[k] = n.hi[i] - n.lo[i];
      size = std::max(size, rho[k] / std::max(f.upper(i) - f.lower(i), 1e-300));
    }
    if (!(size <= 0.5 * s.tried)) continue;
    s.tried = size;
    s.certified = certify_region(s, rho);
  }
}

double Solver::region_bound(const Live_node& a, const Live_node& b) const {
  double L = 0.0;
  for (const internal::Convex_region& reg : m_scratch.regions) {
    if (reg.ea != a.element || reg.eb != b.element) continue;
    bool inside = true;
    for (int k = 0; k < a.dim; ++k) inside = inside && a.lo[k] >= reg.lo[k] && a.hi[k] <= reg.hi[k];
    for (int k = 0; k < b.dim; ++k)
      inside = inside && b.lo[k] >= reg.lo[a.dim + k] && b.hi[k] <= reg.hi[a.dim + k];
    if (inside) L = std::max(L, reg.lower);
  }
  return L;
}

// A pair of sub-patches holds no minimiser of the distance between the bodies when, on one
// side, the gradient of D = |f_A - f_B|^2 along that side's parameters is nowhere zero over the
// pair (its enclosure excludes zero in some component) and the sub-patch touches no open side
// of its element: a minimiser with that side's point inside the element's domain would make
// the gradient vanish, and one on a carried boundary (a trim edge, a face edge) lies on a curve
// element, whose own pairs hold it (or, with Distance_request::carried_sides, on a side whose
// minima another pair holds). Such a pair is dropped without a bound: the minimum lies in the
// pairs that remain. This is what certifies minima on trim boundaries, where the patch beyond
// the trim comes closer and no hull bound of the straddling sub-patches can rise above the
// minimum, and a face's minimum on a side it shares with a tracked face (a C0 crease) without
// solving it to the tie. Applied to trimmed faces and requested elements only (see below).
bool Solver::holds_no_minimum(int ia, int ib, int side) {
  const int in = side == 0 ? ia : ib;
  const Live_node& n = m_side[side].pools->nodes[in];
  const Live_node& o = m_side[1 - side].pools->nodes[side == 0 ? ib : ia];
  if (!n.is_net() || !o.is_net() || n.dim == 0) return false;
  const Distance_hierarchy::Element& el = m_side[side].h->elements()[n.element];
  // Trimmed faces, and restricted queries' elements with carried sides: elsewhere the hull
  // bounds rise above the minimum away from the stationary points, and near them the gradient
  // vanishes, so the enclosure would not pay.
  unsigned open = el.open_sides;
  // With carried sides requested, both elements of the restricted query: a pair away from the
  // other element's open sides (an ellipsoid's poles) is set aside by its gradient too.
  const bool requested = n.element == m_only[side] &&
                         (m_req.carried_sides[0] | m_req.carried_sides[1]) != 0u;
  if (requested) open &= ~m_req.carried_sides[side];
  if ((!el.trimmed && !requested) || m_side[side].h->reaches_uncarried(n.element, n.lo, n.hi, open))
    return false;
  auto& gradients = m_side[side].pools->gradients;
  if (gradients.size() <= static_cast<std::size_t>(in))
    gradients.resize(m_side[side].pools->nodes.size());
  internal::Gradient_enclosure& e = gradients[in];
  if (e.state == 0) {
    auto& net = m_scratch.region_net;
    const int count = n.count();
    net.resize(count);
    const Hom* src = m_side[side].pools->hom.data() + n.offset;
    for (int k = 0; k < count; ++k) {
      net[k] = src[k];
      net[k].head<3>() -= src[k][3] * n.centre;
    }
    const double width[2] = {n.hi[0] - n.lo[0], n.dim > 1 ? n.hi[1] - n.lo[1] : 1.0};
    internal::Derivative_enclosure full;
    e.state = internal::enclose_piece(net.data(), n.nu, n.nv, n.dim, width, full, 1) ? 1 : -1;
    e.d[0] = full.d[0];
    e.d[1] = full.d[1];
  }
  if (e.state < 0) return false;
  internal::Interval3 r;  // f_side - f_other over the pair, from the world boxes
  double rmax = 0.0;
  for (int c = 0; c < 3; ++c) {
    r[c] = internal::Interval{n.bmin[c] - o.bmax[c], n.bmax[c] - o.bmin[c]};
    rmax = std::max({rmax, std::abs(r[c].lo), std::abs(r[c].hi)});
  }
  for (int k = 0; k < n.dim; ++k) {
    const internal::Interval g = dot(r, e.d[k]);
    // Largest magnitude of each coordinate of the derivative over the node.
    double m[3];
    for (int c = 0; c < 3; ++c) m[c] = std::max(std::abs(e.d[k][c].lo), std::abs(e.d[k][c].hi));
    const double margin = 1e-12 * rmax * std::max({m[0], m[1], m[2]});  // far above rounding
    if (g.lo > margin || g.hi < -margin) {
      // The other side's points moving by s (this side's frame) change the component by at
      // most s |d_k|: it keeps its sign while s stays below this reach. Too short a reach
      // (a component near zero somewhere on the pair): split further instead.
      const double dk = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
      const double reach = ((g.lo > margin ? g.lo : -g.hi) - margin) / dk;
      if (reach < m_req.carried_min_reach) continue;
      m_reach[side] = std::min(m_reach[side], reach);
      if (!m_req.keep_proofs) return true;
      Gradient_proof& p = m_scratch.proofs.emplace_back();
      p.side = side;
      p.component = k;
      p.own_min = n.bmin;
      p.own_max = n.bmax;
      p.other_min = o.bmin;
      p.other_max = o.bmax;
      for (int c = 0; c < 3; ++c) {
        p.derivative_min[c] = e.d[k][c].lo;
        p.derivative_max[c] = e.d[k][c].hi;
      }
      for (int j = 0; j < 2; ++j) {
        p.own_lo[j] = n.lo[j];
        p.own_hi[j] = n.hi[j];
        p.other_lo[j] = o.lo[j];
        p.other_hi[j] = o.hi[j];
      }
      return true;
    }
  }
  return false;
}

void Solver::keep_bound(Live_node& a, Live_node& b, double L, const Normal_gap* normal) {
  if (!m_req.keep_proofs) return;
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

// Gauss-Newton on f(x_A) = h(x_B) from the centres of the two nodes: a common point ends the
// query with distance 0.
bool Solver::try_intersection(const Live_node& a, const Live_node& b) {
  Vec4 x = Vec4::Zero();
  for (int k = 0; k < a.dim; ++k) x[k] = 0.5 * (a.lo[k] + a.hi[k]);
  for (int k = 0; k < b.dim; ++k) x[a.dim + k] = 0.5 * (b.lo[k] + b.hi[k]);
  return try_intersection(a.element, b.element, x);
}

bool Solver::try_intersection(int ea, int eb, Vec4 x) {
  ++m_intersection_attempts;
  const Feature& fa = feature(0, ea);
  const Feature& fb = feature(1, eb);
  const int na = fa.dimension(), nb = fb.dimension(), n = na + nb;
  if (n == 0) return false;
  Vec4 max_step = Vec4::Zero();
  for (int k = 0; k < na; ++k) max_step[k] = 0.25 * (fa.upper(k) - fa.lower(k));
  for (int k = 0; k < nb; ++k) max_step[na + k] = 0.25 * (fb.upper(k) - fb.lower(k));
  const Parameter_domain domain = Parameter_domain::of(fa, fb);
  Feature_point xa, xb;
  double last = HUGE_VAL;
  int stalls = 0;
  for (int it = 0; it < 40; ++it) {
    const unsigned on_bound = domain.clamp(x), lower = domain.lower_mask(x);
    evaluate_feature(fa, *m_side[0].X, x.data(), xa, 1);
    evaluate_feature(fb, *m_side[1].X, x.data() + na, xb, 1);
    const Vec3 d = xa.p - xb.p;
    const double dn = d.norm();
    if (dn <= m_resolution) {
      double qa[2] = {x[0], na > 1 ? x[1] : 0.0}, qb[2] = {x[na], nb > 1 ? x[na + 1] : 0.0};
      if (na == 0) qa[0] = 0.0;
      if (nb == 0) qb[0] = qb[1] = 0.0;
      // A common point of the untrimmed patches outside a trim is not a common point.
      if (!m_side[0].h->on_body(ea, qa) || !m_side[1].h->on_body(eb, qb)) return false;
      const Vec3 mid = 0.5 * (xa.p + xb.p);
      m_best.distance = 0.0;
      m_best.pa = m_best.pb = mid;
      m_best.ea = ea;
      m_best.eb = eb;
      m_best.qa[0] = qa[0];
      m_best.qa[1] = qa[1];
      m_best.qb[0] = qb[0];
      m_best.qb[1] = qb[1];
      m_met = true;
      return true;
    }
    if (dn > 0.999 * last) {
      if (++stalls >= 3) return false;
    } else {
      stalls = 0;
    }
    last = std::min(last, dn);
    Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 4> J(3, n);
    for (int k = 0; k < na; ++k) J.col(k) = xa.d[k];
    for (int k = 0; k < nb; ++k) J.col(na + k) = -xb.d[k];
    Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 4, 1> s(n);
    // A parameter on a bound that the step would push outward is held and the step taken
    // without it: clamped, it stalled the search (a tilted cap's rim crossing a plate, started
    // from the rim: the bodies read 7e-11 apart, 5 deep).
    unsigned held = 0u;
    for (int pass = 0; pass <= n; ++pass) {
      Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 4> Jf = J;
      int free = n;
      for (int k = 0; k < n; ++k)
        if (held & (1u << k)) {
          Jf.col(k).setZero();
          --free;
        }
      if (free >= 3) {  // minimum-norm step
        Eigen::Matrix3d G = Jf * Jf.transpose();
        G.diagonal().array() += 1e-14 * G.trace() + 1e-300;
        s = -Jf.transpose() * G.ldlt().solve(d);
      } else {  // least squares
        Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 4, 4> G = Jf.transpose() * Jf;
        G.diagonal().array() += 1e-14 * G.trace() + 1e-300;
        s = -G.ldlt().solve(Jf.transpose() * d);  // zero along held columns
      }
      unsigned out = 0u;
      for (int k = 0; k < n; ++k)
        if ((on_bound & ~held & (1u << k)) && ((lower & (1u << k)) ? s[k] < 0.0 : s[k] > 0.0))
          out |= 1u << k;
      if (!out) break;
      held |= out;
    }
    if (!s.allFinite()) return false;
    double scale = 1.0;
    for (int k = 0; k < n; ++k)
      if (std::abs(s[k]) > max_step[k] && max_step[k] > 0.0)
        scale = std::min(scale, max_step[k] / std::abs(s[k]));
    for (int k = 0; k < n; ++k) x[k] += scale * s[k];
  }
  return false;
}

// At a common point: transversal when the tangent spaces together span space (a crossing that
// persists under perturbation), else touching; A's outward normal there when A is a surface.
void Solver::classify_meeting() {
  m_transversal = false;
  m_meet_normal.setZero();
  if (m_best.ea < 0 || m_best.eb < 0) return;
  const Feature& fa = feature(0, m_best.ea);
  const Feature& fb = feature(1, m_best.eb);
  const int na = fa.dimension(), nb = fb.dimension();
  Feature_point xa, xb;
  evaluate_feature(fa, *m_side[0].X, m_best.qa, xa, 1);
  evaluate_feature(fb, *m_side[1].X, m_best.qb, xb, 1);
  if (na + nb >= 3) {
    Eigen::Matrix3d G = Eigen::Matrix3d::Zero();
    for (int k = 0; k < na; ++k) G += xa.d[k].normalized() * xa.d[k].normalized().transpose();
    for (int k = 0; k < nb; ++k) G += xb.d[k].normalized() * xb.d[k].normalized().transpose();
    m_transversal = G.allFinite() && G.determinant() > 1e-9;
  }
  m_meet_normal = surface_normal(0);
  if (m_meet_normal == Vec3::Zero()) m_meet_normal = surface_normal(1);
}

Vec3 Solver::surface_normal(int side) const {
  const int e = side == 0 ? m_best.ea : m_best.eb;
  if (e < 0) return Vec3::Zero();
  const Feature& f = feature(side, e);
  if (f.dimension() != 2) return Vec3::Zero();
  Feature_point x;
  evaluate_feature(f, *m_side[side].X, side == 0 ? m_best.qa : m_best.qb, x, 1);
  const Vec3 nn = x.d[0].cross(x.d[1]) * f.outward_sign();
  // (At a pole the cross product is rounding: no normal.)
  const double n2 = nn.squaredNorm();
  if (!(n2 > 1e-16 * x.d[0].squaredNorm() * x.d[1].squaredNorm()) || !(n2 < HUGE_VAL))
    return Vec3::Zero();
  return (side == 0 ? 1.0 : -1.0) * nn / std::sqrt(n2);
}

void Solver::fill(Distance_result& r) const {
  r.upper_bound = m_best.distance;
  r.distance = m_best.distance;
  r.point_a = m_best.pa;
  r.point_b = m_best.pb;
  const auto& ea = m_side[0].h->elements();
  const auto& eb = m_side[1].h->elements();
  if (m_best.ea >= 0) {
    r.kind_a = ea[m_best.ea].kind;
    r.element_a = ea[m_best.ea].index;
    r.face_a = r.kind_a == Element_kind::Face ? r.element_a : -1;
  }
  if (m_best.eb >= 0) {
    r.kind_b = eb[m_best.eb].kind;
    r.element_b = eb[m_best.eb].index;
    r.face_b = r.kind_b == Element_kind::Face ? r.element_b : -1;
  }
  r.params_a = {m_best.qa[0], m_best.qa[1]};
  r.params_b = {m_best.qb[0], m_best.qb[1]};
  if (m_best.distance > 0.0) r.normal = (m_best.pb - m_best.pa) / m_best.distance;
  // At rounding distance the witnesses' direction is noise (a ball resting on a plane at its
  // pole, 6e-13 apart, read (-0.77, 0.60, -0.20)): the surfaces' normal, as at contact. Closer
  // than a millionth of the smaller body, the surface normal where it agrees with d within 5
  // degrees (a face's interior point: exact there; a cap at its rim is not, and d stays),
  // turned along d.
  const double small = m_size[0] > 0.0 && m_size[1] > 0.0 ? std::min(m_size[0], m_size[1])
                                                          : std::max(m_size[0], m_size[1]);
  if (m_best.distance <= 1e-6 * small) {
    const Vec3 n[2] = {surface_normal(0), surface_normal(1)};
    if (m_best.distance <= 1e-12 * small) {
      const Vec3& m = n[0] != Vec3::Zero() ? n[0] : n[1];
      if (m != Vec3::Zero()) r.normal = m.dot(r.normal) < 0.0 ? Vec3(-m) : m;
    } else {
      const double c[2] = {n[0].dot(r.normal), n[1].dot(r.normal)};
      const int k = std::abs(c[0]) >= std::abs(c[1]) ? 0 : 1;
      if (std::abs(c[k]) >= 0.996) r.normal = c[k] < 0.0 ? Vec3(-n[k]) : n[k];
    }
  }
  r.newton_runs = m_newton_runs;
  r.intersection_attempts = m_intersection_attempts;
  r.nodes_created = static_cast<long>(m_side[0].pools->nodes.size() + m_side[1].pools->nodes.size());
}

Distance_result Solver::run() {
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  for (auto& s : m_scratch.side) s.clear();
  m_scratch.heap.clear();
  m_scratch.solutions.clear();
  m_scratch.regions.clear();
  m_scratch.proofs.clear();
  m_scratch.bounds.clear();
  for (int side = 0; side < 2; ++side) {
    const Bbox_3& box = m_side[side].h->box();
    m_size[side] =
        Vec3(box.xmax() - box.xmin(), box.ymax() - box.ymin(), box.zmax() - box.zmin()).norm();
    const std::vector<Symmetry>& own = m_side[side].h->symmetries();
    m_scratch.placed[side].resize(own.size());
    m_scratch.along_motion[side].resize(own.size());
    for (std::size_t k = 0; k < own.size(); ++k) {
      m_scratch.placed[side][k] = own[k].placed(*m_side[side].X);
      m_scratch.along_motion[side][k] =
          m_req.motion_axis.any() && near_symmetry(m_req.motion_axis, m_scratch.placed[side][k],
                                                   k_near_symmetry * m_size[side]);
    }
  }

  // Floating-point resolution of the scene: coordinates are good to a few ulps of their size,
  // in the world and in the body frames they were placed from (a part modelled in assembly
  // coordinates, 1.7e3 from its frame's origin, placed near the world's: its world points
  // carry the rounding of 1.7e3, and a ball through it read 2e-13 'apart').
  double coord = 0.0;
  for (int side = 0; side < 2; ++side) {
    const Bbox_3& body = m_side[side].h->box();
    const Bbox_3 world = transformed(body, *m_side[side].X);
    for (int k = 0; k < 3; ++k)
      coord = std::max({coord, std::abs(world.min(k)), std::abs(world.max(k)),
                        std::abs(body.min(k)), std::abs(body.max(k)),
                        std::abs(m_side[side].X->translation()[k])});
  }
  m_resolution = 16.0 * std::numeric_limits<double>::epsilon() * std::max(coord, 1e-300);

  Distance_result result;
  if (m_req.cutoff < HUGE_VAL && m_req.cutoff > m_resolution) m_best.distance = m_req.cutoff;  // no witness yet (ea = -1)
  if (m_req.stationary && m_only[0] >= 0 && m_only[1] >= 0) {
    internal::Known_solution s{m_only[0], m_only[1], Vec4::Zero()};
    for (int k = 0; k < 4; ++k) s.params[k] = (*m_req.stationary)[k];
    s.given = true;
    m_scratch.solutions.push_back(s);
  }
  auto& heap = m_scratch.heap;
  double dropped = HUGE_VAL;  // smallest bound among pruned and settled pairs
  if (m_starts != nullptr) {
    // Sub-patch pairs of an earlier query whose proofs failed: each boxed anew at these poses,
    // each sub-patch made once.
    std::size_t size = 16;
    while (size < 2 * m_starts->size()) size *= 2;
    for (auto& table : m_scratch.sub_patches) table.assign(size, -1);
    for (const Sub_patch_pair& s : *m_starts) {
      const int na = m_side[0].sub_patch(m_only[0], s.a_lo.data(), s.a_hi.data(), m_scratch.sub_patches[0]);
      const int nb = m_side[1].sub_patch(m_only[1], s.b_lo.data(), s.b_hi.data(), m_scratch.sub_patches[1]);
      const double cutoff = prune_level() - k_prune * tolerance();
      const double L =
          lower_bound(m_side[0].pools->nodes[na], m_side[1].pools->nodes[nb], cutoff);
      if (L >= cutoff) {
        dropped = std::min(dropped, L);
        keep_bound(m_side[0].pools->nodes[na], m_side[1].pools->nodes[nb], L);
        continue;
      }
      if (holds_no_minimum(na, nb, 0) || holds_no_minimum(na, nb, 1)) continue;
      heap.push_back({L, na, nb});
      std::push_heap(heap.begin(), heap.end(), Heap_order());
    }
  } else if (m_only[0] < 0) {
    const int ra = m_side[0].make_from_tree(0, 0);
    const int rb = m_side[1].make_from_tree(0, 0);
    heap.push_back({lower_bound(m_side[0].pools->nodes[ra], m_side[1].pools->nodes[rb], HUGE_VAL),
                    ra, rb});
  } else {
    // The pieces of the two elements, pair by pair.
    const auto& ea = m_side[0].h->elements()[m_only[0]];
    const auto& eb = m_side[1].h->elements()[m_only[1]];
    const int first_b = static_cast<int>(m_side[1].pools->nodes.size());
    for (int q = 0; q < eb.piece_count; ++q)
      m_side[1].make_from_tree(m_side[1].h->leaf_of_piece(eb.first_piece + q), 1);
    for (int p = 0; p < ea.piece_count; ++p) {
      const int na = m_side[0].make_from_tree(m_side[0].h->leaf_of_piece(ea.first_piece + p), 1);
      if (!m_side[0].h->may_hold_trimmed(m_only[0], m_side[0].pools->nodes[na].lo,
                                         m_side[0].pools->nodes[na].hi))
        continue;
      for (int q = 0; q < eb.piece_count; ++q) {
        const int nb = first_b + q;
        if (!m_side[1].h->may_hold_trimmed(m_only[1], m_side[1].pools->nodes[nb].lo,
                                           m_side[1].pools->nodes[nb].hi))
          continue;
        heap.push_back({lower_bound(m_side[0].pools->nodes[na], m_side[1].pools->nodes[nb],
                                    HUGE_VAL),
                        na, nb});
        std::push_heap(heap.begin(), heap.end(), Heap_order());
      }
    }
  }
  bool out_of_budget = false;
  long pops = 0;

  while (!heap.empty()) {
    const Pair_entry top = heap.front();
    // Prune against 0.999 of the tolerance so that rounding in upper - lower cannot push the
    // final gap past it.
    if (top.lower >= prune_level() - k_prune * tolerance()) break;
    if (static_cast<long>(m_side[0].pools->nodes.size() + m_side[1].pools->nodes.size()) >
        m_req.max_nodes) {
      out_of_budget = true;
      break;
    }
    if (m_req.max_seconds > 0.0 && (pops & 63) == 0 &&
        std::chrono::duration<double>(clock::now() - t0).count() > m_req.max_seconds) {
      out_of_budget = true;
      break;
    }
    std::pop_heap(heap.begin(), heap.end(), Heap_order());
    heap.pop_back();
    ++pops;
    const Live_node a = m_side[0].pools->nodes[top.a];
    const Live_node b = m_side[1].pools->nodes[top.b];
    if (a.is_net() && b.is_net()) {
      const double before = m_best.distance;
      corner_candidates(a, b);
      if (m_best.distance < before) polish(a, b);
      // (While proving a cutoff, convexity bounds around a witness above the floor would
      // settle nothing: the pairs there are set aside or split until they clear the cutoff.)
      if (m_req.newton_polish && !m_scratch.solutions.empty() && (!proving() || m_req.stationary))
        try_certify(a, b);
      // (A pair left here for a meeting keeps its bound: the kept proofs cover the domains.)
      if (top.lower <= m_resolution && m_best.distance > m_resolution &&
          m_intersection_attempts < 64 && (a.depth + b.depth) % 3 == 0) {
        if (try_intersection(a, b)) {
          keep_bound(m_side[0].pools->nodes[top.a], m_side[1].pools->nodes[top.b], top.lower);
          break;
        }
      }
      if (m_best.distance <= m_resolution) {
        keep_bound(m_side[0].pools->nodes[top.a], m_side[1].pools->nodes[top.b], top.lower);
        break;
      }
    }
    const bool sa = m_side[0].splittable(a, m_resolution);
    const bool sb = m_side[1].splittable(b, m_resolution);
    if (!sa && !sb) {
      dropped = std::min(dropped, top.lower);
      keep_bound(m_side[0].pools->nodes[top.a], m_side[1].pools->nodes[top.b], top.lower);
      continue;
    }
    const int which = (sa && (!sb || a.size >= b.size)) ? 0 : 1;
    int c[2];
    m_side[which].children(which == 0 ? top.a : top.b, c[0], c[1]);
    for (int k = 0; k < 2; ++k) {
      const int ia = which == 0 ? c[k] : top.a;
      const int ib = which == 1 ? c[k] : top.b;
      {  // a piece of a trimmed face whose parameter box misses the trim holds nothing
        const Live_node& child = m_side[which].pools->nodes[c[k]];
        if (child.is_net() &&
            !m_side[which].h->may_hold_trimmed(child.element, child.lo, child.hi))
          continue;
      }
      const double cutoff = prune_level() - k_prune * tolerance();
      Normal_gap normal;
      const double L =
          std::max(top.lower, lower_bound(m_side[0].pools->nodes[ia], m_side[1].pools->nodes[ib],
                                          cutoff, top.lower, &normal));
      if (L < cutoff) {
        if (holds_no_minimum(ia, ib, 0) || holds_no_minimum(ia, ib, 1)) continue;
        heap.push_back({L, ia, ib});
        std::push_heap(heap.begin(), heap.end(), Heap_order());
      } else {
        dropped = std::min(dropped, L);
        keep_bound(m_side[0].pools->nodes[ia], m_side[1].pools->nodes[ib], L, &normal);
      }
    }
  }
  if (m_req.keep_proofs)
    for (const Pair_entry& e : heap)
      keep_bound(m_side[0].pools->nodes[e.a], m_side[1].pools->nodes[e.b], e.lower);
  // Smallest bound of the pairs pruned, settled or left open (set-aside pairs are in none).
  const double open_lower = heap.empty() ? dropped : std::min(dropped, heap.front().lower);
  // Bounds that reach zero with a witness that does not: look for a common point from the
  // witness, so that bodies that meet are never reported a rounding error apart.
  if (!m_met && m_best.ea >= 0 && m_best.distance > m_resolution) {
    if (std::min(open_lower, m_best.distance) <= m_resolution) {
      const int na = feature(0, m_best.ea).dimension();
      Vec4 x = Vec4::Zero();
      for (int k = 0; k < na; ++k) x[k] = m_best.qa[k];
      for (int k = 0; k < feature(1, m_best.eb).dimension(); ++k) x[na + k] = m_best.qb[k];
      try_intersection(m_best.ea, m_best.eb, x);
    }
  }
  result.pairs_processed = pops;
  fill(result);
  result.uncarried_lower_bound = std::max(0.0, open_lower);
  result.carried_reach = {m_reach[0], m_reach[1]};
  if (m_met || m_best.distance <= m_resolution) {
    // The bodies meet: report exactly zero, never a rounding-level positive number.
    classify_meeting();
    result.distance = result.upper_bound = result.lower_bound = 0.0;
    result.uncarried_lower_bound = 0.0;
    const Vec3 mid = 0.5 * (m_best.pa + m_best.pb);
    result.point_a = result.point_b = mid;
    result.normal = m_meet_normal;
    result.status = m_transversal ? Distance_status::Intersecting
                                             : Distance_status::Touching;
    result.tolerance_used = tolerance();
    return result;
  }
  result.lower_bound = std::max(0.0, std::min(open_lower, m_best.distance));
  result.tolerance_used = tolerance();
  const double gap = result.upper_bound - result.lower_bound;
  if (out_of_budget)
    result.status = Distance_status::Budget_exhausted;
  else if (gap <= result.tolerance_used)
    result.status = Distance_status::Converged;
  else
    result.status = Distance_status::Resolution_limit;
  return result;
}

}  // namespace

Distance_result extremal_distance(const Distance_hierarchy& A, const Rigid_pose_3& X_WA,
                                  const Distance_hierarchy& B, const Rigid_pose_3& X_WB,
                                  const Distance_request& request, Distance_workspace& workspace) {
  EXTREMAL_PRECONDITION_MSG(request.absolute_tolerance >= 0.0 && request.relative_tolerance >= 0.0 &&
                                (request.absolute_tolerance > 0.0 || request.relative_tolerance > 0.0),
                            "tolerances must be >= 0 and not both 0, got absolute "
                                << request.absolute_tolerance << ", relative "
                                << request.relative_tolerance);
  EXTREMAL_PRECONDITION_MSG(request.max_nodes > 0, "max_nodes must be > 0, got " << request.max_nodes);
  EXTREMAL_PRECONDITION_MSG(request.max_seconds >= 0.0,
                            "max_seconds must be >= 0, got " << request.max_seconds);
  Solver solver(A, X_WA, B, X_WB, request, workspace.scratch());
  return solver.run();
}

namespace {
// Element a of A against element b of B, from their pieces or from `starts` (if not null).
Distance_result restricted_query(const Distance_hierarchy& A, const Rigid_pose_3& X_WA,
                                 int element_a, const Distance_hierarchy& B,
                                 const Rigid_pose_3& X_WB, int element_b,
                                 const std::vector<Sub_patch_pair>* starts,
                                 const Distance_request& request, Distance_workspace& workspace) {
  EXTREMAL_PRECONDITION_MSG(
      element_a >= 0 && element_a < static_cast<int>(A.elements().size()) && element_b >= 0 &&
          element_b < static_cast<int>(B.elements().size()),
      "no element pair (" << element_a << ", " << element_b << ") in '" << A.name() << "' and '"
                          << B.name() << "'");
  EXTREMAL_PRECONDITION_MSG(request.max_nodes > 0, "max_nodes must be > 0, got " << request.max_nodes);
  Solver solver(A, X_WA, B, X_WB, request, workspace.scratch());
  solver.restrict_to(element_a, element_b);
  if (starts != nullptr) solver.start_from(*starts);
  return solver.run();
}
}  // namespace

Distance_result extremal_distance_between(const Distance_hierarchy& A, const Rigid_pose_3& X_WA,
                                          int element_a, const Distance_hierarchy& B,
                                          const Rigid_pose_3& X_WB, int element_b,
                                          const Distance_request& request,
                                          Distance_workspace& workspace) {
  return restricted_query(A, X_WA, element_a, B, X_WB, element_b, nullptr, request, workspace);
}

Distance_result extremal_distance_between(const Distance_hierarchy& A, const Rigid_pose_3& X_WA,
                                          int element_a, const Distance_hierarchy& B,
                                          const Rigid_pose_3& X_WB, int element_b,
                                          const std::vector<Sub_patch_pair>& starts,
                                          const Distance_request& request,
                                          Distance_workspace& workspace) {
  return restricted_query(A, X_WA, element_a, B, X_WB, element_b, &starts, request, workspace);
}

Distance_result extremal_distance(const Distance_hierarchy& A, const Rigid_pose_3& X_WA,
                                  const Distance_hierarchy& B, const Rigid_pose_3& X_WB,
                                  const Distance_request& request) {
  Distance_workspace ws;
  return extremal_distance(A, X_WA, B, X_WB, request, ws);
}

Distance_result extremal_distance(const Body& A, const Rigid_pose_3& X_WA, const Body& B,
                                  const Rigid_pose_3& X_WB, const Distance_request& request) {
  const Distance_hierarchy ha(A), hb(B);
  return extremal_distance(ha, X_WA, hb, X_WB, request);
}

// ---- Trackers -------------------------------------------------------------------------------

namespace {

Feature feature_of(const Body& body, Element_kind kind, int index, const char* which) {
  switch (kind) {
    case Element_kind::Point:
      EXTREMAL_PRECONDITION_MSG(body.is_point, "body " << which << " '" << body.name
                                                       << "' is not a point body");
      return Feature::point(Vec3::Zero());
    case Element_kind::Face:
      EXTREMAL_PRECONDITION_MSG(index >= 0 && index < static_cast<int>(body.faces.size()),
                                "body " << which << " '" << body.name << "' has no face " << index);
      return Feature::surface(body.faces[index].surface);
    case Element_kind::Curve: {
      const int nc = static_cast<int>(body.curves.size());
      if (index >= nc && index - nc < static_cast<int>(body.edges.size()) &&
          body.edges[index - nc].curve)  // a B-rep edge's 3D curve
        return Feature::curve(*body.edges[index - nc].curve);
      EXTREMAL_PRECONDITION_MSG(index >= 0 && index < nc,
                                "body " << which << " '" << body.name << "' has no curve " << index);
      return Feature::curve(body.curves[index]);
    }
  }
  return Feature::point(Vec3::Zero());
}

}  // namespace

Tracker_seed tracker_seed(const Body& A, const Body& B, const Distance_result& r) {
  Tracker_seed s;
  s.kind_a = r.kind_a;
  s.kind_b = r.kind_b;
  s.element_a = r.element_a;
  s.element_b = r.element_b;
  s.feature_a = feature_of(A, r.kind_a, r.element_a, "A");
  s.feature_b = feature_of(B, r.kind_b, r.element_b, "B");
  const int na = s.feature_a.dimension();
  for (int k = 0; k < na; ++k) s.params[k] = r.params_a[k];
  for (int k = 0; k < s.feature_b.dimension(); ++k) s.params[na + k] = r.params_b[k];
  return s;
}

Audit_decision audit_tracked_pair(const Distance_result& global, double tracked_distance,
                                  Element_kind kind_a, int element_a, Element_kind kind_b,
                                  int element_b, double margin) {
  Audit_decision d;
  d.same_elements = global.kind_a == kind_a && global.element_a == element_a &&
                    global.kind_b == kind_b && global.element_b == element_b;
  d.improvement = tracked_distance - global.upper_bound;
  const double tol = std::max(global.upper_bound - global.lower_bound, global.tolerance_used);
  // The tracked pair is a real pair, so tracked_distance >= true minimum >= lower_bound. Re-seed
  // when the certified minimum lies clearly below it, wherever the global witness is (a pair on
  // the same elements can sit in another basin: another local minimum of the same faces).
  d.reseed = d.improvement > tol + margin;
  return d;
}

}  // namespace extremal
