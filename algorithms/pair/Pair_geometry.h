// The extremal-pair conditions between two posed features and their derivatives
// (docs/design.md, "The pair system"). With d = f - h (f on A, h on B, world frame):
//   Phi = [d.f_i (i over A's parameters), d.h_j (j over B's parameters)]
//   dPhi/dt = M U + b, U the parameter velocities, b the motion term at fixed parameters.
// Vectors and matrices are padded to size 4: unused entries of Phi and b are zero and the
// unused block of M is the identity, so every solve is one fixed-size 4x4 solve.
#pragma once

#include <Eigen/Core>

#include "algorithms/pair/Feature.h"
#include "kernel/Rigid_pose_3.h"

namespace extremal {

using Vec4 = Eigen::Vector4d;
using Mat4 = Eigen::Matrix4d;

// Which conditions the system expresses. Both vanish exactly at the extremal pair; they differ
// in their Jacobian. The projection form (the seed's) loses rank at tangential contact (d = 0);
// the normal form replaces the rows of the side opposite a reference surface R by
// n_R . t_j (normals parallel), whose Jacobian stays regular through contact
// (docs/design.md, "Where the seed's form breaks").
enum class Formulation { Projection, Normal_of_a, Normal_of_b };

struct Pair_system {
  int na = 0, nb = 0;  // parameter counts of A and B; params = [A's..., B's...]
  Formulation form = Formulation::Projection;
  Feature_point a, b;  // both features at the parameters, in the world
  Vec3 d = Vec3::Zero();  // a.p - b.p
  double distance = 0.0;   // |d|, taken once per build (control, sign and errors read it)
  Vec4 tangent_length2 = Vec4::Zero();  // |tangent k|^2, once per build (errors, solve scale)
  // S M is exactly symmetric (S = +1 on A's rows, -1 on B's): true where the build writes
  // mirrored entries (the surface-surface projection rows), so a solve need not symmetrise.
  bool symmetric_hessian = false;
  // sign (t_u x t_v) of each surface: outward, not unit (zero for curves and points). The
  // tracker's step reads only its direction (the distance's sign), so the build takes no square
  // root or division for it; unit_normal() gives the unit vector.
  Vec3 outward_a = Vec3::Zero(), outward_b = Vec3::Zero();
  Vec4 projection = Vec4::Zero();  // the seed's projection errors, whatever the form
  Vec4 phi = Vec4::Zero();         // the conditions of `form`
  Mat4 M = Mat4::Identity();       // d phi / d params
  Vec4 motion = Vec4::Zero();      // d phi / dt at fixed parameters (b of the design card)
  // The knot spans the last build found on each side, where the next build looks first.
  Span_hint spans_a, spans_b;

  int size() const { return na + nb; }
  // Tangent along parameter k (A's first, then B's).
  const Vec3& tangent(int k) const { return k < na ? a.d[k] : b.d[k - na]; }
};

struct Posed_feature {
  const Feature* feature;
  const Rigid_pose_3* pose;
  const Twist_3* twist;  // may be null: at rest
};

// Evaluates the conditions of `form`, M and, when `with_motion`, b at `params`. The normal
// forms need a surface on the reference side (otherwise the projection form is used). No heap
// allocation.
void build_pair_system(const Posed_feature& A, const Posed_feature& B, const Vec4& params,
                       Pair_system& out, bool with_motion = true,
                       Formulation form = Formulation::Projection);

// outward / |outward|, zero where it vanishes (a pole, or no surface).
Vec3 unit_normal(const Vec3& outward);

// Seed's normalised projection errors Phi_k / (|d| |tangent_k|); zero where undefined.
Vec4 normalised_projection_errors(const Pair_system& s);

// The parameter box of a pair, [A's..., B's...], with the closed (wrapping) directions.
struct Parameter_domain {
  int n = 0;
  Vec4 lower = Vec4::Zero(), upper = Vec4::Zero();
  unsigned closed = 0;  // bit k: parameter k wraps

  static Parameter_domain of(const Feature& A, const Feature& B);
  // Puts parameters back into the domain: closed directions wrap, the rest clamp. Bit k of the
  // returned mask is set when parameter k sits on a bound.
  unsigned clamp(Vec4& params) const;
  // Every used parameter strictly between its bounds (false for NaN).
  bool strictly_inside(const Vec4& params) const;
  // Bit k set when parameter k sits on its lower bound.
  unsigned lower_mask(const Vec4& params) const;
};

unsigned keep_in_domain(const Feature& A, const Feature& B, Vec4& params);

// How solve_constrained treats a Jacobian that is not that of a minimum.
struct Solve_mode {
  // Seek a minimum of |d|: Phi is [grad_A, -grad_B] of |d|^2 / 2, so H = S M (S = +1 on A's
  // rows, -1 on B's) is its Hessian, positive definite at a strict minimum. When it is not
  // (far from the pair, near a saddle or maximum) H is shifted to be positive definite, which
  // turns the step into a descent step; near a minimum the step is the plain Newton step.
  // Off inside penetration, where the extremal pair is a saddle.
  bool minimum = true;
  int na = 0;  // A's parameter count, for S
  // Natural size of M's entries (the squared tangent lengths); M is singular when a pivot
  // falls below 1e-12 of it. Zero: the largest entry of M.
  double scale = 0.0;
  // Damped least squares instead of a plain solve: directions in which M is (nearly) singular
  // (a continuum of pairs, a pole) get no step, the rest the Newton step. Never fails on finite
  // input.
  bool damped = false;
  // How a Hessian that is not positive definite is shifted: scaled by its diagonal (keeps the
  // Newton step along weakly curved directions: the tracker near poles) or uniformly (the
  // steadier choice for Newton at rest from sampled starts, which the global solver polishes
  // with).
  bool scaled_shift = false;
  // S M is exactly symmetric (Pair_system::symmetric_hessian): no symmetrising mean needed.
  bool symmetric = false;
  // Seeking a minimum with a parameter of B held on its bound: its identity row is negated with
  // B's rows, so H is shifted and every step heavily damped. Newton at rest relies on that to
  // settle on a pole held on a bound; the tracker turns it off (its steps there would be half
  // Newton steps: linear convergence).
  bool damp_when_b_held = true;
};

// The Solve_mode for a pair system: seeking a minimum unless `minimum` is false.
Solve_mode solve_mode_for(const Pair_system& s, bool minimum = true);

// Solves M x = rhs for the active parameters: a parameter on a bound (bit k of `on_bound`)
// whose solution would push it outward is frozen (x_k = 0) and the rest re-solved, so a pair on
// an edge continues as the reduced problem. Returns false if the system is singular or the
// answer not finite (x is then zero). `lower_side` bit k says the bound is the lower one.
// Parameters in `frozen` (a subset of on_bound) are held whatever the solution says.
bool solve_constrained(const Mat4& M, const Vec4& rhs, int n, unsigned on_bound,
                       unsigned lower_side, Vec4& x, const Solve_mode& mode = {false, 0},
                       unsigned frozen = 0u);

namespace internal {
// solve_constrained's common case, exposed for its tests: seeking a minimum with nothing frozen
// (S = +1 on the first na rows, -1 on the rest of the n active ones), H = S M positive definite
// with every pivot above 1e-12 scale (two surfaces: by 2 x 2 blocks). False, x untouched, where
// the general path has to decide.
bool solve_minimum_pd(const Mat4& M, const Vec4& rhs, int na, int n, double scale, bool symmetric,
                      Vec4& x);
}  // namespace internal


struct Newton_options {
  int max_iterations = 60;
  double tolerance = 1e-15;  // on the normalised projection errors
};

struct Newton_result {
  Vec4 params = Vec4::Zero();
  int iterations = 0;
  bool converged = false;
};

// Newton's method on Phi = 0 with both bodies at rest, steps limited to a quarter of each
// parameter domain and kept inside it. Converges to the extremal pair near `start`.
Newton_result solve_pair_at_rest(const Posed_feature& A, const Posed_feature& B,
                                 const Vec4& start, const Newton_options& options = {});

}  // namespace extremal
