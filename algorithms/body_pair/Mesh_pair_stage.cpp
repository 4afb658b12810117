#include "algorithms/body_pair/internal/Mesh_pair_stage.h"

#include <algorithm>
#include <cmath>

#include "algorithms/body_pair/internal/Body_pair_support.h"
#include "algorithms/distance/Penetration_depth.h"
#include "algorithms/mesh/internal/Mesh_tuning.h"

namespace extremal::internal {

namespace {

// A side this engine takes: a mesh without faces or curves, or a point.
bool mesh_or_point(const Tracking_model& m) {
  const Body& b = m.body();
  return b.is_point || (m.mesh() && b.faces.empty() && b.curves.empty());
}

}  // namespace

bool Mesh_pair_stage::takes(const Tracking_model& a, const Tracking_model& b) {
  return mesh_or_point(a) && mesh_or_point(b) && (a.mesh() || b.mesh());
}

Mesh_pair_stage::Mesh_pair_stage(std::shared_ptr<const Tracking_model> a,
                                 std::shared_ptr<const Tracking_model> b,
                                 const Body_pair_options& options)
    : m_models{std::move(a), std::move(b)}, m_a(*m_models[0]), m_b(*m_models[1]),
      m_options(options), m_swapped(!m_a.mesh()), m_mesh(m_a.mesh() ? *m_a.mesh() : *m_b.mesh()),
      m_other(m_a.mesh() ? m_b.mesh() : nullptr), m_front(m_mesh, m_other) {}

void Mesh_pair_stage::add_statistics(Pair_statistics& s) const {
  const Mesh_front_statistics& f = m_front.statistics();
  s.front_opened += f.opened;
  s.front_box_bounds += f.box_bounds;
  s.front_triangle_pairs += f.triangle_pairs;
  s.front_traversals += f.traversals;
  s.trackers = 1;
  s.candidates = static_cast<int>(m_front.size());
}

bool Mesh_pair_stage::nested(const Rigid_pose_3& X_MO, const Mesh_closest& c) const {
  if (!m_other) {  // the point, inside the closed mesh by its closest feature's pseudo-normal
    if (!m_mesh.closed() || c.triangle_a < 0) return false;
    const Vec3* t = m_mesh.triangle(c.triangle_a);
    Mesh_point closest = closest_on_triangle_feature(X_MO.translation(), t[0], t[1], t[2]);
    closest.triangle = c.triangle_a;
    return m_mesh.inside(X_MO.translation(), closest);
  }
  if (!m_mesh.closed() && !m_other->closed()) return false;
  // Surfaces apart: each surface lies wholly inside or outside the other body, so one vertex
  // of each decides, and only while the boxes overlap (tests
  // MeshPairs.ABallInsideAClosedMeshIsNestedAndReadsTheHullsDepth,
  // Overlap.AnOpenMeshInAClosedMeshReadsTheHullsDepth).
  const Bbox_3 other_in_m = transformed(m_other->box(), X_MO);
  if (box_distance(m_mesh.box(), other_in_m) > 0.0) return false;
  if (m_mesh.closed() && m_mesh.inside(X_MO.apply_point(m_other->corners(0)[0]))) return true;
  return m_other->closed() && m_other->inside(X_MO.inverse().apply_point(m_mesh.corners(0)[0]));
}

void Mesh_pair_stage::read_depth(const Rigid_pose_3& X_WA, const Rigid_pose_3& X_WB,
                                 const Vec3& entry_side) {
  Pair_answer& r = m_answer;
  Signed_distance_result h =
      hull_signed_distance(m_a.hierarchy(), X_WA, m_b.hierarchy(), X_WB, m_options.overlap);
  keep_entry_side(m_a.hierarchy(), X_WA, m_b.hierarchy(), X_WB, entry_side, m_options.overlap, h);
  if (!(h.distance < -m_options.contact_tolerance)) return;  // the hulls barely meet: contact
  r.distance = h.distance;
  r.point_a = h.point_a;
  r.point_b = h.point_b;
  r.normal = h.normal;
  // A mesh body's triangles are its hierarchy's faces (it has no others), a point is 0.
  r.feature_a = h.kind_a == Element_kind::Face ? h.element_a : 0;
  r.feature_b = h.kind_b == Element_kind::Face ? h.element_b : 0;
  r.params.setZero();
  int k = 0;
  if (m_a.mesh()) r.params[k++] = h.params_a[0], r.params[k++] = h.params_a[1];
  if (m_b.mesh()) r.params[k++] = h.params_b[0], r.params[k++] = h.params_b[1];
}

const Pair_answer& Mesh_pair_stage::step(const Pair_step& step) {
  const Rigid_pose_3& X_WA = step.X_WA;
  const Rigid_pose_3& X_WB = step.X_WB;
  Pair_answer& r = m_answer;
  const Rigid_pose_3& X_WM = m_swapped ? X_WB : X_WA;
  const Rigid_pose_3& X_WO = m_swapped ? X_WA : X_WB;
  const Rigid_pose_3 X_MO = X_WM.inverse() * X_WO;
  double closer = 0.0;
  if (m_started) {
    const Tracking_model& M = m_swapped ? m_b : m_a;
    const Tracking_model& O = m_swapped ? m_a : m_b;
    closer = approach_bound(M.box(), O.box(), m_last, X_MO).closer;
  } else {
    m_front.reset();
  }
  m_started = true;
  m_last = X_MO;
  const double last = std::abs(m_front.closest().distance);
  const double tolerance = std::min(k_front_relative_tolerance * last, step.budget.at(last));
  const Mesh_closest& c = m_front.update(X_MO, closer, std::isfinite(tolerance) ? tolerance : 0.0);

  // The surfaces' closest pair, in the world; A's witness first.
  const Vec3 on_m = X_WM.apply_point(c.point_a), on_o = X_WM.apply_point(c.point_b);
  r.distance = c.distance;
  r.point_a = m_swapped ? on_o : on_m;
  r.point_b = m_swapped ? on_m : on_o;
  // A point's feature is 0 and its witness has no parameters (swapped: A is the point).
  r.feature_a = m_swapped ? 0 : c.triangle_a;
  r.feature_b = m_swapped ? c.triangle_a : (m_other ? c.triangle_b : 0);
  r.params << c.uv_a[0], c.uv_a[1], m_other ? c.uv_b[0] : 0.0, m_other ? c.uv_b[1] : 0.0;
  r.edge_a = r.edge_b = -1;
  r.degeneracy = Degeneracy::None;
  r.shape = Reading_shape::Interior;
  r.source = Reading_source::Tracked;
  r.rejected_by = Reading_rule::None;

  const double tol = m_options.contact_tolerance;
  if (!m_other && c.distance > 0.0 && nested(X_MO, c)) r.distance = -c.distance;
  // point_b - point_a = distance * normal, inside as apart.
  r.normal = r.distance != 0.0 ? Vec3((r.point_b - r.point_a) / r.distance) : Vec3::Zero();
  // A closed mesh against another or an open one: the hulls' depth where the surfaces meet
  // or one lies inside the other. Against an open one (a sheet), the side entered by while
  // they meet and the side it is on while apart; one inside has no side (tests
  // Overlap.AClosedMeshThroughAnOpenMeshKeepsItsEntrySidesDepthWhileTheSurfacesMeet,
  // Overlap.AnOpenMeshInAClosedMeshReadsTheHullsDepth).
  if (m_other && (m_mesh.closed() || m_other->closed())) {
    const bool sheet = !(m_mesh.closed() && m_other->closed());
    if (!(c.distance > tol)) {
      read_depth(X_WA, X_WB, m_entry_side);
    } else if (nested(X_MO, c)) {
      m_entry_side = Vec3::Zero();
      read_depth(X_WA, X_WB, m_entry_side);
    } else if (sheet) {
      m_entry_side = X_WA.rotation().transpose() * r.normal;
    }
  }
  // Apart: the front's certified bound (the least decayed key of its entries).
  r.lower_bound = c.lower_bound;
  return r;
}

}  // namespace extremal::internal
