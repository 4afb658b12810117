// The certified global solver's branch and bound (Global_distance.h, "Method"): the live nodes
// of both sides, the queue's entries, the sub-patch sides, and the solver, whose members are
// defined by concern: Distance_solver_walk.cpp (the queue and the walk), _bounds.cpp (lower
// bounds and kept bounds), _witness.cpp (witness search and polish), _exclusion.cpp (convexity
// certificates and gradient exclusion), _intersection.cpp (common points). Not API.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "algorithms/distance/Global_distance.h"
#include "algorithms/distance/internal/Bezier_net.h"
#include "algorithms/distance/internal/Restricted_solve.h"
#include "kernel/Error.h"
#include "kernel/Nurbs_refinement.h"

namespace extremal::internal {

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
  bool given = false;  // about Proof_request::stationary
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

// ---- The branch and bound -------------------------------------------------------------------

constexpr double k_prune = 0.999;
// While nothing can be pruned (no witness, no cutoff), a net this many times larger than the
// group it is paired with splits the group instead: only two nets give a witness. Set by hunt
// seed 1001, scene 3 (a 3,000 mm sheet against a 12-face part: no witness within 50,000 nodes
// splitting the sheet) and BodyScenes.TwoBodiesOfTheAs1AssemblyInRelativeMotion (at 4 its
// start found another pair of its parallel faces' continuum and kept 2 trackers, not 1).
constexpr double k_witness_split_ratio = 16.0;

struct Heap_order {
  bool operator()(const Pair_entry& x, const Pair_entry& y) const { return x.lower > y.lower; }
};

// The unit normal of a sub-patch's net, its diagonals crossed; false for curves and collapsed
// nets (a pole).
inline bool net_normal(const Live_node& n, const Vec3* cart, Vec3& axis) {
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
inline bool near_symmetry(const Symmetry& r, const Symmetry& s, double offset) {
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
inline bool second_derivatives_continuous(const Feature& f, int dir, double lo, double hi) {
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

inline int corner_count(const Live_node& n) { return n.dim == 0 ? 1 : n.dim == 1 ? 2 : 4; }

// Corner k of a net: its pole index and parameters (corners of a Bezier net lie on the piece).
inline int corner(const Live_node& n, int k, double q[2]) {
  const int iu = (k & 1) ? n.nu - 1 : 0;
  const int iv = (k & 2) ? n.nv - 1 : 0;
  q[0] = (k & 1) ? n.hi[0] : n.lo[0];
  q[1] = (k & 2) ? n.hi[1] : n.lo[1];
  return iu * n.nv + iv;
}

class Distance_solver {
 public:
  Distance_solver(const Distance_hierarchy& A, const Rigid_pose_3& X_WA, const Distance_hierarchy& B,
         const Rigid_pose_3& X_WB, const Distance_request& request,
         const Proof_request& proof, internal::Distance_scratch& scratch)
      : m_req(request), m_proof(proof), m_scratch(scratch) {
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
  // Without run(): the lower bound convexity gives over `box` about x (inside it), if the
  // squared distance is certified convex over the box at these poses (convex_region_lower).
  std::optional<double> convex_region_lower(const Parameter_box& box, const Vec4& x);

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
    return m_req.cutoff < HUGE_VAL && m_proof.cutoff_floor > -HUGE_VAL &&
           m_best.distance >= m_proof.cutoff_floor;
  }
  double prune_level() const { return proving() ? m_req.cutoff : m_best.distance; }
  // Local convexity certificates around Newton solutions (see certify_region).
  void try_certify(const Live_node& a, const Live_node& b);
  bool certify_region(internal::Known_solution& sol, const double* rho);
  // Whether |f_A - f_B|^2 is convex over reg's box (which holds x), and reg.lower the bound on
  // the distance there that convexity about x gives.
  bool convex_over(const Vec4& x, internal::Convex_region& reg);
  // m_resolution, from the two bodies' coordinates at their poses.
  void set_resolution();
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
  const Proof_request& m_proof;
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

}  // namespace extremal::internal
