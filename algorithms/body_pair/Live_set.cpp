#include "algorithms/body_pair/internal/Live_set.h"

#include <algorithm>
#include <cmath>

#include "algorithms/body_pair/internal/Body_pair_support.h"
#include "algorithms/body_pair/internal/Reading_rules.h"
#include "algorithms/body_pair/internal/Tuning.h"
#include "algorithms/distance/Triangle_distance.h"

namespace extremal::internal {

namespace {

void triangle_corners(const Tracking_model& m, const Primitive& p, const Rigid_pose_3& X, Vec3 out[3]) {
  const auto& tri = m.body().mesh.triangles[p.index];
  for (int k = 0; k < 3; ++k) out[k] = X.apply_point(to_vec3(m.body().mesh.vertices[tri[k]]));
}

// Descent direction of |own - other|^2 / 2 along the parameters of a surface primitive at q.
void surface_descent(const Feature& f, const Rigid_pose_3& X, const double* q, const Vec3& other,
                     double g[2], double scale[2]) {
  Feature_point fp;
  evaluate_feature(f, X, q, fp, 1);
  const Vec3 d = fp.p - other;
  for (int k = 0; k < 2; ++k) {
    g[k] = -d.dot(fp.d[k]);
    scale[k] = d.norm() * fp.d[k].norm();
  }
}


}  // namespace

Live_set::Live_set(Pair_context& context) : m_context(context) {
  m_live.reserve(64);
  m_free.reserve(64);
}

int Live_set::add(int pa, int pb, const Vec4& params) {
  int k;
  if (!m_free.empty()) {
    k = m_free.back();
    m_free.pop_back();
  } else {
    k = static_cast<int>(m_live.size());
    m_live.emplace_back();
  }
  Live& L = m_live[k];
  const Primitive& A = m_context.model_a->primitives()[pa];
  const Primitive& B = m_context.model_b->primitives()[pb];
  L.pa = pa;
  L.pb = pb;
  L.alive = true;
  L.valid = false;
  L.stepped = -1;
  L.provenance = Provenance::Unreached;
  L.was_shallower = false;
  L.rejected_by = Reading_rule::None;
  L.closed_form = closed_form_pair(A, B);
  if (!L.closed_form)
    L.tracker = Extremal_tracker(A.feature, B.feature, params, m_context.options.tracker);
  ++m_generation;
  return k;
}

void Live_set::kill(int k) {
  m_live[k].alive = false;
  m_free.push_back(k);
  ++m_generation;
}

void Live_set::kill_all() {
  for (std::size_t k = 0; k < m_live.size(); ++k)
    if (m_live[k].alive) kill(static_cast<int>(k));
}

int Live_set::move(int pa, int pb, const Vec4& params) {
  int moved = -1;
  for (std::size_t k = 0; k < m_live.size(); ++k)
    if (m_live[k].alive && m_live[k].pa == pa && m_live[k].pb == pb && !m_live[k].closed_form &&
        (moved < 0 || (m_live[moved].valid && !m_live[k].valid)))
      moved = static_cast<int>(k);
  if (moved < 0) return -1;
  Live& L = m_live[moved];
  L.tracker.reset(params);
  L.stepped = -1;
  // (A tracker that came through contact keeps it in another basin of its pair.)
  if (L.provenance != Provenance::Through_contact) L.provenance = Provenance::Unreached;
  L.was_shallower = false;
  ++m_generation;
  return moved;
}

double Live_set::best() const {
  double best = HUGE_VAL;
  for (const Live& L : m_live)
    if (L.alive && L.valid) best = std::min(best, L.result.distance);
  return best;
}

bool Live_set::any_valid() const {
  return std::any_of(m_live.begin(), m_live.end(), [](const Live& L) { return L.alive && L.valid; });
}

int Live_set::count() const {
  return static_cast<int>(
      std::count_if(m_live.begin(), m_live.end(), [](const Live& L) { return L.alive; }));
}

void Live_set::step_pending() {
  for (std::size_t k = 0; k < m_live.size(); ++k) {
    if (!m_live[k].alive || m_live[k].stepped == m_context.now.steps) continue;
    step_live(static_cast<int>(k));
    for (int hop = 0; hop < 3 && transition(static_cast<int>(k)); ++hop) {
    }
  }
}

void Live_set::index() {
  m_keys.clear();
  for (std::size_t k = 0; k < m_live.size(); ++k)
    if (m_live[k].alive)
      m_keys.emplace_back(pair_key(m_live[k].pa, m_live[k].pb), static_cast<int>(k));
  std::sort(m_keys.begin(), m_keys.end());
}

bool is_converged_along_free(const Pair_context& context, const Live& L, double limit) {
  // Converged along every parameter not held on a domain bound (one held there keeps the
  // crease's projection error): a tracker lagging behind its minimum (no corrections, a low
  // gain) may sit above a point of its own pair, the crease among them.
  const Feature& fa = context.primitive(0, L.pa).feature;
  const Feature& fb = context.primitive(1, L.pb).feature;
  const int na = fa.dimension();
  for (int k = 0; k < na + fb.dimension(); ++k) {
    const Feature& f = k < na ? fa : fb;
    const int j = k < na ? k : k - na;
    const double q = L.result.params[k];
    if (!f.is_closed(j) && (q <= f.lower(j) || q >= f.upper(j))) continue;
    if (!(std::abs(L.result.normalised_errors[k]) <= limit)) return false;
  }
  return true;
}

bool descends_from_edge(const Feature& fa, const Feature& fb, const Track_result& r, double limit) {
  if (!r.on_edge || !(r.distance > 0.0)) return false;
  // d = f_A - f_B: the distance's derivative along A's parameter k has the sign of d . t_k,
  // along B's of -d . t_k. Held on a lower bound it must not be negative, on an upper one not
  // positive.
  const int na = fa.dimension();
  for (int k = 0; k < na + fb.dimension(); ++k) {
    if (!(r.on_edge & (1u << k))) continue;
    const Feature& f = k < na ? fa : fb;
    const int j = k < na ? k : k - na;
    const double slope = (k < na ? 1.0 : -1.0) * r.normalised_errors[k];
    const bool lower = r.params[k] - f.lower(j) < f.upper(j) - r.params[k];
    if (lower ? slope < -limit : slope > limit) return true;
  }
  return false;
}

bool at_constrained_minimum(const Pair_context& context, const Live& L, double limit) {
  return is_converged_along_free(context, L, limit) &&
         !descends_from_edge(context.primitive(0, L.pa).feature, context.primitive(1, L.pb).feature,
                             L.result, limit);
}

bool Live_set::tracks_converged(int pa, int pb) const {
  for (const Live& L : m_live)
    if (L.alive && L.valid && !L.closed_form && L.pa == pa && L.pb == pb &&
        at_minimum(L, k_converged_error))
      return true;
  return false;
}

void Live_set::step_live(int k) {
  Live& L = m_live[k];
  const bool first = L.stepped == -1;
  L.stepped = m_context.now.steps;
  const Tracking_model& MA = *m_context.model_a;
  const Tracking_model& MB = *m_context.model_b;
  const Primitive& A = MA.primitives()[L.pa];
  const Primitive& B = MB.primitives()[L.pb];
  if (L.closed_form) {
    Track_result& r = L.result;
    r.time = m_context.now.t;
    r.status = Track_status::Tracking;
    r.degeneracy = Degeneracy::None;
    r.params.setZero();
    r.iterations = 0;
    if (A.kind == Primitive_kind::Triangle && B.kind == Primitive_kind::Triangle) {
      Vec3 ta[3], tb[3];
      triangle_corners(MA, A, *m_context.now.X_WA, ta);
      triangle_corners(MB, B, *m_context.now.X_WB, tb);
      const Triangle_closest c = triangle_distance(ta, tb);
      r.distance = c.distance;
      r.point_a = c.point_a;
      r.point_b = c.point_b;
      r.params << c.uv_a[0], c.uv_a[1], c.uv_b[0], c.uv_b[1];
    } else {
      const bool tri_a = A.kind == Primitive_kind::Triangle;
      Vec3 t[3];
      triangle_corners(tri_a ? MA : MB, tri_a ? A : B, tri_a ? *m_context.now.X_WA : *m_context.now.X_WB, t);
      const Vec3 q = (tri_a ? *m_context.now.X_WB : *m_context.now.X_WA).translation();
      double uv[2];
      const Vec3 c = closest_on_triangle(q, t[0], t[1], t[2], uv);
      r.point_a = tri_a ? c : q;
      r.point_b = tri_a ? q : c;
      r.distance = (r.point_b - r.point_a).norm();
      r.params[0] = uv[0];
      r.params[1] = uv[1];
    }
    r.normal = r.distance > 0.0 ? Vec3((r.point_b - r.point_a) / r.distance) : Vec3::Zero();
    L.regime = regime_of(r.distance, m_context.options.contact_tolerance, false);
    L.valid = true;
    L.rejected_by = Reading_rule::None;
    return;
  }
  const Pair_context& c = m_context;
  L.result = L.tracker.step(c.now.t, *c.now.X_WA, *c.now.V_A, *c.now.X_WB, *c.now.V_B, c.now.dt);
  L.regime = regime_of(L.result.distance, c.options.contact_tolerance, L.result.normal_form);
  m_stats.corrections += L.result.corrections;
  const int cap = c.options.tracker.corrections;
  if (cap > 0 && L.result.corrections == cap) ++m_stats.capped_corrections;
  judge(L, first, m_context);
}

bool Live_set::transition(int k) {
  Live& L = m_live[k];
  if (L.closed_form || !L.alive) return false;
  const Track_result& r = L.result;
  // Only apart: inside, the tracked pair is a saddle of the distance and descent means nothing.
  if (!(r.distance > m_context.options.contact_tolerance)) return false;
  const int na = m_context.model_a->primitives()[L.pa].feature.dimension();
  for (int side = 0; side < 2; ++side) {
    const Tracking_model& M = side == 0 ? *m_context.model_a : *m_context.model_b;
    const int p = side == 0 ? L.pa : L.pb;
    const Primitive& P = M.primitives()[p];
    const double* q = r.params.data() + (side == 0 ? 0 : na);
    const Rigid_pose_3& X = side == 0 ? *m_context.now.X_WA : *m_context.now.X_WB;
    const Vec3& other = side == 0 ? r.point_b : r.point_a;
    int np = -1;
    double nq[2] = {0, 0};
    if (P.is_surface()) {
      const Nurbs_surface_3& S = *P.feature.surface();
      double g[2], scale[2];
      surface_descent(P.feature, X, q, other, g, scale);
      const double bound[4] = {S.u_min(), S.u_max(), S.v_min(), S.v_max()};
      // Sides the point sits on with the descent pointing out of the patch.
      int out_side = -1;
      for (int s = 0; s < 4; ++s) {
        const int dir = s / 2;
        if (q[dir] != bound[s]) continue;
        if (P.feature.collapsed_edges() & (1u << s)) continue;
        if (dir == 0 ? S.is_closed_u() : S.is_closed_v()) continue;
        const double outward = (s % 2 == 0) ? -g[dir] : g[dir];
        if (outward > k_descent * scale[dir]) out_side = s;
      }
      int link_count = 0;
      M.edges_of(p, link_count);
      if (link_count > 0 && (out_side >= 0 || !M.contains(p, q))) {
        // Off a trimmed face, a triangle or a face with B-rep edges: onto the nearest edge.
        Surface_point sp;
        S.evaluate(q[0], q[1], sp, 0);
        double t = 0.0;
        const Vec3 toward = X.inverse().apply_point(other);
        np = M.nearest_edge(p, sp.p, t, &toward);
        nq[0] = t;
      } else if (out_side >= 0 && P.side_neighbour[out_side] >= 0) {
        // Across a matched patch side, if the descent enters the neighbour.
        const int n = P.side_neighbour[out_side];
        const int ns = P.side_neighbour_side[out_side];
        double mq[2];
        if (M.map_across_side(p, out_side, q, mq)) {
          double gn[2], sn[2];
          surface_descent(M.primitives()[n].feature, X, mq, other, gn, sn);
          const int dir = ns / 2;
          const double inward = (ns % 2 == 0) ? gn[dir] : -gn[dir];
          if (inward > k_descent * sn[dir]) {
            np = n;
            nq[0] = mq[0];
            nq[1] = mq[1];
          }
        }
      }
    } else if (P.feature.dimension() == 1) {
      int count = 0;
      const Edge_on_face* faces = M.faces_of(p, count);
      const double t = q[0];
      for (int f = 0; f < count && np < 0; ++f) {
        const Edge_on_face& use = faces[f];
        const Primitive& F = M.primitives()[use.face];
        double uv[2], uv1[2], uv0[2];
        use.map(t, uv);
        const double h = k_edge_difference * (P.feature.upper(0) - P.feature.lower(0));
        use.map(t + h, uv1);
        use.map(t - h, uv0);
        // The edge's normal in the face's parameter plane, oriented into the face.
        double nrm[2] = {-(uv1[1] - uv0[1]), uv1[0] - uv0[0]};
        const double len = std::hypot(nrm[0], nrm[1]);
        if (!(len > 0.0)) continue;
        nrm[0] /= len;
        nrm[1] /= len;
        const Nurbs_surface_3& S = *F.feature.surface();
        const double band = F.trim ? F.trim->tolerance()
                                   : k_untrimmed_band * std::max(S.u_max() - S.u_min(), S.v_max() - S.v_min());
        const double eps = k_side_probe_bands * band;
        auto inside = [&](double s) {
          const double x[2] = {uv[0] + s * eps * nrm[0], uv[1] + s * eps * nrm[1]};
          return x[0] >= S.u_min() && x[0] <= S.u_max() && x[1] >= S.v_min() && x[1] <= S.v_max() &&
                 M.contains(use.face, x);
        };
        const bool plus = inside(1.0), minus = inside(-1.0);
        if (plus == minus) continue;  // cannot tell the face's side here
        if (!plus) nrm[0] = -nrm[0], nrm[1] = -nrm[1];
        double cq[2] = {std::clamp(uv[0], S.u_min(), S.u_max()), std::clamp(uv[1], S.v_min(), S.v_max())};
        double g[2], scale[2];
        surface_descent(F.feature, X, cq, other, g, scale);
        const double inward = g[0] * nrm[0] + g[1] * nrm[1];
        // Only onto a face that starts no farther than the edge: a B-rep edge lies on its faces
        // only up to the file's tolerance (screw.step: 1.8e-4 off at a ball 1 mm away), and a
        // face that starts above it may settle above it, where the edge's pair is lower. (A
        // face pair that does come closer is found as any other, by check_vacated.)
        Surface_point fp;
        S.evaluate(cq[0], cq[1], fp, 0);
        const double from_face = (X.apply_point(fp.p) - other).norm();
        const double slack = std::max(m_context.options.seeding.absolute_tolerance,
                                      m_context.options.seeding.relative_tolerance * r.distance);
        if (inward > k_descent * std::max(scale[0], scale[1]) && from_face <= r.distance + slack) {
          np = use.face;
          nq[0] = cq[0];
          nq[1] = cq[1];
        }
      }
    }
    if (np < 0) continue;
    // Just inside the new primitive's domain: a parameter held on a patch edge is left out of
    // the tracker's corrections, so a handed-over point must not start on one.
    {
      const Feature& f = M.primitives()[np].feature;
      for (int k = 0; k < f.dimension(); ++k) {
        if (f.is_closed(k)) continue;
        const double margin = k_handover_inset * (f.upper(k) - f.lower(k));
        nq[k] = std::clamp(nq[k], f.lower(k) + margin, f.upper(k) - margin);
      }
    }
    // Hand the tracker over: same other side, this side on the new primitive.
    const int npa = side == 0 ? np : L.pa;
    const int npb = side == 0 ? L.pb : np;
    const Feature& fa = m_context.model_a->primitives()[npa].feature;
    const Feature& fb = m_context.model_b->primitives()[npb].feature;
    Vec4 params = Vec4::Zero();
    if (side == 0) {
      for (int c = 0; c < fa.dimension(); ++c) params[c] = nq[c];
      for (int c = 0; c < fb.dimension(); ++c) params[fa.dimension() + c] = r.params[na + c];
    } else {
      for (int c = 0; c < fa.dimension(); ++c) params[c] = r.params[c];
      for (int c = 0; c < fb.dimension(); ++c) params[fa.dimension() + c] = nq[c];
    }
    L.pa = npa;
    L.pb = npb;
    L.tracker = Extremal_tracker(fa, fb, params, m_context.options.tracker);
    if (L.provenance != Provenance::Behind_sheet) L.provenance = Provenance::Unreached;
    L.was_shallower = false;
    ++m_stats.transitions;
    step_live(k);
    return true;
  }
  return false;
}

void Live_set::merge_duplicates() {
  const double tol = k_merge_distance * m_context.length();
  // Only trackers of one primitive pair can merge: compared within runs of equal keys, in slot
  // order (index_live sorts by key, then slot).
  index();
  for (std::size_t first = 0, last = 0; first < m_keys.size(); first = last) {
    last = first + 1;
    while (last < m_keys.size() && m_keys[last].first == m_keys[first].first) ++last;
    for (std::size_t a = first; a < last; ++a) {
      const std::size_t i = static_cast<std::size_t>(m_keys[a].second);
      if (!m_live[i].alive) continue;
      for (std::size_t b = a + 1; b < last; ++b) {
        const std::size_t j = static_cast<std::size_t>(m_keys[b].second);
        Live& x = m_live[i];
        Live& y = m_live[j];
        if (!y.alive) continue;
        if ((x.result.point_a - y.result.point_a).norm() +
                (x.result.point_b - y.result.point_b).norm() >
            tol)
          continue;
        if (!x.valid && y.valid) {  // keep the one that holds (a wandering seed does not)
          kill(static_cast<int>(i));
          ++m_stats.merges;
          break;
        }
        kill(static_cast<int>(j));
        ++m_stats.merges;
      }
    }
  }
}

}  // namespace extremal::internal
