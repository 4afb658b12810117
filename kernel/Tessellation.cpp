// Grid tessellation of faces at a guaranteed chordal deviation (kernel/Tessellation.h).
//
// Per face: (1) plan: the face's Bezier spans, split in halves while that tightens the
// derivative bounds, each give the grid spacing they need; the grid has a line at every span
// and split boundary and, between two lines, the finest spacing any span there asks for; a
// trimmed face's cells are also kept short enough for its trim (plan_face).
// (2) build: the grid is walked row by row (two rows of vertex indices live at a time), vertices
// are evaluated when a kept triangle first uses them, seams and collapsed sides map their grid
// nodes to one vertex, and a trimmed face's cells are clipped by the trim (cell_triangles).
#include "kernel/Tessellation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include "kernel/Nurbs_refinement.h"
#include "kernel/internal/Bspline_basis.h"

namespace extremal {

namespace {

// A span needing more grid cells than this along a direction is split in two there, when the
// halves' bounds ask for fewer cells in all (below): the bounds over a smaller span are tighter.
constexpr double k_split_cells = 4.0;
// Splits kept only when they cut the span's planned cells to at most this fraction.
constexpr double k_split_gain = 0.8;
// At most this many halvings of a Bezier span per direction (up to 2^4 x 2^4 pieces).
constexpr int k_max_split_depth = 4;
// The plan alone may ask for up to this many times the triangle cap before the build starts
// (a trimmed face keeps only the cells inside its trim); beyond it nothing is built.
constexpr double k_grid_over_cap = 8.0;
// Trim curves whose control points are this close to a side of the patch domain (relative to
// its larger width) lie on it: the trim does not cut into the patch there.
constexpr double k_side_relative = 1e-9;
// Trimmed faces get grid cells no longer than a chord of deviation D on a circle of this radius
// times the face's size (plan_face).
constexpr double k_trim_radius = 1.0;
// A trimmed face's cells are halved from its size while that adds more than 1 - this to its
// kept area (plan_face), at most k_max_trim_halvings times (cells 2^-8 of the face's size).
constexpr double k_trim_coverage = 0.95;
constexpr int k_max_trim_halvings = 8;
// Bisection steps locating a trim crossing on a grid edge: 2^-30 of the edge.
constexpr int k_bisection_steps = 30;
// Grid nodes on a side or seam whose points differ by at most this fraction of the patch's
// coordinate size are one vertex (rounding at a sphere's pole, at a closed seam).
constexpr double k_weld_relative = 1e-12;

// A bivariate Bernstein polynomial on [0, 1]^2 with `dim` components per coefficient:
// coefficient (i, j) is c[(i * (n + 1) + j) * dim ...], i along u (degree m), j along v (n).
struct Bernstein {
  int m = 0, n = 0, dim = 1;
  std::vector<double> c;
  Bernstein() = default;
  Bernstein(int m_, int n_, int dim_)
      : m(m_), n(n_), dim(dim_), c(static_cast<std::size_t>((m_ + 1) * (n_ + 1) * dim_), 0.0) {}
  double* at(int i, int j) { return &c[static_cast<std::size_t>((i * (n + 1) + j) * dim)]; }
  const double* at(int i, int j) const {
    return &c[static_cast<std::size_t>((i * (n + 1) + j) * dim)];
  }
};

// Binomial coefficients C(n, k) for n up to three times the largest degree (the degree of
// w^3 S_xy), exact in double.
constexpr int k_max_binomial = 3 * k_max_degree + 1;
double binomial(int n, int k) {
  static const auto table = [] {
    std::vector<double> t(static_cast<std::size_t>(k_max_binomial + 1) * (k_max_binomial + 1), 0.0);
    for (int a = 0; a <= k_max_binomial; ++a) {
      t[static_cast<std::size_t>(a) * (k_max_binomial + 1)] = 1.0;
      for (int b = 1; b <= a; ++b)
        t[static_cast<std::size_t>(a) * (k_max_binomial + 1) + b] =
            t[static_cast<std::size_t>(a - 1) * (k_max_binomial + 1) + b - 1] +
            (b < a ? t[static_cast<std::size_t>(a - 1) * (k_max_binomial + 1) + b] : 0.0);
    }
    return t;
  }();
  EXTREMAL_PRECONDITION(n >= 0 && n <= k_max_binomial && k >= 0 && k <= n);
  return table[static_cast<std::size_t>(n) * (k_max_binomial + 1) + k];
}

// d/du on [0, 1]: degree m - 1, coefficients m (c[i+1] - c[i]); a degree-0 direction gives 0.
Bernstein diff(const Bernstein& a, bool in_u) {
  const int m = in_u ? std::max(a.m - 1, 0) : a.m, n = in_u ? a.n : std::max(a.n - 1, 0);
  Bernstein r(m, n, a.dim);
  if ((in_u ? a.m : a.n) == 0) return r;
  const double k = in_u ? a.m : a.n;
  for (int i = 0; i <= m; ++i)
    for (int j = 0; j <= n; ++j)
      for (int d = 0; d < a.dim; ++d)
        r.at(i, j)[d] = k * ((in_u ? a.at(i + 1, j) : a.at(i, j + 1))[d] - a.at(i, j)[d]);
  return r;
}

// s * a, s scalar (dim 1): B_i^m B_k^p = C(m,i) C(p,k) / C(m+p, i+k) B_{i+k}^{m+p} per direction.
// Computed in the scaled (power-like) basis C(m,i) B_i^m, where the product is a plain
// convolution, and scaled back.
Bernstein product(const Bernstein& s, const Bernstein& a) {
  Bernstein r(s.m + a.m, s.n + a.n, a.dim);
  Bernstein as = a;
  for (int k = 0; k <= a.m; ++k)
    for (int l = 0; l <= a.n; ++l) {
      const double f = binomial(a.m, k) * binomial(a.n, l);
      for (int d = 0; d < a.dim; ++d) as.at(k, l)[d] *= f;
    }
  const int row = (a.n + 1) * a.dim;
  for (int i = 0; i <= s.m; ++i)
    for (int j = 0; j <= s.n; ++j) {
      const double sij = s.at(i, j)[0] * binomial(s.m, i) * binomial(s.n, j);
      if (sij == 0.0) continue;
      for (int k = 0; k <= a.m; ++k) {
        double* out = r.at(i + k, j);
        const double* in = as.at(k, 0);
        for (int x = 0; x < row; ++x) out[x] += sij * in[x];
      }
    }
  for (int i = 0; i <= r.m; ++i)
    for (int j = 0; j <= r.n; ++j) {
      const double f = 1.0 / (binomial(r.m, i) * binomial(r.n, j));
      for (int d = 0; d < r.dim; ++d) r.at(i, j)[d] *= f;
    }
  return r;
}

// sum of scale_k * term_k, every term raised to the largest degree (product with 1).
Bernstein combine(const std::vector<std::pair<double, const Bernstein*>>& terms) {
  int m = 0, n = 0;
  for (const auto& t : terms) m = std::max(m, t.second->m), n = std::max(n, t.second->n);
  Bernstein r(m, n, terms.front().second->dim);
  for (const auto& t : terms) {
    Bernstein one(m - t.second->m, n - t.second->n, 1);
    std::fill(one.c.begin(), one.c.end(), t.first);
    const Bernstein e = product(one, *t.second);
    for (std::size_t k = 0; k < r.c.size(); ++k) r.c[k] += e.c[k];
  }
  return r;
}

// Largest coefficient norm: bounds the polynomial's norm on [0, 1]^2 (the Bernstein basis is a
// partition of unity with non-negative functions).
double max_norm(const Bernstein& a) {
  double best = 0.0;
  for (std::size_t k = 0; k < a.c.size(); k += static_cast<std::size_t>(a.dim)) {
    double s = 0.0;
    for (int d = 0; d < a.dim; ++d) s += a.c[k + d] * a.c[k + d];
    best = std::max(best, s);
  }
  return std::sqrt(best);
}

// Upper bounds on |S_u|, |S_v|, |S_uu|, |S_uv|, |S_vv| over a one-span (Bezier) patch, in its
// own parameters.
struct Derivative_bounds {
  double u = 0.0, v = 0.0, uu = 0.0, uv = 0.0, vv = 0.0;
};

Derivative_bounds derivative_bounds(const Nurbs_surface_3& piece) {
  const int p = piece.degree_u(), q = piece.degree_v();
  const double du = piece.u_max() - piece.u_min(), dv = piece.v_max() - piece.v_min();
  // Coordinates about the net's centroid, so that rounding in the products stays small (the
  // derivatives do not depend on the origin).
  Vec3 centre = Vec3::Zero();
  for (const Point_3& P : piece.poles()) centre += to_vec3(P);
  centre /= static_cast<double>(piece.poles().size());
  Bernstein A(p, q, 3), w(p, q, 1);
  double w_min = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= p; ++i)
    for (int j = 0; j <= q; ++j) {
      const double wij = piece.weight(i, j);
      const Vec3 P = wij * (to_vec3(piece.pole(i, j)) - centre);
      for (int d = 0; d < 3; ++d) A.at(i, j)[d] = P[d];
      w.at(i, j)[0] = wij;
      w_min = std::min(w_min, wij);
    }
  const Bernstein A_u = diff(A, true), A_v = diff(A, false);
  const Bernstein A_uu = diff(A_u, true), A_uv = diff(A_u, false), A_vv = diff(A_v, false);
  Derivative_bounds b;
  if (!piece.is_rational()) {  // S = A (all weights 1): its derivatives' nets
    b.u = max_norm(A_u);
    b.v = max_norm(A_v);
    b.uu = max_norm(A_uu);
    b.uv = max_norm(A_uv);
    b.vv = max_norm(A_vv);
  } else {
    // S = A / w. The polynomials N_x = w^2 S_x and N_xy = w^3 S_xy:
    //   N_u  = w A_u - w_u A
    //   N_uu = w^2 A_uu - 2 w w_u A_u + (2 w_u^2 - w w_uu) A
    //   N_uv = w^2 A_uv - w w_v A_u - w w_u A_v + (2 w_u w_v - w w_uv) A
    // and |S_x| <= max |N_x coefficient| / (min weight)^2, |S_xy| the same over the cube
    // (w >= its smallest coefficient).
    const Bernstein w_u = diff(w, true), w_v = diff(w, false);
    const Bernstein w_uu = diff(w_u, true), w_uv = diff(w_u, false), w_vv = diff(w_v, false);
    const Bernstein f1 = product(w, A_u), f2 = product(w_u, A), f3 = product(w, A_v),
                    f4 = product(w_v, A);
    b.u = max_norm(combine({{1.0, &f1}, {-1.0, &f2}})) / (w_min * w_min);
    b.v = max_norm(combine({{1.0, &f3}, {-1.0, &f4}})) / (w_min * w_min);
    const Bernstein ww = product(w, w), w_wu = product(w, w_u), w_wv = product(w, w_v);
    const Bernstein wu_wu = product(w_u, w_u), wu_wv = product(w_u, w_v), wv_wv = product(w_v, w_v);
    const Bernstein w_wuu = product(w, w_uu), w_wuv = product(w, w_uv), w_wvv = product(w, w_vv);
    const Bernstein cu = combine({{2.0, &wu_wu}, {-1.0, &w_wuu}});
    const Bernstein cuv = combine({{2.0, &wu_wv}, {-1.0, &w_wuv}});
    const Bernstein cv = combine({{2.0, &wv_wv}, {-1.0, &w_wvv}});
    const Bernstein t1 = product(ww, A_uu), t2 = product(w_wu, A_u), t3 = product(cu, A);
    const Bernstein s1 = product(ww, A_uv), s2 = product(w_wv, A_u), s3 = product(w_wu, A_v),
                    s4 = product(cuv, A);
    const Bernstein r1 = product(ww, A_vv), r2 = product(w_wv, A_v), r3 = product(cv, A);
    const double w3 = w_min * w_min * w_min;
    b.uu = max_norm(combine({{1.0, &t1}, {-2.0, &t2}, {1.0, &t3}})) / w3;
    b.uv = max_norm(combine({{1.0, &s1}, {-1.0, &s2}, {-1.0, &s3}, {1.0, &s4}})) / w3;
    b.vv = max_norm(combine({{1.0, &r1}, {-2.0, &r2}, {1.0, &r3}})) / w3;
  }
  // From [0, 1]^2 to the piece's own parameters.
  b.u /= du;
  b.v /= dv;
  b.uu /= du * du;
  b.uv /= du * dv;
  b.vv /= dv * dv;
  return b;
}

// Largest hu given hv: M_uu hu^2 + 2 M_uv hv hu <= 8 D - M_vv hv^2 (its positive root).
double largest_h(double m_uu, double m_uv_h, double rest) {
  if (!(rest > 0.0)) return 0.0;
  const double b = m_uv_h, disc = std::sqrt(b * b + m_uu * rest);
  if (!(b + disc > 0.0)) return std::numeric_limits<double>::infinity();
  return rest / (b + disc);
}

// A grid spacing (hu <= width_u, hv <= width_v) with
// (M_uu hu^2 + 2 M_uv hu hv + M_vv hv^2) / 8 <= D: balanced as sqrt(M_uu) hu = sqrt(M_vv) hv
// where both bounds are non-zero, then widened up to the span in the direction that is not
// limiting.
void spacing(const Derivative_bounds& b, double D, double width_u, double width_v, double& hu,
             double& hv) {
  const double a = std::sqrt(b.uu), c = std::sqrt(b.vv), budget = 8.0 * D;
  const double inf = std::numeric_limits<double>::infinity();
  if (a > 0.0 && c > 0.0) {
    const double t = std::sqrt(budget / (2.0 + 2.0 * b.uv / (a * c)));
    hu = t / a;
    hv = t / c;
  } else if (a == 0.0 && c == 0.0) {
    if (b.uv > 0.0) {
      const double k = std::sqrt(budget / (2.0 * b.uv * width_u * width_v));
      hu = k * width_u;
      hv = k * width_v;
    } else {
      hu = inf;
      hv = inf;
    }
  } else if (a == 0.0) {
    hv = std::sqrt(0.5 * budget) / c;
    hu = largest_h(0.0, b.uv * hv, budget - b.vv * hv * hv);
  } else {
    hu = std::sqrt(0.5 * budget) / a;
    hv = largest_h(0.0, b.uv * hu, budget - b.uu * hu * hu);
  }
  if (hv > width_v) {
    hv = width_v;
    hu = std::min(largest_h(b.uu, b.uv * hv, budget - b.vv * hv * hv), width_u);
  } else if (hu > width_u) {
    hu = width_u;
    hv = std::min(largest_h(b.vv, b.uv * hu, budget - b.uu * hu * hu), width_v);
  }
  hu = std::min(hu, width_u);
  hv = std::min(hv, width_v);
}

// A piece of the face's parameter box with the spacing it needs.
struct Leaf {
  double u0, u1, v0, v1, hu, hv;
  double speed_u, speed_v;  // bounds on |S_u|, |S_v| over the piece
};

struct Clip {
  double u0, u1, v0, v1;
};

// What the plan of one face needs: the face, its parameter box, the deflection, and whether its
// trim cuts into its patch.
struct Face_context {
  const Face& face;
  Clip box;
  double D;
  bool trimmed;
};

// Planned cells of a piece clipped to the face's box, and its spacing; false when it holds no
// grid cell of the face (outside the box, or certified outside the trim).
bool plan_leaf(const Nurbs_surface_3& piece, const Face_context& f, Leaf& leaf, double& cells) {
  leaf.u0 = std::max(piece.u_min(), f.box.u0);
  leaf.u1 = std::min(piece.u_max(), f.box.u1);
  leaf.v0 = std::max(piece.v_min(), f.box.v0);
  leaf.v1 = std::min(piece.v_max(), f.box.v1);
  if (!(leaf.u0 < leaf.u1 && leaf.v0 < leaf.v1)) return false;
  if (f.trimmed && f.face.trim_region.box_outside(leaf.u0, leaf.v0, leaf.u1, leaf.v1)) return false;
  const Derivative_bounds b = derivative_bounds(piece);
  spacing(b, f.D, leaf.u1 - leaf.u0, leaf.v1 - leaf.v0, leaf.hu, leaf.hv);
  // A bound that overflowed (NaN) must not pass for "no constraint": a zero spacing, which the
  // cap refuses.
  if (!(leaf.hu > 0.0)) leaf.hu = 0.0;
  if (!(leaf.hv > 0.0)) leaf.hv = 0.0;
  leaf.speed_u = b.u;
  leaf.speed_v = b.v;
  cells = std::ceil((leaf.u1 - leaf.u0) / leaf.hu) * std::ceil((leaf.v1 - leaf.v0) / leaf.hv);
  return true;
}

// Adds the leaves of `piece` (already planned as `leaf`), halving it while the halves' bounds
// cut its cells.
void refine(const Nurbs_surface_3& piece, const Face_context& f, int depth, const Leaf& leaf,
            double cells, std::vector<Leaf>& leaves) {
  const bool split_u = depth < k_max_split_depth && (leaf.u1 - leaf.u0) / leaf.hu > k_split_cells;
  const bool split_v = depth < k_max_split_depth && (leaf.v1 - leaf.v0) / leaf.hv > k_split_cells;
  if (split_u || split_v) {
    std::vector<Nurbs_surface_3> halves;
    const double tu = 0.5 * (leaf.u0 + leaf.u1), tv = 0.5 * (leaf.v0 + leaf.v1);
    if (split_u && tu > piece.u_min() && tu < piece.u_max()) {
      auto h = split(piece, Parameter_direction::U, tu);
      halves.push_back(std::move(h.first));
      halves.push_back(std::move(h.second));
    } else {
      halves.push_back(piece);
    }
    if (split_v && tv > piece.v_min() && tv < piece.v_max()) {
      std::vector<Nurbs_surface_3> quarters;
      for (const auto& h : halves) {
        auto q = split(h, Parameter_direction::V, tv);
        quarters.push_back(std::move(q.first));
        quarters.push_back(std::move(q.second));
      }
      halves = std::move(quarters);
    }
    if (halves.size() > 1) {
      std::vector<Leaf> sub(halves.size());
      std::vector<double> sub_cells(halves.size(), 0.0);
      std::vector<bool> used(halves.size(), false);
      double total = 0.0;
      for (std::size_t k = 0; k < halves.size(); ++k) {
        used[k] = plan_leaf(halves[k], f, sub[k], sub_cells[k]);
        if (used[k]) total += sub_cells[k];
      }
      if (total <= k_split_gain * cells) {
        for (std::size_t k = 0; k < halves.size(); ++k)
          if (used[k]) refine(halves[k], f, depth + 1, sub[k], sub_cells[k], leaves);
        return;
      }
    }
  }
  leaves.push_back(leaf);
}

// One face's grid: lines at `breaks` with `counts` equal cells between consecutive ones.
struct Face_plan {
  std::vector<double> u_breaks, v_breaks;
  std::vector<double> u_counts, v_counts;
  double cells_u = 0.0, cells_v = 0.0;
  bool trimmed = false;  // the trim cuts into the patch: trim tests while building
};

// Grid lines along one direction: at every leaf's sides, and between them the finest spacing
// of the leaves there, cells at most `surface_spacing` long on the surface (|S_u| hu).
void axis_plan(std::vector<double>& breaks, std::vector<double>& counts, double& total,
               const std::vector<Leaf>& leaves, bool in_u, double surface_spacing) {
  std::sort(breaks.begin(), breaks.end());
  breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());
  const std::size_t n = breaks.size() - 1;
  std::vector<double> h(n, std::numeric_limits<double>::infinity());
  for (const Leaf& l : leaves) {
    const double lo = in_u ? l.u0 : l.v0, hi = in_u ? l.u1 : l.v1;
    const double speed = in_u ? l.speed_u : l.speed_v;
    const double hl =
        std::min(in_u ? l.hu : l.hv,
                 speed > 0.0 ? surface_spacing / speed : std::numeric_limits<double>::infinity());
    const auto a = std::lower_bound(breaks.begin(), breaks.end(), lo) - breaks.begin();
    const auto b = std::lower_bound(breaks.begin(), breaks.end(), hi) - breaks.begin();
    for (auto k = a; k < b; ++k) h[k] = std::min(h[k], hl);
  }
  counts.assign(n, 1.0);
  total = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const double width = breaks[k + 1] - breaks[k];
    // No leaf there: one cell. A zero or NaN spacing (a bound that overflowed) gives an
    // infinite count, which the cap refuses.
    if (h[k] == std::numeric_limits<double>::infinity())
      counts[k] = 1.0;
    else if (h[k] > 0.0)
      counts[k] = std::max(1.0, std::ceil(width / h[k]));
    else
      counts[k] = std::numeric_limits<double>::infinity();
    total += counts[k];
  }
}

// The face's parameter box: its domain, within its trim loops' box. False when empty.
bool face_box(const Face& face, Clip& box) {
  const Nurbs_surface_3& s = face.surface;
  box = {s.u_min(), s.u_max(), s.v_min(), s.v_max()};
  if (face.trim_region.is_trimmed()) {
    box.u0 = std::max(box.u0, face.trim_region.u_min());
    box.u1 = std::min(box.u1, face.trim_region.u_max());
    box.v0 = std::max(box.v0, face.trim_region.v_min());
    box.v1 = std::min(box.v1, face.trim_region.v_max());
  }
  return box.u0 < box.u1 && box.v0 < box.v1;
}

// True when the face's trim cuts into its patch: some trim curve is not on a side of the
// domain (a curve whose control points all lie on one side lies on it). A face trimmed only by
// its domain's sides (a box's rectangle, a patch read with its natural boundary) is untrimmed
// here: no trim test, no trim spacing.
bool trim_cuts_patch(const Face& face) {
  if (!face.trim_region.is_trimmed()) return false;
  const Nurbs_surface_3& s = face.surface;
  const double tol = k_side_relative * std::max(s.u_max() - s.u_min(), s.v_max() - s.v_min());
  for (const Trim_loop& loop : face.trims)
    for (const Trim_curve& c : loop.curves) {
      bool u0 = true, u1 = true, v0 = true, v1 = true;
      for (const Point_3& p : c.uv.poles()) {
        u0 = u0 && std::abs(p.x() - s.u_min()) <= tol;
        u1 = u1 && std::abs(p.x() - s.u_max()) <= tol;
        v0 = v0 && std::abs(p.y() - s.v_min()) <= tol;
        v1 = v1 && std::abs(p.y() - s.v_max()) <= tol;
      }
      if (!(u0 || u1 || v0 || v1)) return true;
    }
  return false;
}

// Diagonal of the box of the face's points on a coarse grid over its parameter box (those
// inside the trim when there are any): its size, for the trim spacing.
double face_size(const Face& face, const Clip& box) {
  constexpr int n = 8;
  Bbox_3 inside, all;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double u = i == n ? box.u1 : box.u0 + (box.u1 - box.u0) * i / n;
      const double v = j == n ? box.v1 : box.v0 + (box.v1 - box.v0) * j / n;
      const Bbox_3 b = face.surface.point(u, v).bbox();
      all += b;
      if (face.contains(u, v)) inside += b;
    }
  const Bbox_3& b = inside.xmin() <= inside.xmax() ? inside : all;
  return box_diagonal(b);
}

void grid_lines(const std::vector<double>& breaks, const std::vector<double>& counts,
                std::vector<double>& out) {
  out.clear();
  for (std::size_t k = 0; k + 1 < breaks.size(); ++k) {
    const int n = static_cast<int>(counts[k]);
    for (int s = 0; s < n; ++s)
      out.push_back(std::min(breaks[k] + (breaks[k + 1] - breaks[k]) * s / n, breaks[k + 1]));
  }
  out.push_back(breaks.back());
}

// A trimmed face's cells are clipped by its trim, marching-squares style. A cell's corners
// a (u0, v0), b (u1, v0), c (u1, v1), d (u0, v1) run counter-clockwise in (u, v); a grid edge
// whose ends lie on either side of the trim gets a crossing point on the trim (bisection). The
// part of the cell inside is the polygon of its inside corners and its crossings, cut into
// triangles whose corners are cell corners (refs 0..3) or crossings on the edges ab, bc, cd,
// da (refs 4..7); all turn counter-clockwise in (u, v). A triangle whose centroid is outside
// the trim (the trim wiggles inside the cell) is dropped by the caller. Returns the count.
// Where only two opposite corners are inside, `centre_inside` tells whether the inside joins
// them across the cell.
int cell_triangles(const bool in[4], bool centre_inside, int (&tri)[4][3]) {
  const int n_in = in[0] + in[1] + in[2] + in[3];
  int n = 0;
  auto add = [&](int x, int y, int z) {
    tri[n][0] = x;
    tri[n][1] = y;
    tri[n][2] = z;
    ++n;
  };
  if (n_in == 4) {
    add(0, 1, 2);
    add(0, 2, 3);
    return n;
  }
  if (n_in == 0) return 0;
  if (n_in == 2 && in[0] == in[2]) {  // opposite corners: a saddle
    const int k = in[0] ? 0 : 1;      // the inside corners k and k + 2
    // Corner k's triangle with the crossings on its two edges: edge k (k to k+1) and edge
    // k-1 (k-1 to k).
    add(k, 4 + k, 4 + (k + 3) % 4);
    add(k + 2, 4 + (k + 2) % 4, 4 + (k + 1) % 4);
    if (centre_inside) {
      add(4 + k, 4 + (k + 1) % 4, 4 + (k + 2) % 4);
      add(4 + k, 4 + (k + 2) % 4, 4 + (k + 3) % 4);
    }
    return n;
  }
  // One run of inside corners: the polygon walks them and the two crossings (convex: a square
  // cut by one chord), cut into a fan.
  int poly[6], m = 0;
  int start = 0;
  while (!(in[start] && !in[(start + 3) % 4])) ++start;  // first inside corner of the run
  for (int k = 0; k < 4; ++k) {
    const int c = (start + k) % 4;
    if (!in[c]) break;
    poly[m++] = c;
    if (!in[(c + 1) % 4]) poly[m++] = 4 + c;  // the crossing leaving the run
  }
  poly[m++] = 4 + (start + 3) % 4;  // the crossing entering the run
  for (int k = 1; k + 1 < m; ++k) add(poly[0], poly[k], poly[k + 1]);
  return n;
}

// The crossing of the trim on the grid edge from an inside node to an outside one.
void crossing(const Face& face, double u_in, double v_in, double u_out, double v_out, double& u,
              double& v) {
  for (int k = 0; k < k_bisection_steps; ++k) {
    const double um = 0.5 * (u_in + u_out), vm = 0.5 * (v_in + v_out);
    if (face.contains(um, vm))
      u_in = um, v_in = vm;
    else
      u_out = um, v_out = vm;
  }
  u = u_in;
  v = v_in;
}

// The (u, v) of a cell's ref (cell_triangles) with corners `cu`, `cv` and inside flags `in`.
void ref_uv(const Face& face, const double (&cu)[4], const double (&cv)[4], const bool in[4],
            int ref, double& u, double& v) {
  if (ref < 4) {
    u = cu[ref];
    v = cv[ref];
    return;
  }
  const int e0 = ref - 4, e1 = (e0 + 1) % 4;
  const int i = in[e0] ? e0 : e1, o = in[e0] ? e1 : e0;
  crossing(face, cu[i], cv[i], cu[o], cv[o], u, v);
}

// Parameter area of a trimmed face's grid clipped by its trim (no vertex made).
double kept_parameter_area(const Face& face, const Face_plan& plan) {
  std::vector<double> us, vs;
  grid_lines(plan.u_breaks, plan.u_counts, us);
  grid_lines(plan.v_breaks, plan.v_counts, vs);
  std::vector<char> prev(vs.size()), cur(vs.size());
  for (std::size_t j = 0; j < vs.size(); ++j) prev[j] = face.contains(us[0], vs[j]);
  double area = 0.0;
  for (std::size_t i = 1; i < us.size(); ++i) {
    for (std::size_t j = 0; j < vs.size(); ++j) cur[j] = face.contains(us[i], vs[j]);
    for (std::size_t j = 1; j < vs.size(); ++j) {
      const bool in[4] = {prev[j - 1] != 0, cur[j - 1] != 0, cur[j] != 0, prev[j] != 0};
      const double cu[4] = {us[i - 1], us[i], us[i], us[i - 1]};
      const double cv[4] = {vs[j - 1], vs[j - 1], vs[j], vs[j]};
      const bool saddle = in[0] == in[2] && in[1] == in[3] && in[0] != in[1];
      const bool centre = saddle && face.contains(0.5 * (cu[0] + cu[1]), 0.5 * (cv[0] + cv[2]));
      int tri[4][3];
      const int n = cell_triangles(in, centre, tri);
      for (int t = 0; t < n; ++t) {
        double u[3], v[3];
        for (int k = 0; k < 3; ++k) ref_uv(face, cu, cv, in, tri[t][k], u[k], v[k]);
        if (!face.contains((u[0] + u[1] + u[2]) / 3.0, (v[0] + v[1] + v[2]) / 3.0)) continue;
        area += 0.5 * ((u[1] - u[0]) * (v[2] - v[0]) - (u[2] - u[0]) * (v[1] - v[0]));
      }
    }
    std::swap(prev, cur);
  }
  return area;
}

// The face's grid over `leaves`: lines at their sides; between them the finest spacing the
// leaves ask for (with `curvature`; without, none), cells at most `surface_spacing` long on the
// surface.
Face_plan grid_plan(const Face_context& f, const std::vector<Leaf>& leaves, double surface_spacing,
                    bool curvature) {
  Face_plan plan;
  plan.trimmed = f.trimmed;
  plan.u_breaks = {f.box.u0, f.box.u1};
  plan.v_breaks = {f.box.v0, f.box.v1};
  std::vector<Leaf> used = leaves;
  for (Leaf& l : used) {
    plan.u_breaks.push_back(l.u0);
    plan.u_breaks.push_back(l.u1);
    plan.v_breaks.push_back(l.v0);
    plan.v_breaks.push_back(l.v1);
    if (!curvature) l.hu = l.hv = std::numeric_limits<double>::infinity();
  }
  axis_plan(plan.u_breaks, plan.u_counts, plan.cells_u, used, true, surface_spacing);
  axis_plan(plan.v_breaks, plan.v_counts, plan.cells_v, used, false, surface_spacing);
  return plan;
}

// The face's grid. Untrimmed: the deflection's. Trimmed, the border is as jagged as the cells
// are long, so the cells are also kept no longer on the surface than the larger of
//  - sqrt(8 D L), the chord of sagitta D on a circle of radius k_trim_radius L, L the face's
//    size: the border shrinks with the deflection as a curved face's grid does;
//  - L / 2^k for the first k at which halving the cells again adds less than
//    1 - k_trim_coverage to the kept area (a thin face, an annulus narrower than the cells,
//    would keep nothing). That k is measured on the knot spans' grid without the deflection's
//    lines, so it does not depend on the deflection and finer deflections give finer grids.
// `max_triangles` stops the halving.
Face_plan plan_face(const Face& face, double D, std::size_t max_triangles) {
  Clip box;
  if (!face_box(face, box)) return Face_plan();
  const Face_context f{face, box, D, trim_cuts_patch(face)};
  std::vector<Leaf> spans, leaves;
  const Bezier_patches pieces = extract_bezier(face.surface);
  for (const Nurbs_surface_3& piece : pieces.patches) {
    Leaf leaf;
    double cells = 0.0;
    if (!plan_leaf(piece, f, leaf, cells)) continue;
    spans.push_back(leaf);
    refine(piece, f, 0, leaf, cells, leaves);
  }
  if (!f.trimmed) return grid_plan(f, leaves, std::numeric_limits<double>::infinity(), true);
  const double size = face_size(face, box);
  double coverage_spacing = size;
  double area = kept_parameter_area(face, grid_plan(f, spans, coverage_spacing, false));
  for (int k = 0; k < k_max_trim_halvings; ++k) {
    const Face_plan finer = grid_plan(f, spans, 0.5 * coverage_spacing, false);
    if (!(2.0 * finer.cells_u * finer.cells_v <= static_cast<double>(max_triangles))) break;
    const double finer_area = kept_parameter_area(face, finer);
    if (finer_area > 0.0 && area >= k_trim_coverage * finer_area) break;
    area = finer_area;
    coverage_spacing *= 0.5;
  }
  const double deflection_spacing = std::sqrt(8.0 * D * k_trim_radius * size);
  return grid_plan(f, leaves, std::min(coverage_spacing, deflection_spacing), true);
}

std::string count_text(double n) {
  std::ostringstream os;
  if (n < 1e15)
    os << static_cast<long long>(n);
  else
    os << n;
  return os.str();
}

[[noreturn]] void too_large(double triangles, std::size_t cap, bool estimated) {
  std::ostringstream os;
  if (estimated)
    os << "the tessellation's grid has at least " << count_text(triangles)
       << " triangles, more than " << k_grid_over_cap << " times the cap of " << cap
       << " triangles";
  else
    os << "the tessellation has more than the cap of " << cap << " triangles";
  throw Tessellation_too_large(os.str(), triangles, estimated);
}

// Builds one face's triangles from its plan into `out`.
class Face_builder {
 public:
  Face_builder(const Face& face, int face_id, const Rigid_pose_3& placement,
               const Tessellation_options& options, Tessellation& out)
      : m_face(face),
        m_s(face.surface),
        m_id(face_id),
        m_R(placement.rotation()),
        m_t(placement.translation()),
        m_cap(options.max_triangles),
        m_out(out) {}

  void build(const Face_plan& plan) {
    grid_lines(plan.u_breaks, plan.u_counts, m_us);
    grid_lines(plan.v_breaks, plan.v_counts, m_vs);
    m_nu = static_cast<int>(m_us.size()) - 1;
    m_nv = static_cast<int>(m_vs.size()) - 1;
    find_welds();
    const bool trimmed = plan.trimmed;
    const std::size_t width = static_cast<std::size_t>(m_nv) + 1;
    m_first.assign(width, -1);
    m_row_a.assign(width, -1);
    m_row_b.assign(width, -1);
    m_in_prev.assign(width, 1);
    m_in_cur.assign(width, 1);
    m_vedge_first.assign(width, -1);
    m_vedge_a.assign(width, -1);
    m_vedge_b.assign(width, -1);
    m_hedge.assign(width, -1);
    // Room for every grid triangle (the trimmed face keeps fewer), within the cap.
    const std::size_t grid = 2 * static_cast<std::size_t>(m_nu) * static_cast<std::size_t>(m_nv);
    reserve(std::min(m_out.mesh.triangles.size() + grid, m_cap + 1));
    if (trimmed)
      for (int j = 0; j <= m_nv; ++j) m_in_prev[j] = m_face.contains(m_us[0], m_vs[j]);
    int* prev = m_first.data();
    int* vedge_prev = m_vedge_first.data();
    const bool flip = m_s.outward_sign() < 0;
    for (int i = 1; i <= m_nu; ++i) {
      const bool last_seam = i == m_nu && m_seam_u;
      int* cur = last_seam ? m_first.data() : (i % 2 ? m_row_a.data() : m_row_b.data());
      if (cur != m_first.data()) std::fill(cur, cur + width, -1);
      int* vedge_cur =
          last_seam ? m_vedge_first.data() : (i % 2 ? m_vedge_a.data() : m_vedge_b.data());
      if (vedge_cur != m_vedge_first.data()) std::fill(vedge_cur, vedge_cur + width, -1);
      std::fill(m_hedge.begin(), m_hedge.end(), -1);
      if (trimmed)
        for (int j = 0; j <= m_nv; ++j) m_in_cur[j] = m_face.contains(m_us[i], m_vs[j]);
      const double ua = m_us[i - 1], ub = m_us[i];
      for (int j = 1; j <= m_nv; ++j) {
        const double va = m_vs[j - 1], vb = m_vs[j];
        // Corners a (i-1, j-1), b (i, j-1), c (i, j), d (i-1, j): counter-clockwise in (u, v),
        // so triangles turn with S_u x S_v.
        const bool in[4] = {m_in_prev[j - 1] != 0, m_in_cur[j - 1] != 0, m_in_cur[j] != 0,
                            m_in_prev[j] != 0};
        if (!trimmed) {
          const int ia = vertex(prev, i - 1, j - 1), ic = vertex(cur, i, j);
          triangle(ia, vertex(cur, i, j - 1), ic, flip);
          triangle(ia, ic, vertex(prev, i - 1, j), flip);
          continue;
        }
        const double cu[4] = {ua, ub, ub, ua}, cv[4] = {va, va, vb, vb};
        const bool saddle = in[0] == in[2] && in[1] == in[3] && in[0] != in[1];
        const bool centre = saddle && m_face.contains(0.5 * (ua + ub), 0.5 * (va + vb));
        int tri[4][3];
        const int n = cell_triangles(in, centre, tri);
        for (int t = 0; t < n; ++t) {
          double u[3], v[3];
          for (int k = 0; k < 3; ++k) ref_uv(m_face, cu, cv, in, tri[t][k], u[k], v[k]);
          if (!m_face.contains((u[0] + u[1] + u[2]) / 3.0, (v[0] + v[1] + v[2]) / 3.0)) continue;
          int idx[3];
          for (int k = 0; k < 3; ++k) {
            const int ref = tri[t][k];
            idx[k] = ref == 0   ? vertex(prev, i - 1, j - 1)
                     : ref == 1 ? vertex(cur, i, j - 1)
                     : ref == 2 ? vertex(cur, i, j)
                     : ref == 3 ? vertex(prev, i - 1, j)
                                : edge_vertex(ref - 4, i, j, prev, cur, vedge_prev, vedge_cur,
                                              u[k], v[k]);
          }
          triangle(idx[0], idx[1], idx[2], flip);
        }
      }
      prev = cur;
      vedge_prev = vedge_cur;
      std::swap(m_in_prev, m_in_cur);
    }
  }

 private:
  Vec3 point(double u, double v) {
    m_s.evaluate_placed(u, v, m_R, m_t, m_sp, 0);
    return m_sp.p;
  }

  // The vertex where the trim crosses edge e (0 ab, 1 bc, 2 cd, 3 da) of cell (i, j) at
  // (u, v), shared with the cell across the edge; on a collapsed side, its pole.
  int edge_vertex(int e, int i, int j, int* prev, int* cur, int* vedge_prev, int* vedge_cur,
                  double u, double v) {
    int* slot;
    switch (e) {
      case 0:  // ab: v = v_{j-1}, shared with the cell below
        if (j - 1 == 0 && m_pole_v0) return vertex(prev, i - 1, j - 1);
        slot = &m_hedge[j - 1];
        break;
      case 1:  // bc: u = u_i, shared with the next row's cell
        if (i == m_nu && m_pole_u1) return vertex(cur, i, j);
        slot = &vedge_cur[j];
        break;
      case 2:  // cd: v = v_j, shared with the cell above (across the seam for the last)
        if (j == m_nv && m_pole_v1) return vertex(cur, i, j);
        slot = &m_hedge[(j == m_nv && m_seam_v) ? 0 : j];
        break;
      default:  // da: u = u_{i-1}, shared with the previous row's cell
        if (i - 1 == 0 && m_pole_u0) return vertex(prev, i - 1, j);
        slot = &vedge_prev[j];
        break;
    }
    if (*slot < 0) *slot = new_vertex(u, v);
    return *slot;
  }

  int new_vertex(double u, double v) {
    const Vec3 p = point(u, v);
    const int k = static_cast<int>(m_out.mesh.vertices.size());
    m_out.mesh.vertices.emplace_back(p.x(), p.y(), p.z());
    m_out.vertex_face.push_back(m_id);
    m_out.vertex_uv.push_back({u, v});
    return k;
  }

  // Seams (first and last grid line the same points) and collapsed sides (one point).
  void find_welds() {
    const Bbox_3 box = m_s.hull_bbox();
    double size = 0.0;
    for (int k = 0; k < 3; ++k)
      size = std::max({size, box.max(k) - box.min(k), std::abs(box.max(k)), std::abs(box.min(k))});
    // (The points compared are placed: their rounding grows with the placement's offset too.)
    const double tol = k_weld_relative * (size + m_t.norm());
    auto same = [&](double u0, double v0, double u1, double v1) {
      return (point(u0, v0) - point(u1, v1)).norm() <= tol;
    };
    m_seam_u = m_nu > 1;
    for (int j = 0; j <= m_nv && m_seam_u; ++j)
      m_seam_u = same(m_us[0], m_vs[j], m_us[m_nu], m_vs[j]);
    m_seam_v = m_nv > 1;
    for (int i = 0; i <= m_nu && m_seam_v; ++i)
      m_seam_v = same(m_us[i], m_vs[0], m_us[i], m_vs[m_nv]);
    m_pole_u0 = m_pole_u1 = m_pole_v0 = m_pole_v1 = true;
    for (int j = 1; j <= m_nv; ++j) {
      m_pole_u0 = m_pole_u0 && same(m_us[0], m_vs[0], m_us[0], m_vs[j]);
      m_pole_u1 = m_pole_u1 && same(m_us[m_nu], m_vs[0], m_us[m_nu], m_vs[j]);
    }
    for (int i = 1; i <= m_nu; ++i) {
      m_pole_v0 = m_pole_v0 && same(m_us[0], m_vs[0], m_us[i], m_vs[0]);
      m_pole_v1 = m_pole_v1 && same(m_us[0], m_vs[m_nv], m_us[i], m_vs[m_nv]);
    }
    m_pole_index[0] = m_pole_index[1] = m_pole_index[2] = m_pole_index[3] = -1;
  }

  // The vertex of grid node (i, j), whose row's indices are `row`; made on first use.
  int vertex(int* row, int i, int j) {
    int* slot;
    if (i == 0 && m_pole_u0)
      slot = &m_pole_index[0];
    else if (i == m_nu && m_pole_u1)
      slot = &m_pole_index[1];
    else if (j == 0 && m_pole_v0)
      slot = &m_pole_index[2];
    else if (j == m_nv && m_pole_v1)
      slot = &m_pole_index[3];
    else
      slot = &row[(j == m_nv && m_seam_v) ? 0 : j];
    if (*slot < 0) *slot = new_vertex(m_us[i], m_vs[(j == m_nv && m_seam_v && !m_pole_v1) ? 0 : j]);
    return *slot;
  }

  void triangle(int a, int b, int c, bool flip) {
    if (a == b || b == c || a == c) return;  // collapsed onto a pole
    if (m_out.mesh.triangles.size() >= m_cap)
      too_large(static_cast<double>(m_out.mesh.triangles.size()) + 1.0, m_cap, false);
    if (flip) std::swap(b, c);
    m_out.mesh.triangles.push_back({a, b, c});
    m_out.triangle_face.push_back(m_id);
  }

  void reserve(std::size_t triangles) {
    auto& t = m_out.mesh.triangles;
    if (triangles <= t.capacity()) return;
    const std::size_t n = std::max(triangles, t.capacity() + t.capacity() / 2);
    t.reserve(n);
    m_out.triangle_face.reserve(n);
    // A grid of T triangles has about T / 2 vertices.
    const std::size_t nv = m_out.mesh.vertices.size() + (n - t.size()) / 2 + 2 * (m_nu + m_nv) + 4;
    if (nv > m_out.mesh.vertices.capacity()) {
      m_out.mesh.vertices.reserve(nv);
      m_out.vertex_face.reserve(nv);
      m_out.vertex_uv.reserve(nv);
    }
  }

  const Face& m_face;
  const Nurbs_surface_3& m_s;
  int m_id;
  Mat3 m_R;
  Vec3 m_t;
  std::size_t m_cap;
  Tessellation& m_out;
  Surface_point m_sp{Surface_point::Unset{}};
  std::vector<double> m_us, m_vs;
  std::vector<int> m_first, m_row_a, m_row_b;
  // Crossing vertices on the grid edges along v at u_0, u_{i-1} and u_i (index j: the edge
  // from v_{j-1} to v_j), and along u at each v_j in the current row of cells.
  std::vector<int> m_vedge_first, m_vedge_a, m_vedge_b, m_hedge;
  std::vector<char> m_in_prev, m_in_cur;
  int m_nu = 0, m_nv = 0;
  bool m_seam_u = false, m_seam_v = false;
  bool m_pole_u0 = false, m_pole_u1 = false, m_pole_v0 = false, m_pole_v1 = false;
  int m_pole_index[4] = {-1, -1, -1, -1};
};

}  // namespace

void tessellate(const Body& body, const Rigid_pose_3& placement, int body_index,
                const Tessellation_options& options, Tessellation& out) {
  EXTREMAL_PRECONDITION_MSG(std::isfinite(options.deflection) && options.deflection > 0.0,
                            "deflection " << options.deflection << " must be finite and > 0");
  EXTREMAL_PRECONDITION_MSG(
      options.max_triangles <= k_max_triangles_cap,
      "max_triangles " << options.max_triangles << " exceeds " << k_max_triangles_cap);
  // Plan every face first: a deflection far too fine for the cap stops here, before any
  // vertex is made.
  std::vector<Face_plan> plans;
  plans.reserve(body.faces.size());
  double grid_triangles =
      static_cast<double>(out.mesh.triangles.size() + body.mesh.triangles.size());
  for (const Face& face : body.faces) {
    plans.push_back(plan_face(face, options.deflection, options.max_triangles));
    grid_triangles += 2.0 * plans.back().cells_u * plans.back().cells_v;
    if (!(grid_triangles <= k_grid_over_cap * static_cast<double>(options.max_triangles)))
      too_large(grid_triangles, options.max_triangles, true);
  }
  for (std::size_t f = 0; f < body.faces.size(); ++f) {
    const int id = static_cast<int>(out.face_body.size());
    out.face_body.push_back(body_index);
    out.face_index.push_back(static_cast<int>(f));
    ++out.faces;
    if (plans[f].u_counts.empty()) continue;
    out.grid_cells += plans[f].cells_u * plans[f].cells_v;
    Face_builder(body.faces[f], id, placement, options, out).build(plans[f]);
  }
  // A mesh body's own triangles, placed.
  if (!body.mesh.empty()) {
    if (out.mesh.triangles.size() + body.mesh.triangles.size() > options.max_triangles)
      too_large(static_cast<double>(out.mesh.triangles.size() + body.mesh.triangles.size()),
                options.max_triangles, false);
    const int base = static_cast<int>(out.mesh.vertices.size());
    for (const Point_3& p : body.mesh.vertices) {
      out.mesh.vertices.push_back(placement(p));
      out.vertex_face.push_back(-1);
      out.vertex_uv.push_back({0.0, 0.0});
    }
    for (const auto& t : body.mesh.triangles) {
      out.mesh.triangles.push_back({base + t[0], base + t[1], base + t[2]});
      out.triangle_face.push_back(-1);
    }
  }
}

}  // namespace extremal
