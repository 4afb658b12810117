#include "algorithms/distance/Global_distance.h"

#include <memory>
#include <vector>

#include "algorithms/distance/internal/Distance_solver.h"
#include "kernel/Error.h"

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


namespace internal {

Distance_result extremal_distance(const Distance_hierarchy& A, const Rigid_pose_3& X_WA,
                                  const Distance_hierarchy& B, const Rigid_pose_3& X_WB,
                                  const Distance_request& request, const Proof_request& proof,
                                  Distance_workspace& workspace) {
  EXTREMAL_PRECONDITION_MSG(request.absolute_tolerance >= 0.0 && request.relative_tolerance >= 0.0 &&
                                (request.absolute_tolerance > 0.0 || request.relative_tolerance > 0.0),
                            "tolerances must be >= 0 and not both 0, got absolute "
                                << request.absolute_tolerance << ", relative "
                                << request.relative_tolerance);
  EXTREMAL_PRECONDITION_MSG(request.max_nodes > 0, "max_nodes must be > 0, got " << request.max_nodes);
  EXTREMAL_PRECONDITION_MSG(request.max_seconds >= 0.0,
                            "max_seconds must be >= 0, got " << request.max_seconds);
  Distance_solver solver(A, X_WA, B, X_WB, request, proof, workspace.scratch());
  return solver.run();
}

}  // namespace internal

Distance_result extremal_distance(const Distance_hierarchy& A, const Rigid_pose_3& X_WA,
                                  const Distance_hierarchy& B, const Rigid_pose_3& X_WB,
                                  const Distance_request& request, Distance_workspace& workspace) {
  return internal::extremal_distance(A, X_WA, B, X_WB, request, internal::Proof_request(),
                                     workspace);
}

namespace {
// Element a of A against element b of B, from their pieces or from `starts` (if not null).
Distance_result restricted_query(const Distance_hierarchy& A, const Rigid_pose_3& X_WA,
                                 int element_a, const Distance_hierarchy& B,
                                 const Rigid_pose_3& X_WB, int element_b,
                                 const std::vector<internal::Sub_patch_pair>* starts,
                                 const Distance_request& request,
                                 const internal::Proof_request& proof,
                                 Distance_workspace& workspace) {
  EXTREMAL_PRECONDITION_MSG(
      element_a >= 0 && element_a < static_cast<int>(A.elements().size()) && element_b >= 0 &&
          element_b < static_cast<int>(B.elements().size()),
      "no element pair (" << element_a << ", " << element_b << ") in '" << A.name() << "' and '"
                          << B.name() << "'");
  EXTREMAL_PRECONDITION_MSG(request.max_nodes > 0, "max_nodes must be > 0, got " << request.max_nodes);
  internal::Distance_solver solver(A, X_WA, B, X_WB, request, proof, workspace.scratch());
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
  return restricted_query(A, X_WA, element_a, B, X_WB, element_b, nullptr, request,
                          internal::Proof_request(), workspace);
}

namespace internal {

Distance_result extremal_distance_between(const Distance_hierarchy& A, const Rigid_pose_3& X_WA,
                                          int element_a, const Distance_hierarchy& B,
                                          const Rigid_pose_3& X_WB, int element_b,
                                          const Distance_request& request,
                                          const Proof_request& proof,
                                          Distance_workspace& workspace) {
  return restricted_query(A, X_WA, element_a, B, X_WB, element_b, nullptr, request, proof,
                          workspace);
}

Distance_result extremal_distance_between(const Distance_hierarchy& A, const Rigid_pose_3& X_WA,
                                          int element_a, const Distance_hierarchy& B,
                                          const Rigid_pose_3& X_WB, int element_b,
                                          const std::vector<Sub_patch_pair>& starts,
                                          const Distance_request& request,
                                          const Proof_request& proof,
                                          Distance_workspace& workspace) {
  return restricted_query(A, X_WA, element_a, B, X_WB, element_b, &starts, request, proof,
                          workspace);
}

std::optional<Parameter_box> stationary_region(const Distance_workspace& workspace) {
  for (const Convex_region& r : workspace.scratch().regions) {
    if (!r.given) continue;
    Parameter_box box;
    box.element_a = r.ea;
    box.element_b = r.eb;
    for (int k = 0; k < 4; ++k) {
      box.lo[k] = r.lo[k];
      box.hi[k] = r.hi[k];
    }
    return box;
  }
  return std::nullopt;
}

std::optional<double> convex_region_lower(const Distance_hierarchy& A, const Rigid_pose_3& X_WA,
                                          const Distance_hierarchy& B, const Rigid_pose_3& X_WB,
                                          const Parameter_box& box, const std::array<double, 4>& x,
                                          Distance_workspace& workspace) {
  const Distance_request request;
  const Proof_request proof;
  Distance_solver solver(A, X_WA, B, X_WB, request, proof, workspace.scratch());
  return solver.convex_region_lower(box, Vec4(x[0], x[1], x[2], x[3]));
}

}  // namespace internal

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