#include "algorithms/pair/Extremal_tracker.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernel/Error.h"

namespace extremal {

namespace {
// Far from the pair a full Newton step can leap to another stationary pair: the parameter
// change per step is limited to this fraction of each domain, keeping the direction.
constexpr double k_max_change_fraction = 0.125;
// A reference surface whose witness comes within this fraction of a parameter's range from a
// pole hands the normal form's reference over, until it is farther than the second (choose_form).
constexpr double k_near_pole_fraction = 1e-3;
constexpr double k_leave_pole_fraction = 0.1;
}  // namespace

const char* to_string(Track_status s) {
  switch (s) {
    case Track_status::Tracking: return "tracking";
    case Track_status::On_boundary: return "boundary";
    case Track_status::Singular_fallback: return "fallback";
  }
  return "unknown";
}

const char* to_string(Degeneracy d) {
  switch (d) {
    case Degeneracy::None: return "";
    case Degeneracy::Pole: return "pole";
    case Degeneracy::Parallel: return "parallel";
    case Degeneracy::Coincident: return "coincident";
    case Degeneracy::Singular: return "singular";
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
  EXTREMAL_PRECONDITION_MSG(options.contact_band >= 0.0, "contact_band must be >= 0");
  m_domain.clamp(m_params);
  m_max_change.setConstant(std::numeric_limits<double>::infinity());
  for (int k = 0; k < m_domain.n; ++k)
    m_max_change[k] = k_max_change_fraction * (m_domain.upper[k] - m_domain.lower[k]);
  // Parameters whose bounds are poles: a collapsed edge across a wrapping direction.
  for (int side = 0; side < 2; ++side) {
    const Feature& f = side == 0 ? a : b;
    if (f.dimension() != 2) continue;
    const int offset = side == 0 ? 0 : a.dimension();
    const unsigned c = f.collapsed_edges();
    // One end may be a pole and the other a real edge (a disk: centre and rim).
    if (m_domain.closed & (1u << (offset + 1))) {
      if (c & 1u) m_pole_lower |= 1u << offset;
      if (c & 2u) m_pole_upper |= 1u << offset;
    }
    if (m_domain.closed & (1u << offset)) {
      if (c & 4u) m_pole_lower |= 1u << (offset + 1);
      if (c & 8u) m_pole_upper |= 1u << (offset + 1);
    }
  }
  // The normal form needs a reference surface and parameters on the other side.
  if (a.dimension() == 2 && b.dimension() > 0) {
    m_normal_form = Formulation::Normal_of_a;
    m_band = options.contact_band * std::min(a.size(), b.size());
  } else if (b.dimension() == 2 && a.dimension() > 0) {
    m_normal_form = Formulation::Normal_of_b;
    m_band = options.contact_band * std::min(a.size(), b.size());
  }
}

unsigned Extremal_tracker::clamp_to_edges(Vec4& params) const {
  const unsigned on_bound = m_domain.clamp(params);
  if (!(on_bound & (m_pole_lower | m_pole_upper))) return on_bound;
  const unsigned lower = m_domain.lower_mask(params);
  return on_bound & ~((lower & m_pole_lower) | (~lower & m_pole_upper));
}

void Extremal_tracker::reset(const Vec4& params) {
  m_params = params;
  m_domain.clamp(m_params);
}

bool Extremal_tracker::near_pole(int side, const Vec4& params, double fraction) const {
  if (!(m_pole_lower | m_pole_upper)) return false;
  const int first = side == 0 ? 0 : m_a.dimension();
  const int count = side == 0 ? m_a.dimension() : m_b.dimension();
  for (int k = first; k < first + count; ++k) {
    const double near = fraction * (m_domain.upper[k] - m_domain.lower[k]);
    if (((m_pole_lower >> k) & 1u) && params[k] - m_domain.lower[k] < near) return true;
    if (((m_pole_upper >> k) & 1u) && m_domain.upper[k] - params[k] < near) return true;
  }
  return false;
}

void Extremal_tracker::update_reference_at_pole(const Vec4& params) {
  if (m_normal_form == Formulation::Projection || !(m_pole_lower | m_pole_upper)) return;
  const int side = m_normal_form == Formulation::Normal_of_a ? 0 : 1;
  m_reference_at_pole =
      near_pole(side, params, m_reference_at_pole ? k_leave_pole_fraction : k_near_pole_fraction);
}

Formulation Extremal_tracker::choose_form(unsigned on_edge, const Vec4& params) const {
  if (!m_in_band) return Formulation::Projection;
  // A reference surface held on its patch edge: its normal no longer gives the pair's
  // direction, the other side's does (an ellipsoid below a plane's rim: the normal form of the
  // plane finds the ellipsoid's lowest point, not its point nearest the rim). The other surface
  // becomes the reference, or the projection form holds where it is held too or no surface.
  // A reference at a pole of its parametrisation keeps its normal, but its rows (d . t, whose
  // tangent vanishes there) hold the other witness along one direction only, and the normal
  // rows of a flat other surface hold it nowhere: a ball's pole sliding 0.01 deep on a plane
  // left the plane's witness behind (read -0.33). The other surface is the reference there
  // (update_reference_at_pole), if it is one, not held and not at a pole itself.
  const int na = m_a.dimension();
  const bool held_a = (on_edge & 3u) != 0u, held_b = ((on_edge >> na) & 3u) != 0u;
  if (m_normal_form == Formulation::Normal_of_a) {
    const bool b_can = m_b.dimension() == 2 && !held_b && na > 0;
    if (held_a) return b_can ? Formulation::Normal_of_b : Formulation::Projection;
    if (m_reference_at_pole && b_can && !near_pole(1, params, k_near_pole_fraction))
      return Formulation::Normal_of_b;
  }
  if (m_normal_form == Formulation::Normal_of_b) {
    const bool a_can = na == 2 && !held_a && m_b.dimension() > 0;
    if (held_b) return a_can ? Formulation::Normal_of_a : Formulation::Projection;
    if (m_reference_at_pole && a_can && !near_pole(0, params, k_near_pole_fraction))
      return Formulation::Normal_of_a;
  }
  return m_normal_form;
}

unsigned Extremal_tracker::edge_mask(const Vec4& params) const {
  Vec4 p = params;
  return clamp_to_edges(p);
}

double Extremal_tracker::signed_distance(unsigned on_edge, const Vec4& params) const {
  // Inside when d points against a face's outward normal at an interior point of that face:
  // A's, or B's where A's witness is on an edge of A. On a face edge the normal says nothing
  // about the solid (beside a cylinder's cap rim, say, d points below the cap's plane while the
  // bodies are apart); the other face's witness, off its edges, is the foot of d, so its normal
  // does (a tilted peg's rim pressed into a plate read its depth as a gap). Both on edges:
  // positive. At a pole (a collapsed edge, which is no edge of the face) the normal is the
  // tangents' limit: a point entering a ball through its pole is inside.
  // The outward cross product stands for the unit normal (the sign is all that is read); one
  // whose squared length underflows or overflows has no direction, as the unit normal had none.
  const auto has_direction = [](const Vec3& m) {
    const double m2 = m.squaredNorm();
    return m2 > 0.0 && m2 < HUGE_VAL;
  };
  const Vec3 ab = m_system.b.p - m_system.a.p;
  const double len = m_system.distance;  // |ab| = |d|
  const int na = m_a.dimension();
  if (m_options.sign_from_b && m_b.dimension() == 2 && !((on_edge >> na) & 3u)) {
    const Vec3 m = outward_direction(m_b, m_system.b, params.data() + na, m_system.outward_b);
    if (has_direction(m)) return ab.dot(m) > 0.0 ? -len : len;
  }
  if (m_a.dimension() == 2 && !(on_edge & 3u)) {
    const Vec3 m = outward_direction(m_a, m_system.a, params.data(), m_system.outward_a);
    return ab.dot(m) < 0.0 && has_direction(m) ? -len : len;
  }
  if (m_b.dimension() == 2) {
    const Vec3 m = outward_direction(m_b, m_system.b, params.data() + m_a.dimension(),
                                     m_system.outward_b);
    return ab.dot(m) > 0.0 && !((on_edge >> m_a.dimension()) & 3u) && has_direction(m) ? -len
                                                                                        : len;
  }
  return len;
}

unsigned Extremal_tracker::held_by_height(unsigned on_edge, unsigned lower,
                                          const Vec4& params) const {
  // Near contact and inside, the pair to hold is the witness of one side (the other's edge
  // point, say) nearest to the tangent plane of the other, the reference R, or deepest behind
  // it: the least height h = n_R . (p - q) over that side's points. Newton's step says nothing
  // about whether a held parameter should leave its edge there: the normal form's row for it,
  // n_R . t_k, cannot be zeroed on a flat face (a tilted cylinder's cap, its rim pressed into
  // a plate), and inside, the projection form's pair is a saddle. The height's slope does say.
  // (Newton let the rim go at random; the cap's interior then read its distance along the
  // cap's normal, and the side's, the side's.) In the projection form the reference is the
  // side with nothing held; apart there, the descent steps of the minimum decide.
  if (!on_edge) return 0u;
  const int na = m_a.dimension(), nb = m_b.dimension();
  const unsigned mask_a = (1u << na) - 1u, held_a = on_edge & mask_a, held_b = on_edge >> na;
  bool ref_a = m_system.form == Formulation::Normal_of_a;
  if (m_system.form == Formulation::Projection) {
    if (!(m_last_signed < 0.0) || (held_a && held_b)) return 0u;
    ref_a = held_b != 0u;
  }
  // A reference witness at a pole stands for the pair's direction only in the limit: a tilted
  // peg's rim held on a small ball's top kept the ball's witness on its pole, 2.6 times too
  // deep. Newton decides there, as before.
  if ((ref_a ? na : nb) != 2 || near_pole(ref_a ? 0 : 1, params, k_near_pole_fraction)) return 0u;
  const Vec3 n_r = ref_a ? outward_direction(m_a, m_system.a, params.data(), m_system.outward_a)
                         : outward_direction(m_b, m_system.b, params.data() + na,
                                             m_system.outward_b);
  const int first = ref_a ? na : 0, last = ref_a ? na + nb : na;
  // A slope within rounding of zero (an edge along the tangent plane: a roller's end on a
  // floor) is left to Newton.
  const double n_len = n_r.norm();
  unsigned held = 0u;
  for (int k = first; k < last; ++k) {
    if (!(on_edge & (1u << k))) continue;
    const double inward = (lower & (1u << k)) ? 1.0 : -1.0;
    const double slope = inward * n_r.dot(m_system.tangent(k));
    if (slope > 1e-6 * n_len * std::sqrt(m_system.tangent_length2[k])) held |= 1u << k;
  }
  return held;
}

Degeneracy Extremal_tracker::classify_singular() const {
  const Pair_system& s = m_system;
  for (const Feature_point* f : {&s.a, &s.b}) {
    const int dim = f == &s.a ? s.na : s.nb;
    if (dim != 2) continue;
    const double lu = f->d[0].norm(), lv = f->d[1].norm();
    if (std::min(lu, lv) <= 1e-6 * std::max(lu, lv)) return Degeneracy::Pole;
  }
  if (s.na == 2 && s.nb == 2 &&
      unit_normal(s.outward_a).cross(unit_normal(s.outward_b)).norm() < 1e-6) {
    const double size = std::max(m_a.size(), m_b.size());
    return s.distance <= 1e-9 * size ? Degeneracy::Coincident : Degeneracy::Parallel;
  }
  return Degeneracy::Singular;
}

void Extremal_tracker::control(const Vec4& params, const Rigid_pose_3& X_WA, const Twist_3* V_A,
                               const Rigid_pose_3& X_WB, const Twist_3* V_B, double gain_dt,
                               Vec4& U, Degeneracy& degeneracy) {
  const bool moving = V_A != nullptr;
  // A pole is no edge: the pair goes over it (cross_poles), so it never freezes there.
  Vec4 p = params;
  const unsigned on_bound = clamp_to_edges(p);
  update_reference_at_pole(params);
  build_pair_system({&m_a, &X_WA, V_A}, {&m_b, &X_WB, V_B}, params, m_system, moving,
                    choose_form(on_bound, params));
  // Hand-over with hysteresis: enter the normal form inside the band, leave beyond twice it.
  const double dist = m_system.distance;
  const bool in_band = m_normal_form != Formulation::Projection &&
                       (dist < m_band || (m_in_band && dist < 2.0 * m_band));
  if (in_band != m_in_band) {
    m_in_band = in_band;
    build_pair_system({&m_a, &X_WA, V_A}, {&m_b, &X_WB, V_B}, params, m_system, moving,
                      choose_form(on_bound, params));
  }
  const int n = m_system.size();
  // gain_dt > 0: the step's dt with the configured gains; a correction uses K dt = 1. The lanes
  // past n stay zero, of either sign (phi and the motion are zero there, M the identity).
  Vec4 rhs;
  if (moving) {
    const Vec4 Kdt = (m_options.gain.array() > 0.0).select(m_options.gain * gain_dt, Vec4::Ones());
    rhs = -Kdt.cwiseProduct(m_system.phi) - gain_dt * m_system.motion;
  } else {
    rhs = -m_system.phi;
  }
  // rhs is the parameter change over the step (U dt); U follows by dividing by dt.
  const unsigned lower = on_bound ? m_domain.lower_mask(p) : 0u;  // only read where on_bound
  // Kept for fill_result, which describes the pair this system was built at.
  m_last_on_edge = on_bound;
  m_last_signed = signed_distance(on_bound, params);
  Solve_mode mode = solve_mode_for(m_system);
  mode.scaled_shift = true;
  mode.damp_when_b_held = false;
  // Seek a minimum in the projection form while apart. The penetration pair is a saddle and
  // is tracked as such, but only once the pair is nearly converged: far from it the sign of
  // the distance means nothing yet. A parameter held on an edge keeps its error (0.3 for a
  // tilted cap's rim in a plate), which says nothing about how near the pair is.
  auto far_from_pair = [&] {
    const Vec4 e = normalised_projection_errors(m_system);
    for (int k = 0; k < n; ++k)
      if (!(on_bound & (1u << k)) && std::abs(e[k]) > 0.1) return true;
    return false;
  };
  mode.minimum = m_system.form == Formulation::Projection &&
                 (m_last_signed >= 0.0 || far_from_pair());
  const unsigned held = held_by_height(on_bound, lower, params);
  if (!solve_constrained(m_system.M, rhs, n, on_bound, lower, U, mode, held)) {
    degeneracy = classify_singular();
    mode.damped = true;
    if (!solve_constrained(m_system.M, rhs, n, on_bound, lower, U, mode, held)) U.setZero();
  }
  double scale = 1.0;
  if ((U.cwiseAbs().array() > m_max_change.array()).any())  // rare: far from the pair
    for (int k = 0; k < n; ++k)
      if (std::abs(U[k]) > m_max_change[k])
        scale = std::min(scale, m_max_change[k] / std::abs(U[k]));
  U *= scale / gain_dt;
}

void Extremal_tracker::cross_poles(Vec4& x) const {
  const unsigned collapsed[2] = {m_a.collapsed_edges(), m_b.collapsed_edges()};
  const int offset[2] = {0, m_a.dimension()};
  for (int side = 0; side < 2; ++side) {
    if (!collapsed[side] || (side == 0 ? m_a.dimension() : m_b.dimension()) != 2) continue;
    for (int dir = 0; dir < 2; ++dir) {  // dir: the parameter that runs into the edge
      const int k = offset[side] + dir, other = offset[side] + 1 - dir;
      if (!(m_domain.closed & (1u << other))) continue;  // needs the other direction to wrap
      const unsigned low_bit = dir == 0 ? 1u : 4u, high_bit = dir == 0 ? 2u : 8u;
      const double lo = m_domain.lower[k], hi = m_domain.upper[k];
      const double half = 0.5 * (m_domain.upper[other] - m_domain.lower[other]);
      if ((collapsed[side] & low_bit) && x[k] < lo) {
        x[k] = 2.0 * lo - x[k];
        x[other] += half;
      } else if ((collapsed[side] & high_bit) && x[k] > hi) {
        x[k] = 2.0 * hi - x[k];
        x[other] += half;
      }
    }
  }
}

void Extremal_tracker::leave_poles(Vec4& x) const {
  // The normal form's pole rows are divided by the distance to the pole (Pair_geometry.cpp),
  // which needs a distance: a parameter on a pole is moved off it by 1e-9 of its range. The
  // point moves by about that fraction of the surface's size along the surface, so the
  // distance changes by its square: nothing at double precision.
  constexpr double k_off_pole = 1e-9;
  for (int k = 0; k < m_domain.n; ++k) {
    const double off = k_off_pole * (m_domain.upper[k] - m_domain.lower[k]);
    if ((m_pole_lower & (1u << k)) && x[k] < m_domain.lower[k] + off)
      x[k] = m_domain.lower[k] + off;
    else if ((m_pole_upper & (1u << k)) && x[k] > m_domain.upper[k] - off)
      x[k] = m_domain.upper[k] - off;
  }
}

int Extremal_tracker::correct(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB,
                              Degeneracy& degeneracy) {
  int done = 0;
  const Posed_feature a{&m_a, &X_WA, nullptr}, b{&m_b, &X_WB, nullptr};
  // Merit of a candidate: the distance while seeking a minimum, else the residual of the
  // active conditions. Newton directions descend on it, so halving the step until it drops
  // keeps corrections from oscillating where the linearisation is poor (near a pole).
  // A parameter held on a patch edge keeps its condition's residual (the reduced problem is
  // solved without it): the merit leaves it out.
  auto merit = [&](bool minimum, unsigned edges) {
    if (minimum) return m_system.distance;
    double r2 = 0.0;
    for (int k = 0; k < m_system.size(); ++k)
      if (!(edges & (1u << k))) r2 += m_system.phi[k] * m_system.phi[k];
    return std::sqrt(r2);
  };
  while (done < m_options.corrections) {
    const unsigned edges = edge_mask(m_params);
    update_reference_at_pole(m_params);
    const Formulation form = choose_form(edges, m_params);
    build_pair_system(a, b, m_params, m_system, false, form);
    // A held parameter keeps its projection error too; counting it ran every correction on
    // every step of an edge pair.
    Vec4 errors = normalised_projection_errors(m_system).cwiseAbs();
    for (int k = 0; k < 4; ++k)
      if (edges & (1u << k)) errors[k] = 0.0;
    if (errors.maxCoeff() <= m_options.correction_tolerance) break;
    const bool minimum =
        m_system.form == Formulation::Projection && signed_distance(edges, m_params) >= 0.0;
    const double before = merit(minimum, edges);
    Vec4 U;
    control(m_params, X_WA, nullptr, X_WB, nullptr, 1.0, U, degeneracy);
    ++done;
    // (control may have crossed the band: the candidates are measured in the step's form.)
    const Formulation step_form = choose_form(edges, m_params);
    double alpha = 1.0;
    Vec4 x = m_params;
    for (int halving = 0; halving < 12; ++halving, alpha *= 0.5) {
      x = m_params + alpha * U;
      cross_poles(x);
      m_domain.clamp(x);
      build_pair_system(a, b, x, m_system, false, step_form);
      if (merit(minimum, edges) <= before) break;
    }
    m_params = x;
  }
  return done;
}

void Extremal_tracker::fill_result(double t, double signed_dist, unsigned on_edge) {
  Track_result& r = m_result;
  r.time = t;
  r.params = m_params;
  r.point_a = m_system.a.p;
  r.point_b = m_system.b.p;
  r.distance = signed_dist;
  r.on_edge = on_edge;
  // At contact, and so close that d's direction is its rounding and the tracker's residual (a
  // ball rolling on a plane read horizontal normals), the normal is a surface's: A's outward
  // one, else minus B's, from a side not held on a patch edge (its normal is not the pair's
  // direction there; at a pole, the normal's limit), turned so that b - a = distance * normal
  // keeps its sign. Held sides only at distance 0, where d gives no direction at all.
  r.normal.setZero();
  const double sa = m_a.size(), sb = m_b.size();
  const double small = sa > 0.0 && sb > 0.0 ? std::min(sa, sb) : std::max(sa, sb);
  if (std::abs(r.distance) <= 1e-6 * small) {
    const int na = m_a.dimension();
    Vec3 side_normal[2] = {Vec3::Zero(), Vec3::Zero()};
    if (na == 2)
      side_normal[0] = unit_normal(outward_direction(m_a, m_system.a, m_params.data(),
                                                     m_system.outward_a));
    if (m_b.dimension() == 2)
      side_normal[1] = -unit_normal(outward_direction(m_b, m_system.b, m_params.data() + na,
                                                      m_system.outward_b));
    const bool held[2] = {(on_edge & 3u) != 0u, ((on_edge >> na) & 3u) != 0u};
    for (int pass = 0; pass < (r.distance == 0.0 ? 2 : 1) && r.normal == Vec3::Zero(); ++pass)
      for (int side = 0; side < 2 && r.normal == Vec3::Zero(); ++side)
        if ((pass == 1 || !held[side]) && side_normal[side].allFinite())
          r.normal = side_normal[side];
    if (r.distance * r.normal.dot(r.point_b - r.point_a) < 0.0) r.normal = -r.normal;
  }
  if (r.normal == Vec3::Zero() && r.distance != 0.0)
    r.normal = (r.point_b - r.point_a) / r.distance;
  if (r.normal == Vec3::Zero() && m_a.dimension() + m_b.dimension() > 0) {
    // No normal yet: d = 0 and no surface normal (curves meeting, a bolt head's inner rim on its
    // hole's rim, both B-rep edges). A unit vector across both first tangents stands for it.
    const Vec3 ta = m_a.dimension() > 0 ? m_system.a.d[0] : Vec3::Zero();
    const Vec3 tb = m_b.dimension() > 0 ? m_system.b.d[0] : Vec3::Zero();
    Vec3 across = ta.cross(tb);
    if (!(across.squaredNorm() > 1e-20 * ta.squaredNorm() * tb.squaredNorm()) ||
        across == Vec3::Zero()) {
      const Vec3 t = ta != Vec3::Zero() ? ta : tb;
      int least = 0;  // the axis least along t
      t.cwiseAbs().minCoeff(&least);
      across = t.cross(Vec3::Unit(least));
    }
    if (across.allFinite() && across != Vec3::Zero()) r.normal = across.normalized();
  }
  r.projection_errors = m_system.projection;
  r.normalised_errors = normalised_projection_errors(m_system);
  r.normal_form = m_system.form != Formulation::Projection;
  r.alignment_error = r.reference_error = r.other_error = 0.0;
  if (r.normal_form) {
    // phi's rows on the side opposite the reference are n_R . t_j with n_R unit; a held
    // parameter keeps its residual, and a tangent that vanishes (a pole: its row is divided
    // by the distance to it) carries no condition.
    const int na = m_a.dimension(), n = m_system.size();
    const bool ref_a = m_system.form == Formulation::Normal_of_a;
    const int first = ref_a ? na : 0, last = ref_a ? n : na;
    for (int k = ref_a ? 0 : na; k < (ref_a ? na : n); ++k)
      r.reference_error = std::max(r.reference_error, std::abs(r.normalised_errors[k]));
    const Vec3 ab = m_system.b.p - m_system.a.p;
    const Vec3 normal = unit_normal(
        ref_a ? outward_direction(m_a, m_system.a, m_params.data(), m_system.outward_a)
              : outward_direction(m_b, m_system.b, m_params.data() + na, m_system.outward_b));
    for (int k = first; k < last; ++k) {
      const int other = first + (last - 1 - k);
      const double len2 = m_system.tangent_length2[k];
      if ((on_edge & (1u << k)) || !(len2 > 1e-16 * m_system.tangent_length2[other])) continue;
      r.alignment_error =
          std::max(r.alignment_error, std::abs(normal.dot(m_system.tangent(k))) / std::sqrt(len2));
      if (m_system.distance > 0.0)
        r.other_error = std::max(r.other_error, std::abs(ab.dot(m_system.tangent(k))) /
                                                    (m_system.distance * std::sqrt(len2)));
    }
  }
}

const Track_result& Extremal_tracker::evaluate(double t, const Rigid_pose_3& X_WA,
                                               const Rigid_pose_3& X_WB) {
  const unsigned on_edge = edge_mask(m_params);
  update_reference_at_pole(m_params);
  build_pair_system({&m_a, &X_WA, nullptr}, {&m_b, &X_WB, nullptr}, m_params, m_system, false,
                    choose_form(on_edge, m_params));
  fill_result(t, signed_distance(on_edge, m_params), on_edge);
  m_result.iterations = 0;
  m_result.status = Track_status::Tracking;
  m_result.degeneracy = Degeneracy::None;
  return m_result;
}

const Track_result& Extremal_tracker::step(double t, const Rigid_pose_3& X_WA,
                                           const Twist_3& V_A, const Rigid_pose_3& X_WB,
                                           const Twist_3& V_B, double dt) {
  EXTREMAL_PRECONDITION_MSG(dt > 0.0 && std::isfinite(dt), "dt = " << dt << " must be > 0");
  const int substeps = m_options.substeps;
  const double h = dt / substeps;
  Degeneracy degeneracy = Degeneracy::None;
  const int corrections = m_options.corrections > 0 ? correct(X_WA, X_WB, degeneracy) : 0;
  int solves = corrections;
  Vec4 x = m_params;
  bool result_on_edge = false;
  for (int s = 0; s < substeps; ++s) {
    // Poses at the start of the substep, from the twists (held constant over the step).
    const double tau = s * h;
    Vec4 k1;
    if (s == 0) {  // the given poses, read in place (no copies on the hot path)
      control(x, X_WA, &V_A, X_WB, &V_B, h, k1, degeneracy);
    } else {
      const Rigid_pose_3 A0 = advance(X_WA, V_A, tau), B0 = advance(X_WB, V_B, tau);
      control(x, A0, &V_A, B0, &V_B, h, k1, degeneracy);
    }
    ++solves;
    if (s == 0) {  // the pair at time t, before the parameters move
      fill_result(t, m_last_signed, m_last_on_edge);
      result_on_edge = m_last_on_edge != 0;
    }
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
      control(y, Ah, &V_A, Bh, &V_B, h, k2, degeneracy);
      y = x + 0.5 * h * k2;
      m_domain.clamp(y);
      control(y, Ah, &V_A, Bh, &V_B, h, k3, degeneracy);
      y = x + h * k3;
      m_domain.clamp(y);
      control(y, A1, &V_A, B1, &V_B, h, k4, degeneracy);
      solves += 3;
      x += (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
    if (!m_domain.strictly_inside(x)) {  // the usual step stays inside: nothing to do
      if (m_pole_lower | m_pole_upper) cross_poles(x);  // only pairs with poles cross them
      m_domain.clamp(x);
    }
    if (m_in_band && (m_pole_lower | m_pole_upper)) leave_poles(x);
  }
  m_params = x;
  m_result.degeneracy = degeneracy;
  m_result.status = degeneracy != Degeneracy::None ? Track_status::Singular_fallback
                    : result_on_edge                 ? Track_status::On_boundary
                                                     : Track_status::Tracking;
  m_result.iterations = solves;
  m_result.corrections = corrections;
  return m_result;
}

}  // namespace extremal
