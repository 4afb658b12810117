#include "Stress_ladder.h"

#include <algorithm>
#include <boost/multiprecision/cpp_bin_float.hpp>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <functional>
#include <map>
#include <sstream>
#include <stdexcept>

#include "algorithms/body_pair/Body_pair_tracker.h"
#include "kernel/Shapes.h"

namespace extremal::experiments {

namespace {

using Quad = boost::multiprecision::cpp_bin_float_quad;  // 113-bit significand

constexpr double k_pi = 3.14159265358979323846;
constexpr double k_eps = std::numeric_limits<double>::epsilon();
constexpr double k_dt = 1e-3;  // tracked rows at 1 kHz

// How far an answer may lie from the exact shapes' reference for reasons of the input alone
// (rung_slack): the NURBS control points and weights of the analytic shapes are rounded
// (sqrt(1/2) weights, blossoms divided by 3) and a rotation matrix is orthonormal only to
// rounding, which moves the shapes by a few epsilons of their size; and the solver places
// control points in the world in doubles, each coordinate off by up to half an ulp of its
// magnitude. Set by the ladder's own excesses (bench/RESULTS.md, "Stress ladder"): lower bounds
// above the reference by up to 0.6 epsilon x the largest coordinate (offset sweep) and none
// above it by more than 2 epsilons x the size elsewhere.
constexpr double k_shape_ulps = 16.0;       // x epsilon x the scene's size
constexpr double k_coordinate_ulps = 2.0;   // x epsilon x the largest world coordinate

// ---- quadruple-precision vectors and poses ---------------------------------------------------

struct Qv {
  Quad x, y, z;
};
Qv qv(const Vec3& v) { return {Quad(v.x()), Quad(v.y()), Quad(v.z())}; }
Qv operator+(const Qv& a, const Qv& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Qv operator-(const Qv& a, const Qv& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Qv operator*(const Quad& s, const Qv& a) { return {s * a.x, s * a.y, s * a.z}; }
Quad dot(const Qv& a, const Qv& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Qv cross(const Qv& a, const Qv& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
Quad norm(const Qv& a) { return sqrt(dot(a, a)); }
Qv normalized(const Qv& a) { return (Quad(1) / norm(a)) * a; }

// A pose's rotation and translation as given (doubles, exact in Quad): the reference is the
// distance between the body-frame shapes mapped by exactly this affine map.
struct Qpose {
  Quad R[3][3];
  Qv t;
  explicit Qpose(const Rigid_pose_3& X) : t(qv(X.translation())) {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) R[i][j] = Quad(X.rotation()(i, j));
  }
  Qv rotate(const Qv& p) const {
    return {R[0][0] * p.x + R[0][1] * p.y + R[0][2] * p.z,
            R[1][0] * p.x + R[1][1] * p.y + R[1][2] * p.z,
            R[2][0] * p.x + R[2][1] * p.y + R[2][2] * p.z};
  }
  Qv apply(const Qv& p) const { return rotate(p) + t; }
};

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("stress ladder reference: " + what);
}

void require_identity(const Rigid_pose_3& X, const char* body) {
  require(X.rotation() == Mat3::Identity() && X.translation() == Vec3::Zero(),
          std::string(body) + " must stay at the identity pose");
}

// Largest value of f over [lo, hi] (f unimodal near its largest sample): `samples` samples,
// then golden-section search on the two intervals beside the best, to a bracket far below the
// square root of Quad's epsilon, so the value is exact to Quad's rounding.
template <class F>
Quad maximise(const F& f, const Quad& lo, const Quad& hi, int samples) {
  Quad best_x = lo, best = f(lo);
  for (int k = 1; k <= samples; ++k) {
    const Quad x = lo + (hi - lo) * k / samples;
    const Quad v = f(x);
    if (v > best) best = v, best_x = x;
  }
  const Quad h = (hi - lo) / samples;
  Quad a = best_x - h, b = best_x + h;
  const Quad g = (sqrt(Quad(5)) - 1) / 2;
  Quad c = b - g * (b - a), d = a + g * (b - a), fc = f(c), fd = f(d);
  for (int it = 0; it < 170; ++it) {
    if (fc > fd) {
      b = d, d = c, fd = fc;
      c = b - g * (b - a), fc = f(c);
    } else {
      a = c, c = d, fc = fd;
      d = a + g * (b - a), fd = f(d);
    }
  }
  return std::max({best, fc, fd});
}

const Quad& quad_pi() {
  static const Quad pi = 4 * atan(Quad(1));
  return pi;
}

// ---- motions ---------------------------------------------------------------------------------

struct Placement {
  Rigid_pose_3 pose;
  Twist_3 twist;
};

// A turn at rate omega about the line through `point` along `axis` while that line moves at
// `velocity`: the motion of a rung about its pose that keeps its degeneracy.
struct Screw_motion {
  Rigid_pose_3 start;
  Vec3 axis = Vec3::UnitZ();
  Vec3 point = Vec3::Zero();
  double omega = 0.0;
  Vec3 velocity = Vec3::Zero();

  Placement at(double t) const {
    if (t == 0.0) {
      Twist_3 w;
      w.angular = omega * axis;
      w.linear = velocity + w.angular.cross(start.translation() - point);
      return {start, w};
    }
    const Mat3 turn = Eigen::AngleAxisd(omega * t, axis).toRotationMatrix();
    const Vec3 q = point + velocity * t;
    const Vec3 origin = q + turn * (start.translation() - point);
    Twist_3 w;
    w.angular = omega * axis;
    w.linear = velocity + w.angular.cross(origin - q);
    return {Rigid_pose_3(turn * start.rotation(), origin), w};
  }
};

Screw_motion still(const Rigid_pose_3& X = Rigid_pose_3()) { return {X}; }

struct Rung_scene {
  Body a, b;
  Screw_motion ma, mb;
  std::function<Quad(const Rigid_pose_3&, const Rigid_pose_3&)> reference;
  double size = 1.0;  // the largest body extent
};

Mat3 rotation(const Vec3& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

// ---- shapes without a builder in the kernel --------------------------------------------------

Body body_of(Nurbs_surface_3 s, const std::string& kind, const std::string& name) {
  Body b;
  b.name = name;
  b.faces.emplace_back(std::move(s), kind);
  return b;
}

// The side of a cone with its apex at the origin and its base circle (radius, height) open:
// the rational circle times a line, the apex a collapsed edge at v = 0. Outward (the solid) is
// away from the axis, so a point in the cone's cavity is apart from it.
Nurbs_surface_3 cone_side(double radius, double height) {
  const Nurbs_curve_3 circle = make_circle(1.0);
  std::vector<Point_3> poles;
  std::vector<double> weights;
  for (int i = 0; i < circle.number_of_poles(); ++i) {
    const Vec3 q = to_vec3(circle.poles()[i]);
    poles.emplace_back(0.0, 0.0, 0.0);
    poles.emplace_back(radius * q.x(), radius * q.y(), height);
    weights.push_back(circle.weights()[i]);
    weights.push_back(circle.weights()[i]);
  }
  Nurbs_surface_3 s(2, 1, circle.number_of_poles(), 2, std::move(poles), circle.knots(),
                    {0, 0, 1, 1}, std::move(weights));
  // f_u x f_v points away from the axis and down: the cavity side is -f_u x f_v.
  s.set_outward_sign(-1);
  return s;
}

// z = k ((x - x0)^2 + (y - y0)^2) over [-1, 1]^2 as a bicubic B-spline with a knot at 1/2:
// x = -1 + 2u at the Greville abscissae, z from the blossom of each quadratic.
Nurbs_surface_3 paraboloid_bicubic(double k, double x0, double y0) {
  const std::vector<double> t = {0, 0, 0, 0, 0.5, 1, 1, 1, 1};
  auto greville = [&](int i) { return -1.0 + 2.0 * (t[i + 1] + t[i + 2] + t[i + 3]) / 3.0; };
  // Ordinate i of (2u + e)^2, e = -1 - c: blossom of 4u^2 + 4e u + e^2.
  auto ordinate = [&](int i, double c) {
    const double a = t[i + 1], b = t[i + 2], d = t[i + 3], e = -1.0 - c;
    return 4.0 * (a * b + a * d + b * d) / 3.0 + 4.0 * e * (a + b + d) / 3.0 + e * e;
  };
  std::vector<Point_3> poles;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      poles.emplace_back(greville(i), greville(j), k * (ordinate(i, x0) + ordinate(j, y0)));
  Nurbs_surface_3 s(3, 3, 5, 5, std::move(poles), t, t);
  s.set_outward_sign(k < 0 ? +1 : -1);  // a cap's solid is below it, a bowl's above
  return s;
}

// Two bumps on a flat bicubic B-spline over [-2, 2] x [-1, 1] (uneven knots, so the tops lie
// inside knot spans): heights c1 and c2 on poles (3, 3) and (7, 3), whose basis functions'
// supports in u meet only at u = 0.5.
const std::vector<double> k_bump_knots_u = {0,    0,    0,    0,    0.11, 0.26, 0.37, 0.5,
                                            0.63, 0.77, 0.88, 1,    1,    1,    1};
const std::vector<double> k_bump_knots_v = {0, 0, 0, 0, 0.23, 0.52, 0.76, 1, 1, 1, 1};

Nurbs_surface_3 two_bumps(double c1, double c2) {
  const std::vector<double>& tu = k_bump_knots_u;
  const std::vector<double>& tv = k_bump_knots_v;
  const int nu = static_cast<int>(tu.size()) - 4, nv = static_cast<int>(tv.size()) - 4;
  std::vector<Point_3> poles;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double x = -2.0 + 4.0 * (tu[i + 1] + tu[i + 2] + tu[i + 3]) / 3.0;
      const double y = -1.0 + 2.0 * (tv[j + 1] + tv[j + 2] + tv[j + 3]) / 3.0;
      const double z = (j == 3 && i == 3) ? c1 : (j == 3 && i == 7) ? c2 : 0.0;
      poles.emplace_back(x, y, z);
    }
  Nurbs_surface_3 s(3, 3, nu, nv, std::move(poles), tu, tv);
  s.set_outward_sign(+1);
  return s;
}

// The cubic B-spline basis function on knots t[0..4] at x (Cox-de Boor), in Quad.
Quad basis(const Quad* t, int p, const Quad& x) {
  if (p == 0) return (t[0] <= x && x < t[1]) ? Quad(1) : Quad(0);
  Quad v = 0;
  if (t[p] > t[0]) v += (x - t[0]) / (t[p] - t[0]) * basis(t, p - 1, x);
  if (t[p + 1] > t[1]) v += (t[p + 1] - x) / (t[p + 1] - t[1]) * basis(t + 1, p - 1, x);
  return v;
}
// Largest value of the cubic basis function i of knot vector `knots`.
Quad basis_max(const std::vector<double>& knots, int i) {
  Quad t[5];
  for (int k = 0; k < 5; ++k) t[k] = Quad(knots[i + k]);
  return maximise([&](const Quad& x) { return basis(t, 3, x); }, t[0], t[4], 400);
}

// A sphere octant (x, y, z >= 0) as one rational biquadratic Bezier patch, its weights spread
// over [1/spread, spread] by the Moebius reparametrisation w_ij -> w_ij a^i b^j (a = sqrt(spread),
// b = 1 / a), which keeps the point set.
Nurbs_surface_3 octant(double r, double spread) {
  const double s = std::sqrt(0.5);
  const double lx[3] = {1, 1, 0}, ly[3] = {0, 1, 1}, lw[3] = {1, s, 1};
  const double mr[3] = {1, 1, 0}, mz[3] = {0, 1, 1}, mw[3] = {1, s, 1};
  const double a = std::sqrt(spread), b = 1.0 / a;
  std::vector<Point_3> poles;
  std::vector<double> weights;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      poles.emplace_back(r * lx[i] * mr[j], r * ly[i] * mr[j], r * mz[j]);
      weights.push_back(lw[i] * mw[j] * std::pow(a, i) * std::pow(b, j));
    }
  Nurbs_surface_3 patch = make_freeform(2, 2, 3, 3, std::move(poles), std::move(weights));
  Surface_point sp;
  patch.evaluate(0.5, 0.5, sp, 1);
  patch.set_outward_sign(sp.du.cross(sp.dv).dot(sp.p) >= 0.0 ? 1 : -1);
  return patch;
}

// The unit square z = 0 (u along x, v along y) trimmed to its part on the side n . q >= c of a
// line, as a B-rep face: the loop's pieces are straight uv curves, each an edge whose 3D curve
// is the same segment. `corners` receives the loop (counterclockwise).
Body trimmed_square(const Vec3& n, double c, std::vector<Vec3>& corners) {
  const std::vector<Vec3> square = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  corners.clear();
  for (int k = 0; k < 4; ++k) {  // one Sutherland-Hodgman pass
    const Vec3& p = square[k];
    const Vec3& q = square[(k + 1) % 4];
    const double fp = n.dot(p) - c, fq = n.dot(q) - c;
    if (fp >= 0) corners.push_back(p);
    if ((fp >= 0) != (fq >= 0)) corners.push_back(p + (fp / (fp - fq)) * (q - p));
  }
  std::vector<Point_3> poles = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0}};
  Body b = body_of(Nurbs_surface_3(1, 1, 2, 2, std::move(poles), {0, 0, 1, 1}, {0, 0, 1, 1}),
                   "plane", "trimmed square");
  Trim_loop loop;
  for (std::size_t k = 0; k < corners.size(); ++k) {
    const Point_3 p = to_point(corners[k]), q = to_point(corners[(k + 1) % corners.size()]);
    const Nurbs_curve_3 segment(1, {p, q}, {0, 0, 1, 1});
    loop.curves.push_back({segment, static_cast<int>(k), false});
    Edge e;
    e.curve = segment;
    e.t_min = 0.0;
    e.t_max = 1.0;
    e.uses.push_back({0, 0, static_cast<int>(k)});
    b.edges.push_back(std::move(e));
  }
  b.faces[0].trims.push_back(std::move(loop));
  b.faces[0].update_trim_region(1e-9);  // the band the command line reads files with
  return b;
}

// ---- references ------------------------------------------------------------------------------

// Signed distance between two ellipsoids, each the image of the unit sphere under its pose's
// rotation times diag(axes) plus its translation: the largest separation of their support
// slabs, max over unit m of m.(t_B - t_A) - |M_A^T m| - |M_B^T m| (exact for convex bodies; any
// m gives a lower bound), by Newton's method on the sphere from `start`.
Quad ellipsoid_gap(const Rigid_pose_3& X_WA, const Vec3& axes_a, const Rigid_pose_3& X_WB,
                   const Vec3& axes_b, const Vec3& start) {
  Quad PA[3][3], PB[3][3];
  auto shape = [](const Rigid_pose_3& X, const Vec3& axes, Quad P[3][3]) {
    Quad M[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) M[i][j] = Quad(X.rotation()(i, j)) * Quad(axes[j]);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) P[i][j] = M[i][0] * M[j][0] + M[i][1] * M[j][1] + M[i][2] * M[j][2];
  };
  shape(X_WA, axes_a, PA);
  shape(X_WB, axes_b, PB);
  auto mul = [](const Quad P[3][3], const Qv& m) {
    return Qv{P[0][0] * m.x + P[0][1] * m.y + P[0][2] * m.z,
              P[1][0] * m.x + P[1][1] * m.y + P[1][2] * m.z,
              P[2][0] * m.x + P[2][1] * m.y + P[2][2] * m.z};
  };
  const Qv delta = qv(X_WB.translation()) - qv(X_WA.translation());
  auto G = [&](const Qv& m) {
    return dot(m, delta) - sqrt(dot(m, mul(PA, m))) - sqrt(dot(m, mul(PB, m)));
  };
  Qv m = normalized(qv(start));
  for (int it = 0; it < 60; ++it) {
    const Qv pa = mul(PA, m), pb = mul(PB, m);
    const Quad ha = sqrt(dot(m, pa)), hb = sqrt(dot(m, pb));
    const Qv g = delta - (Quad(1) / ha) * pa - (Quad(1) / hb) * pb;
    // A basis of the tangent plane at m.
    const Qv e = abs(m.x) < Quad(0.6) ? Qv{1, 0, 0} : Qv{0, 1, 0};
    const Qv u1 = normalized(cross(m, e)), u2 = cross(m, u1);
    const Qv u[2] = {u1, u2};
    // Hessian of G: -(P/h - (P m)(P m)^T / h^3) per body; on the sphere less (m.g) I.
    auto hess = [&](const Qv& x, const Qv& y) {
      const Quad a = dot(x, mul(PA, y)) / ha - dot(x, pa) * dot(y, pa) / (ha * ha * ha);
      const Quad b = dot(x, mul(PB, y)) / hb - dot(x, pb) * dot(y, pb) / (hb * hb * hb);
      return -(a + b);
    };
    const Quad mg = dot(m, g);
    const Quad H00 = hess(u[0], u[0]) - mg, H01 = hess(u[0], u[1]), H11 = hess(u[1], u[1]) - mg;
    const Quad g0 = dot(u[0], g), g1 = dot(u[1], g);
    const Quad det = H00 * H11 - H01 * H01;
    const Quad x0 = -(H11 * g0 - H01 * g1) / det, x1 = -(H00 * g1 - H01 * g0) / det;
    m = normalized(m + x0 * u[0] + x1 * u[1]);
    if (abs(x0) + abs(x1) < Quad(1e-32)) break;
  }
  // Overlapping convex bodies: the same maximum is minus their depth (the signed distance).
  return G(m);
}

// Gap between a bore (a hole: cylinder side radius R, height H, at the identity) and a shaft (radius r,
// length L) inside it: R minus the largest distance from the bore's axis of a shaft point,
// which lies on one of the shaft's two rim circles (the distance from the axis is convex).
Quad shaft_gap(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB, double R, double H, double r,
               double L) {
  require_identity(X_WA, "the bore");
  const Qpose P(X_WB);
  const Qv e1 = P.rotate({1, 0, 0}), e2 = P.rotate({0, 1, 0});
  Quad widest = 0;
  for (double z : {0.0, L}) {
    const Qv m = P.apply({0, 0, Quad(z)});
    require(m.z > Quad(r) && m.z < Quad(H - r), "the shaft's rims must stay inside the bore");
    auto rho2 = [&](const Quad& phi) {
      const Quad c = cos(phi), s = sin(phi);
      const Quad x = m.x + Quad(r) * (c * e1.x + s * e2.x);
      const Quad y = m.y + Quad(r) * (c * e1.y + s * e2.y);
      return x * x + y * y;
    };
    widest = std::max(widest, maximise(rho2, Quad(0), 2 * quad_pi(), 720));
  }
  const Quad gap = Quad(R) - sqrt(widest);
  require(gap > 0, "the shaft must not touch the bore");
  return gap;
}

// Gap between two cylinders (radius r, length L, each along its body z from 0 to L) whose axes
// are skew or parallel, with the common perpendicular's feet inside both: the axes' distance
// less both radii.
Quad skew_cylinders_gap(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB, double r, double L) {
  const Qpose A(X_WA), B(X_WB);
  const Qv ca = A.apply({0, 0, Quad(L / 2)}), cb = B.apply({0, 0, Quad(L / 2)});
  const Qv a = A.rotate({0, 0, 1}), b = B.rotate({0, 0, 1});
  const Qv w = cb - ca;
  const Quad aa = dot(a, a), ab = dot(a, b), bb = dot(b, b), aw = dot(a, w), bw = dot(b, w);
  const Quad det = ab * ab - aa * bb;
  Quad d;
  if (abs(det) > Quad(1e-60)) {
    // Feet ca + s a and cb + t b: d/ds and d/dt of |w + t b - s a|^2 vanish.
    const Quad s = (-bb * aw + ab * bw) / det, t = (aa * bw - ab * aw) / det;
    require(abs(s) < Quad(L / 2 - r) && abs(t) < Quad(L / 2 - r),
            "the common perpendicular must meet both cylinders' sides");
    d = norm(w + t * b - s * a);
  } else {
    d = norm(w - (aw / aa) * a);
  }
  const Quad gap = d - 2 * Quad(r);
  require(gap > 0, "the cylinders must be apart");
  return gap;
}

// ---- the sweeps ------------------------------------------------------------------------------

// 10^from, 10^(from +- step), ... to 10^to (correctly rounded), then 0 if asked.
std::vector<double> decades(int from, int to, bool with_zero, int step = 1) {
  std::vector<double> v;
  for (int k = from; from <= to ? k <= to : k >= to; k += from <= to ? step : -step)
    v.push_back(std::stod("1e" + std::to_string(k)));
  if (with_zero) v.push_back(0.0);
  return v;
}

Rung_scene make_scene(const std::string& key, double x) {
  Rung_scene s;
  if (key == "angle_shaft_in_bore") {
    // A shaft (r 1, length 4) centred in a bore (a hole r 2, height 8: the side alone, its
    // outward normal into the hole), tilted by x about a horizontal axis: the gap
    // 2 - cos x - 2 sin x is reached at a rim point, and over the whole side at x = 0. It turns
    // about the bore's axis and slides along it.
    Nurbs_surface_3 hole = make_cylinder_side(2.0, 8.0);
    hole.set_outward_sign(-hole.outward_sign());
    s.a = body_of(std::move(hole), "cylinder", "bore");
    s.b = make_cylinder_body(1.0, 4.0, "shaft");
    const Mat3 R0 = rotation(Vec3(std::cos(0.3), std::sin(0.3), 0.0), x);
    const Rigid_pose_3 X0(R0, Vec3(0, 0, 4) - R0 * Vec3(0, 0, 2));
    s.ma = still();
    s.mb = {X0, Vec3::UnitZ(), Vec3::Zero(), 1.0, Vec3(0, 0, 0.5)};
    s.reference = [](const Rigid_pose_3& A, const Rigid_pose_3& B) {
      return shaft_gap(A, B, 2.0, 8.0, 1.0, 4.0);
    };
    s.size = 8.0;
  } else if (key == "angle_cylinders_side_by_side") {
    // Two cylinders (r 1, length 4) side by side, B's axis turned by x about the line joining
    // their centres: the gap 0.5 at the centres, along a whole line at x = 0. Each turns about
    // its own axis; B slides along its axis.
    s.a = make_cylinder_body(1.0, 4.0, "cylinder A");
    s.b = make_cylinder_body(1.0, 4.0, "cylinder B");
    const Mat3 R0 = rotation(Vec3::UnitX(), x);
    const Vec3 centre(2.5, 0, 0), axis = R0 * Vec3::UnitZ();
    s.ma = {Rigid_pose_3(Mat3::Identity(), Vec3(0, 0, -2)), Vec3::UnitZ(), Vec3::Zero(), 0.7};
    s.mb = {Rigid_pose_3(R0, centre - 2.0 * axis), axis, centre, 1.3, 0.4 * axis};
    s.reference = [](const Rigid_pose_3& A, const Rigid_pose_3& B) {
      return skew_cylinders_gap(A, B, 1.0, 4.0);
    };
    s.size = 4.0;
  } else if (key == "angle_plane_over_plane") {
    // A 1 x 1 plane facing a 2 x 2 one 0.3 above it, tilted by x: the nearest point is its
    // lowest corner, the whole plane at x = 0. It turns about the vertical and slides.
    s.a = make_plane_body(2.0, 2.0, "plane A");
    s.b = make_plane_body(1.0, 1.0, "plane B");
    const Mat3 R0 = rotation(Vec3(1.0, 0.3, 0.0), x) * rotation(Vec3::UnitX(), k_pi);
    const Vec3 c(0.1, -0.05, 0.3);
    s.ma = still();
    s.mb = {Rigid_pose_3(R0, c), Vec3::UnitZ(), c, 0.8, Vec3(0.2, 0, 0)};
    s.reference = [](const Rigid_pose_3& A, const Rigid_pose_3& B) {
      require_identity(A, "plane A");
      const Qpose P(B);
      Quad low = 1e9;
      for (double u : {-0.5, 0.5})
        for (double v : {-0.5, 0.5}) {
          const Qv q = P.apply({Quad(u), Quad(v), 0});
          require(abs(q.x) < 1 && abs(q.y) < 1, "plane B must stay over plane A");
          low = std::min(low, q.z);
        }
      require(low > 0, "plane B must stay above plane A");
      return low;
    };
    s.size = 2.0;
  } else if (key == "gap_sphere_plane") {
    // A unit sphere x above a 4 x 4 plane, turned so that the nearest point is no pole; it
    // slides parallel to the plane and spins about its centre.
    s.a = make_plane_body(4.0, 4.0, "plane");
    s.b = make_sphere_body(1.0);
    const Vec3 c(0.13, -0.07, 1.0 + x);
    s.ma = still();
    s.mb = {Rigid_pose_3(rotation(Vec3(1, 1, 0), 0.7), c), Vec3(0.4, -0.9, 0.3).normalized(), c,
            0.9, Vec3(0.3, 0.1, 0)};
    s.reference = [](const Rigid_pose_3& A, const Rigid_pose_3& B) {
      require_identity(A, "the plane");
      // The lowest point of the image of the unit sphere: t_z - |row z of R|.
      const Qpose P(B);
      return P.t.z - sqrt(P.R[2][0] * P.R[2][0] + P.R[2][1] * P.R[2][1] + P.R[2][2] * P.R[2][2]);
    };
    s.size = 4.0;
  } else if (key == "gap_ellipsoids" || key == "offset_ellipsoids") {
    // Two ellipsoids in general orientation, B placed so that their support points along n are
    // x apart (gap sweep) or 0.3 apart with the whole scene moved by x along a generic
    // direction (offset sweep). Both turn about the common normal line through the contact
    // points, which keeps the gap.
    const bool offset = key == "offset_ellipsoids";
    const double gap = offset ? 0.3 : x;
    const Vec3 shift = offset ? Vec3(x * Vec3(0.6, -0.48, 0.64)) : Vec3(Vec3::Zero());
    const Vec3 axes_a(3.0, 2.0, 1.5), axes_b(2.0, 1.2, 1.0);
    s.a = make_ellipsoid_body(axes_a.x(), axes_a.y(), axes_a.z(), "ellipsoid A");
    s.b = make_ellipsoid_body(axes_b.x(), axes_b.y(), axes_b.z(), "ellipsoid B");
    const Mat3 RA = rotation(Vec3(1, 2, 3), 0.4), RB = rotation(Vec3(-0.3, 0.8, 0.5), 1.1);
    const Vec3 n = Vec3(0.3, -0.5, 0.8).normalized();
    auto support = [&](const Mat3& R, const Vec3& axes, const Vec3& dir) {
      const Mat3 P = R * axes.cwiseAbs2().asDiagonal() * R.transpose();
      return Vec3(P * dir / std::sqrt(dir.dot(P * dir)));
    };
    const Vec3 xa = support(RA, axes_a, n);
    const Vec3 cb = xa + gap * n + support(RB, axes_b, n);
    s.ma = {Rigid_pose_3(RA, shift), n, xa + shift, 0.6};
    s.mb = {Rigid_pose_3(RB, cb + shift), n, xa + shift, -0.9};
    s.reference = [axes_a, axes_b, n](const Rigid_pose_3& A, const Rigid_pose_3& B) {
      return ellipsoid_gap(A, axes_a, B, axes_b, n);
    };
    s.size = 6.0;
  } else if (key == "gap_curved_faces") {
    // A bicubic cap (peak at a generic parameter) under a bicubic bowl whose lowest point is x
    // above the peak: A lies below the peak's height, B above its lowest point. Each turns
    // about the vertical through its extreme point (both paraboloids of revolution there).
    const Vec3 peak(0.23, -0.31, 0.0), bottom(-0.17, 0.29, 0.0);
    s.a = body_of(paraboloid_bicubic(-0.4, peak.x(), peak.y()), "bspline", "cap");
    s.b = body_of(paraboloid_bicubic(0.3, bottom.x(), bottom.y()), "bspline", "bowl");
    const Vec3 tb = peak - bottom + Vec3(0, 0, x);
    s.ma = {Rigid_pose_3(), Vec3::UnitZ(), peak, 0.5};
    s.mb = {Rigid_pose_3(Mat3::Identity(), tb), Vec3::UnitZ(), peak + Vec3(0, 0, x), -0.8};
    s.reference = [peak, bottom](const Rigid_pose_3& A, const Rigid_pose_3& B) {
      const Qv pa = Qpose(A).apply(qv(peak)), pb = Qpose(B).apply(qv(bottom));
      require(abs(pa.x - pb.x) < Quad(1e-12) && abs(pa.y - pb.y) < Quad(1e-12),
              "the extreme points must stay on one vertical");
      require(Qpose(A).R[2][2] == 1 && Qpose(B).R[2][2] == 1, "the turns must be about z");
      return pb.z - pa.z;
    };
    s.size = 2.0;
  } else if (key == "axis_torus" || key == "axis_sphere_pole" || key == "axis_cone") {
    // A point x from the axis of a torus (3, 1) at height 0.5 (the minima become a circle at
    // x = 0), above a unit sphere's pole (the minimum reaches the pole), or in a cone's cavity
    // (half-angle 45 degrees) 0.2 above its apex (a circle at x = 0). It circles the axis.
    const Vec3 p(x * std::cos(0.7), x * std::sin(0.7), key == "axis_torus" ? 0.5
                                                       : key == "axis_cone" ? 0.2
                                                                            : 1.5);
    if (key == "axis_torus") s.a = make_torus_body(3.0, 1.0);
    if (key == "axis_sphere_pole") s.a = make_sphere_body(1.0);
    if (key == "axis_cone") s.a = body_of(cone_side(1.0, 1.0), "cone", "cone");
    s.b = make_point_body();
    s.ma = still();
    s.mb = {Rigid_pose_3(Mat3::Identity(), p), Vec3::UnitZ(), Vec3::Zero(), 1.0};
    s.reference = [key](const Rigid_pose_3& A, const Rigid_pose_3& B) {
      require_identity(A, "the surface");
      const Qv q = qv(B.translation());
      const Quad rho = sqrt(q.x * q.x + q.y * q.y);
      if (key == "axis_torus") return sqrt((3 - rho) * (3 - rho) + q.z * q.z) - 1;
      if (key == "axis_sphere_pole") return norm(q) - 1;
      // Cone z = rho: the foot on the generator on the point's side lies at height (rho+z)/2.
      require(q.z > rho && (rho + q.z) / 2 < 1, "the point must stay in the cone's cavity");
      return (q.z - rho) * sqrt(Quad(0.5));
    };
    s.size = key == "axis_torus" ? 8.0 : 2.0;
  } else if (key == "minima_two_bumps") {
    // A 6 x 4 plane 0.8 above a bicubic patch with two bumps whose tops differ by x: the
    // distance is to the higher one. The plane slides and turns about the vertical.
    const Quad m1 = basis_max(k_bump_knots_u, 3), m2 = basis_max(k_bump_knots_u, 7);
    const Quad mv = basis_max(k_bump_knots_v, 3);
    const double c1 = 1.0;
    const double c2 = static_cast<double>((Quad(c1) * m1 * mv - Quad(x)) / (m2 * mv));
    const Quad top = std::max(Quad(c1) * m1 * mv, Quad(c2) * m2 * mv);
    s.a = body_of(two_bumps(c1, c2), "bspline", "two bumps");
    s.b = make_plane_body(6.0, 4.0);
    const Vec3 c(0.1, -0.05, 0.8);
    s.ma = still();
    const Mat3 flip = Vec3(1, -1, -1).asDiagonal();  // exactly level, facing down
    s.mb = {Rigid_pose_3(flip, c), Vec3::UnitZ(), c, 0.6,
            Vec3(0.15, 0.1, 0)};
    s.reference = [top](const Rigid_pose_3& A, const Rigid_pose_3& B) {
      require_identity(A, "the patch");
      require(B.rotation()(2, 0) == 0 && B.rotation()(2, 1) == 0, "the plane must stay level");
      return Quad(B.translation().z()) - top;
    };
    s.size = 6.0;
  } else if (key == "weights_octant") {
    // A point 0.5 outside a sphere octant whose weights span [1/x, x]; it turns about an axis
    // through the centre.
    s.a = body_of(octant(1.0, x), "bspline", "octant");
    s.b = make_point_body();
    s.ma = still();
    s.mb = {Rigid_pose_3(Mat3::Identity(), 1.5 * Vec3(1.0, 0.8, 1.2).normalized()),
            Vec3(0.3, -0.5, 0.8).normalized(), Vec3::Zero(), 1.0};
    s.reference = [](const Rigid_pose_3& A, const Rigid_pose_3& B) {
      require_identity(A, "the octant");
      const Qv q = qv(B.translation());
      require(q.x > 0 && q.y > 0 && q.z > 0, "the point must stay over the octant");
      return norm(q) - 1;
    };
    s.size = 1.5;
  } else if (key == "trim_outside" || key == "trim_inside") {
    // A point 0.37 above a square trimmed by a slanted line that passes x from the point's foot:
    // the foot just outside the face (the minimum on the trim) or just inside it. The point
    // slides along the trim line.
    const Vec3 n(std::cos(0.4), std::sin(0.4), 0.0), along(-n.y(), n.x(), 0.0);
    const Vec3 on_line(0.5, 0.45, 0.0);
    std::vector<Vec3> corners;
    s.a = trimmed_square(n, n.dot(on_line), corners);
    s.b = make_point_body();
    const double side = key == "trim_inside" ? 1.0 : -1.0;
    const Vec3 p = on_line + 0.05 * along + side * x * n + Vec3(0, 0, 0.37);
    s.ma = still();
    s.mb = {Rigid_pose_3(Mat3::Identity(), p), Vec3::UnitZ(), p, 0.0, 0.2 * along};
    s.reference = [corners](const Rigid_pose_3& A, const Rigid_pose_3& B) {
      require_identity(A, "the face");
      const Qv q = qv(B.translation());
      bool inside = true;
      Quad nearest = 1e9;
      for (std::size_t k = 0; k < corners.size(); ++k) {
        const Qv a = qv(corners[k]), b = qv(corners[(k + 1) % corners.size()]);
        const Qv e = b - a, f = Qv{q.x, q.y, 0} - a;
        if (e.x * f.y - e.y * f.x < 0) inside = false;
        Quad s = dot(f, e) / dot(e, e);
        s = std::min(Quad(1), std::max(Quad(0), s));
        nearest = std::min(nearest, norm(f - s * e));
      }
      return inside ? abs(q.z) : sqrt(q.z * q.z + nearest * nearest);
    };
    s.size = 1.5;
  } else {
    throw std::invalid_argument("unknown stress ladder sweep '" + key + "'");
  }
  return s;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

bool finite(double x) { return std::isfinite(x); }

}  // namespace

const std::vector<Ladder_sweep>& ladder_sweeps() {
  static const std::vector<Ladder_sweep> sweeps = [] {
    const std::vector<double> angle = decades(-1, -12, true), gap = decades(-1, -14, true);
    const std::vector<double> axis = decades(-1, -15, true);
    std::vector<Ladder_sweep> v;
    v.push_back({"angle_shaft_in_bore", "angle between axes", "angle", "shaft tilted in a bore",
                 "tilt (rad)", "max over the rims of the distance to the axis (Quad)", angle,
                 {1e-3, 1e-9, 0.0}, "", ""});
    v.push_back({"angle_cylinders_side_by_side", "angle between axes", "angle",
                 "cylinder beside cylinder", "angle (rad)",
                 "distance of the skew axes - radii (Quad)", angle, {1e-3, 1e-9, 0.0}, "", ""});
    v.push_back({"angle_plane_over_plane", "angle between axes", "angle", "plane over plane",
                 "tilt (rad)", "lowest corner (Quad)", angle, {1e-3, 1e-9, 0.0}, "", ""});
    v.push_back({"gap_sphere_plane", "gap to tangency", "gap", "sphere over plane", "gap",
                 "c_z - |row z of R| (Quad)", gap, {1e-3, 1e-10, 1e-14}, "", ""});
    v.push_back({"gap_ellipsoids", "gap to tangency", "gap", "ellipsoid over ellipsoid", "gap",
                 "support-slab separation, Newton on the sphere (Quad)", gap,
                 {1e-3, 1e-10, 1e-14}, "", ""});
    v.push_back({"gap_curved_faces", "gap to tangency", "gap", "bicubic cap under bicubic bowl",
                 "gap", "peak-to-bottom height (Quad)", gap, {1e-3, 1e-10, 1e-14}, "", ""});
    v.push_back({"axis_torus", "point near an axis or a pole", "axis", "point near a torus's axis",
                 "distance to the axis", "sqrt((R - rho)^2 + z^2) - r (Quad)", axis,
                 {1e-3, 1e-9, 0.0}, "", ""});
    v.push_back({"axis_sphere_pole", "point near an axis or a pole", "axis",
                 "point over a sphere's pole", "distance to the axis", "|p| - r (Quad)", axis,
                 {1e-3, 1e-9, 0.0}, "", ""});
    v.push_back({"axis_cone", "point near an axis or a pole", "axis",
                 "point in a cone near its apex", "distance to the axis",
                 "(z - rho) sin 45 deg (Quad)", axis, {1e-3, 1e-9, 0.0}, "", ""});
    v.push_back({"minima_two_bumps", "two near-equal minima", "minima",
                 "plane over two bumps of a bicubic patch", "difference of the minima",
                 "plane height - higher top, basis maxima (Quad)", decades(-1, -15, true),
                 {1e-3, 1e-9, 0.0}, "", ""});
    v.push_back({"weights_octant", "rational weights", "weights",
                 "point over a sphere octant", "weight spread s (weights in [1/s, s])",
                 "|p| - r (Quad)", decades(0, 28, false, 2), {1.0, 1e4, 1e26}, "", ""});
    v.push_back({"offset_ellipsoids", "distance from the origin", "offset",
                 "ellipsoid pair moved away from the origin", "offset",
                 "support-slab separation, Newton on the sphere (Quad)", decades(0, 9, false),
                 {1.0, 1e6, 1e9}, "", ""});
    v.push_back({"trim_outside", "trim near a minimum", "trim",
                 "point over a trimmed square, foot outside", "trim to foot",
                 "distance to the trimmed square (Quad)", decades(-1, -12, true),
                 {1e-3, 1e-9, 0.0}, "", ""});
    v.push_back({"trim_inside", "trim near a minimum", "trim",
                 "point over a trimmed square, foot inside", "trim to foot",
                 "distance to the trimmed square (Quad)", decades(-1, -12, true),
                 {1e-3, 1e-9, 0.0}, "", ""});
    return v;
  }();
  return sweeps;
}

Rung_result run_rung(const Ladder_sweep& sweep, double value, const Ladder_options& options) {
  using Clock = std::chrono::steady_clock;
  const Rung_scene s = make_scene(sweep.key, value);
  Rung_result r;
  r.sweep = sweep.key;
  r.parameter = value;
  const Placement pa = s.ma.at(0.0), pb = s.mb.at(0.0);
  const Quad reference = s.reference(pa.pose, pb.pose);
  r.reference = static_cast<double>(reference);
  const double reach = std::max(pa.pose.translation().cwiseAbs().maxCoeff(),
                                pb.pose.translation().cwiseAbs().maxCoeff());
  r.slack = k_eps * (k_shape_ulps * s.size + k_coordinate_ulps * reach);

  // One-shot.
  const Distance_hierarchy ha(s.a), hb(s.b);
  Distance_workspace ws;
  std::vector<double> times;
  // A first, untimed solve grows the workspace's buffers: the timed ones run warm, as an
  // application's repeated queries do.
  Distance_result d = extremal_distance(ha, pa.pose, hb, pb.pose, options.one_shot, ws);
  double spent = 0.0;
  for (int k = 0; k < options.max_repeats; ++k) {
    const auto t0 = Clock::now();
    d = extremal_distance(ha, pa.pose, hb, pb.pose, options.one_shot, ws);
    const double dt = std::chrono::duration<double>(Clock::now() - t0).count();
    times.push_back(dt);
    spent += dt;
    if (spent >= options.repeat_seconds) break;
  }
  r.seconds = median(times);
  r.repeats = static_cast<int>(times.size());
  r.status = d.status;
  r.distance = d.distance;
  r.lower = d.lower_bound;
  r.upper = d.upper_bound;
  r.tolerance_used = d.tolerance_used;
  r.nodes = d.nodes_created;
  r.budget = std::max(options.one_shot.absolute_tolerance,
                      options.one_shot.relative_tolerance * std::abs(r.reference));
  r.error = finite(d.distance) ? static_cast<double>(abs(Quad(d.distance) - reference))
                               : std::numeric_limits<double>::quiet_NaN();
  r.lower_gap = finite(d.lower_bound) ? static_cast<double>(reference - Quad(d.lower_bound))
                                      : std::numeric_limits<double>::quiet_NaN();

  // Tracked.
  r.tracked_budget = options.tracked.tolerance.at(r.reference);
  Body_pair_tracker tracker(s.a, s.b, options.tracked);
  std::map<std::string, int> statuses;
  std::vector<double> step_times;
  // EXTREMAL_LADDER_TRACE=1 prints every tracked row.
  const bool trace = std::getenv("EXTREMAL_LADDER_TRACE") != nullptr;
  for (int k = 0; k < options.tracked_steps; ++k) {
    const double t = k * k_dt;
    const Placement qa = s.ma.at(t), qb = s.mb.at(t);
    const auto t0 = Clock::now();
    const Pair_report& rep = tracker.step(t, qa.pose, qa.twist, qb.pose, qb.twist, k_dt);
    if (k > 0) step_times.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
    ++r.steps;
    ++statuses[to_string(rep.status)];
    const bool nan = !(finite(rep.distance) && rep.point_a.allFinite() &&
                       rep.point_b.allFinite() && rep.normal.allFinite()) ||
                     (rep.lower_bound && !finite(*rep.lower_bound));
    if (nan) {
      ++r.nan_rows;
      continue;
    }
    const Quad ref = s.reference(qa.pose, qb.pose);
    const double error = static_cast<double>(abs(Quad(rep.distance) - ref));
    if (trace)
      std::printf("  row %d t %.3f: %s distance %.17g reference %.17g lower %.17g features %d %d "
                  "params %.9f %.9f %.9f %.9f\n",
                  k, t, to_string(rep.status), rep.distance, static_cast<double>(ref),
                  rep.lower_bound ? *rep.lower_bound : std::nan(""), rep.feature_a,
                  rep.feature_b, rep.params[0], rep.params[1], rep.params[2], rep.params[3]);
    r.tracked_max_error = std::max(r.tracked_max_error, error);
    if (rep.status == Pair_status::Uncertified)
      ++r.uncertified_rows;
    else
      r.tracked_max_claimed_error = std::max(r.tracked_max_claimed_error, error);
    if (rep.lower_bound) {
      ++r.bound_rows;
      const double gap = static_cast<double>(ref - Quad(*rep.lower_bound));
      r.tracked_min_lower_gap = std::min(r.tracked_min_lower_gap, gap);
      r.tracked_max_lower_gap = std::max(r.tracked_max_lower_gap, gap);
    }
  }
  if (trace) {
    const Pair_statistics& st = tracker.statistics();
    std::printf("  statistics: trackers %d candidates %d audits %d reseeds %d seeds %ld "
                "vacated checks %ld solves %ld (nodes %ld) queued %ld located %ld\n",
                st.trackers, st.candidates, st.audits, st.reseeds, st.seeds, st.vacated_checks,
                st.vacated_solves, st.vacated_nodes, st.vacated_queued, st.located);
  }
  r.step_seconds = median(step_times);
  std::ostringstream os;
  for (const auto& [name, count] : statuses)
    os << (os.tellp() > 0 ? ", " : "") << name << " " << count;
  r.tracked_statuses = os.str();
  r.violations = rung_violations(r);
  return r;
}

std::vector<std::string> rung_violations(const Rung_result& r) {
  std::vector<std::string> v;
  auto say = [&](const std::string& what, double x) {
    std::ostringstream os;
    os.precision(3);
    os << what << " " << std::scientific << x;
    v.push_back(os.str());
  };
  if (!(finite(r.distance) && finite(r.lower) && finite(r.upper)))
    v.push_back("one-shot: not finite");
  else {
    if (r.lower_gap < -r.slack) say("one-shot: lower bound above the reference by", -r.lower_gap);
    if (r.reference - r.distance > r.slack)
      say("one-shot: witness distance below the reference by", r.reference - r.distance);
    if (r.certified() && r.error > std::max(r.tolerance_used, r.budget) + r.slack)
      say("one-shot: certified but off the reference by", r.error);
  }
  if (r.nan_rows > 0) v.push_back("tracked: " + std::to_string(r.nan_rows) + " rows not finite");
  if (r.tracked_min_lower_gap < -r.slack)
    say("tracked: lower bound above the reference by", -r.tracked_min_lower_gap);
  if (r.tracked_max_claimed_error > r.tracked_budget + r.slack)
    say("tracked: a row not marked uncertified is off the reference by",
        r.tracked_max_claimed_error);
  return v;
}

}  // namespace extremal::experiments
