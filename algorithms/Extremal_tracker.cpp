#include "algorithms/Extremal_tracker.h"

#include <cmath>
#include <limits>

#include "kernel/Error.h"

namespace extremal {

namespace {
constexpr double k_max_change_fraction = 0.125;
}  // namespace

const char* to_string(Track_status s) {
  switch (s) {
    case Track_status::Tracking: return "tracking";
    case Track_status::Singular_jacobian: return "fallback";
  }
  return "unknown";
}

Extremal_tracker::Extremal_tracker(const Feature& a, const Feature& b, const Vec4& initial,
                                   const Tracker_options& options)
    : m_a(a), m_b(b), m_options(options), m_domain(Parameter_domain::of(a, b)),
      m_params(initial) {
  EXTREMAL_PRECONDITION_MSG(options.gain.allFinite() && options.gain.minCoeff() >= 0.0,
                            "tracker gain must be finite and >= 0");
  EXTREMAL_PRECONDITION_MSG(options.substeps >= 1, "substeps must be >= 1");
  EXTREMAL_PRECONDITION_MSG(options.corrections >= 0, "corrections must be >= 0");
  m_domain.clamp(m_params);
  m_max_change.setConstant(std::numeric_limits<double>::infinity());
  for (int k = 0; k < m_domain.n; ++k)
    m_max_change[k] = k_max_change_fraction * (m_domain.upper[k] - m_domain.lower[k]);
}

void Extremal_tracker::reset(const Vec4& params) {
  m_params = params;
  m_domain.clamp(m_params);
}

bool Extremal_tracker::control(const Vec4& params, const Rigid_pose_3& X_WA, const Twist_3& V_A,
                               const Rigid_pose_3& X_WB, const Twist_3& V_B, double dt,
                               Vec4& U) {
  build_pair_system({&m_a, &X_WA, &V_A}, {&m_b, &X_WB, &V_B}, params, m_system, true);
  const int n = m_system.size();
  Vec4 rhs;
  for (int k = 0; k < 4; ++k) {
    const double K = m_options.gain[k] > 0.0 ? m_options.gain[k] : 1.0 / dt;
    rhs[k] = k < n ? -K * m_system.phi[k] - m_system.motion[k] : 0.0;
  }
  Vec4 p = params;
  const unsigned on_bound = m_domain.clamp(p);
  if (!solve_constrained(m_system.M, rhs, n, on_bound, m_domain.lower_mask(p), U,
                         solve_mode_for(m_system)))
    return false;
  // Far from the pair a full Newton step can leap to another stationary pair; limit the
  // parameter change per step to a fraction of each domain, keeping the direction.
  double scale = 1.0;
  for (int k = 0; k < n; ++k) {
    const double change = std::abs(U[k]) * dt;
    if (change > m_max_change[k]) scale = std::min(scale, m_max_change[k] / change);
  }
  U *= scale;
  return true;
}

int Extremal_tracker::correct(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB) {
  int done = 0;
  const Posed_feature a{&m_a, &X_WA, nullptr}, b{&m_b, &X_WB, nullptr};
  const int n = m_a.dimension() + m_b.dimension();
  while (done < m_options.corrections) {
    build_pair_system(a, b, m_params, m_system, false);
    if (normalised_projection_errors(m_system).cwiseAbs().maxCoeff() <=
        m_options.correction_tolerance)
      break;
    Vec4 x = m_params;
    const unsigned on_bound = m_domain.clamp(x);
    Vec4 step;
    ++done;
    if (!solve_constrained(m_system.M, -m_system.phi, n, on_bound, m_domain.lower_mask(x),
                           step, solve_mode_for(m_system)))
      break;
    double scale = 1.0;
    for (int k = 0; k < n; ++k)
      if (std::abs(step[k]) > m_max_change[k]) scale = std::min(scale, m_max_change[k] / std::abs(step[k]));
    m_params += scale * step;
    m_domain.clamp(m_params);
  }
  return done;
}

void Extremal_tracker::fill_result(double t) {
  Track_result& r = m_result;
  r.time = t;
  r.params = m_params;
  r.point_a = m_system.a.p;
  r.point_b = m_system.b.p;
  const Vec3 ab = r.point_b - r.point_a;
  r.distance = ab.norm();
  r.normal = r.distance > 0.0 ? Vec3(ab / r.distance) : Vec3::Zero();
  r.projection_errors = m_system.phi;
  r.normalised_errors = normalised_projection_errors(m_system);
}

const Track_result& Extremal_tracker::evaluate(double t, const Rigid_pose_3& X_WA,
                                               const Rigid_pose_3& X_WB) {
  build_pair_system({&m_a, &X_WA, nullptr}, {&m_b, &X_WB, nullptr}, m_params, m_system, false);
  fill_result(t);
  m_result.iterations = 0;
  m_result.status = Track_status::Tracking;
  return m_result;
}

const Track_result& Extremal_tracker::step(double t, const Rigid_pose_3& X_WA,
                                           const Twist_3& V_A, const Rigid_pose_3& X_WB,
                                           const Twist_3& V_B, double dt) {
  EXTREMAL_PRECONDITION_MSG(dt > 0.0 && std::isfinite(dt), "dt = " << dt << " must be > 0");
  const int substeps = m_options.substeps;
  const double h = dt / substeps;
  int solves = 0;
  bool singular = false;
  solves += correct(X_WA, X_WB);
  Vec4 x = m_params;
  for (int s = 0; s < substeps && !singular; ++s) {
    // Poses at the start of the substep, from the twists (held constant over the step).
    const double tau = s * h;
    const Rigid_pose_3 A0 = s == 0 ? X_WA : advance(X_WA, V_A, tau);
    const Rigid_pose_3 B0 = s == 0 ? X_WB : advance(X_WB, V_B, tau);
    Vec4 k1;
    ++solves;
    if (!control(x, A0, V_A, B0, V_B, h, k1)) {
      singular = true;
      break;
    }
    if (s == 0) fill_result(t);  // the pair at time t, before the parameters move
    if (m_options.integrator == Integrator::Euler) {
      x += h * k1;
    } else {
      const Rigid_pose_3 Ah = advance(X_WA, V_A, tau + 0.5 * h);
      const Rigid_pose_3 Bh = advance(X_WB, V_B, tau + 0.5 * h);
      const Rigid_pose_3 A1 = advance(X_WA, V_A, tau + h);
      const Rigid_pose_3 B1 = advance(X_WB, V_B, tau + h);
      Vec4 k2, k3, k4;
      Vec4 y = x + 0.5 * h * k1;
      m_domain.clamp(y);
      singular = !control(y, Ah, V_A, Bh, V_B, h, k2);
      y = x + 0.5 * h * k2;
      m_domain.clamp(y);
      singular = singular || !control(y, Ah, V_A, Bh, V_B, h, k3);
      y = x + h * k3;
      m_domain.clamp(y);
      singular = singular || !control(y, A1, V_A, B1, V_B, h, k4);
      solves += 3;
      if (singular) break;
      x += (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
    m_domain.clamp(x);
  }
  if (singular) {
    // Keep the last good parameters and report the pair there.
    build_pair_system({&m_a, &X_WA, nullptr}, {&m_b, &X_WB, nullptr}, m_params, m_system, false);
    fill_result(t);
    m_result.status = Track_status::Singular_jacobian;
  } else {
    m_params = x;
    m_result.status = Track_status::Tracking;
  }
  m_result.iterations = solves;
  return m_result;
}

}  // namespace extremal
