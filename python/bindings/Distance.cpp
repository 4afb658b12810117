// extremal.distance: the certified one-shot distance of `extremal distance`, plain or signed.
#include <array>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "Convert.h"

namespace extremal::python {

namespace {

struct Py_element {
  std::string kind;  // "face", "curve", "point"
  int index = -1;
  std::array<double, 2> params{{0.0, 0.0}};
};

struct Py_distance_result {
  double distance = 0.0, lower_bound = 0.0, upper_bound = 0.0;
  Vec3 point_a = Vec3::Zero(), point_b = Vec3::Zero(), normal = Vec3::Zero();
  int face_a = -1, face_b = -1;
  std::string status;
  bool certified = false;
  std::optional<std::string> body_a, body_b;
  Py_element element_a, element_b;
  double tolerance = 0.0;
  bool is_signed = false;
  // Signed queries only.
  std::optional<std::string> overlap, depth;
  std::optional<bool> closed_a, closed_b;
  std::optional<std::string> closed_a_reason, closed_b_reason;
};

// The result's common fields, from either kind of result (the same names on both).
template <class Result>
Py_distance_result common(const Result& r, const std::vector<Placed_body>& A, int body_a,
                          const std::vector<Placed_body>& B, int body_b, double tolerance) {
  Py_distance_result out;
  out.distance = r.distance;
  out.lower_bound = r.lower_bound;
  out.upper_bound = r.upper_bound;
  out.point_a = r.point_a;
  out.point_b = r.point_b;
  out.normal = r.normal;
  out.face_a = r.face_a;
  out.face_b = r.face_b;
  out.status = to_string(r.status);
  out.certified = r.is_certified();
  if (body_a >= 0) out.body_a = A[static_cast<std::size_t>(body_a)].body->name;
  if (body_b >= 0) out.body_b = B[static_cast<std::size_t>(body_b)].body->name;
  out.element_a = {to_string(r.kind_a), r.element_a, r.params_a};
  out.element_b = {to_string(r.kind_b), r.element_b, r.params_b};
  out.tolerance = tolerance;
  return out;
}

// The whole query's time, as `extremal distance`: a set of many bodies gets this in all.
constexpr double k_default_seconds = 60.0;

Py_distance_result distance_py(const py::handle& a, const py::handle& b, const py::handle& pose_a,
                               const py::handle& pose_b, double tolerance, bool signed_distance,
                               std::optional<int> max_cells, double max_seconds) {
  if (!(std::isfinite(tolerance) && tolerance > 0.0)) {
    std::ostringstream os;
    os << "tolerance: must be finite and > 0, got " << tolerance;
    throw Invalid_input(os.str());
  }
  if (max_cells && *max_cells < 1)
    throw Invalid_input("max_cells: must be at least 1, got " + std::to_string(*max_cells));
  if (max_cells && !signed_distance) throw Invalid_input("max_cells: only with signed=True");
  if (!(max_seconds >= 0.0)) throw Invalid_input("max_seconds: must be >= 0 (0: no limit)");
  const std::vector<Body_ptr> bodies_a = bodies_from(a, "a");
  const std::vector<Body_ptr> bodies_b = bodies_from(b, "b");
  const Rigid_pose_3 X_WA = pose_from(pose_a, "pose_a");
  const Rigid_pose_3 X_WB = pose_from(pose_b, "pose_b");

  py::gil_scoped_release release;
  // Each body placed by the argument's pose after its placement in its file.
  std::vector<Placed_body> set_a, set_b;
  auto place = [](const std::vector<Body_ptr>& bodies, const Rigid_pose_3& X, const char* which,
                  std::vector<Placed_body>& set) {
    for (const Body_ptr& p : bodies) {
      try {
        set.push_back({&p->body(), &p->hierarchy(), X * p->body().placement});
      } catch (const Invalid_input& e) {
        throw Invalid_input(std::string(which) + ": body '" + p->body().name + "': " + e.what());
      }
    }
  };
  place(bodies_a, X_WA, "a", set_a);
  place(bodies_b, X_WB, "b", set_b);

  if (signed_distance) {
    Signed_distance_request request;
    request.absolute_tolerance = tolerance;
    request.relative_tolerance = 0.0;
    if (max_cells) request.max_cells = *max_cells;
    const Signed_set_distance_result set = signed_set_distance(set_a, set_b, request, max_seconds);
    const Signed_distance_result& r = set.result;
    Py_distance_result out = common(r, set_a, set.body_a, set_b, set.body_b, tolerance);
    out.is_signed = true;
    out.overlap = to_string(r.overlap);
    if (r.overlap != Overlap_kind::None)
      out.depth = r.depth_is_translation_distance ? "translation" : "hull";
    out.closed_a = r.closed_a.closed;
    out.closed_a_reason = r.closed_a.reason;
    out.closed_b = r.closed_b.closed;
    out.closed_b_reason = r.closed_b.reason;
    return out;
  }
  Distance_request request;
  request.absolute_tolerance = tolerance;
  request.relative_tolerance = 0.0;
  Distance_workspace workspace;
  const Set_distance_result set = set_distance(set_a, set_b, request, workspace, max_seconds);
  return common(set.result, set_a, set.body_a, set_b, set.body_b, tolerance);
}

}  // namespace

void bind_distance(py::module_& m) {
  py::class_<Py_distance_result>(m, "DistanceResult", R"doc(
A certified distance: lower_bound <= the true distance <= upper_bound, `distance` within the
tolerance of it. point_a, point_b (world) are the witnesses, `normal` the unit vector from A to B
(point_b - point_a = distance * normal apart), face_a, face_b their faces (-1 when a witness is
on a curve or is a point). `status` as `extremal distance --json` says it ('converged',
'intersecting', 'touching', 'budget_exhausted', 'resolution_limit'; signed: also 'penetrating',
'containment_unknown'); `certified` unless the budget ran out or the resolution was reached.
)doc")
      .def_readonly("distance", &Py_distance_result::distance)
      .def_readonly("lower_bound", &Py_distance_result::lower_bound)
      .def_readonly("upper_bound", &Py_distance_result::upper_bound)
      .def_property_readonly("point_a", [](const Py_distance_result& r) { return vec_array(r.point_a); })
      .def_property_readonly("point_b", [](const Py_distance_result& r) { return vec_array(r.point_b); })
      .def_property_readonly("normal", [](const Py_distance_result& r) { return vec_array(r.normal); })
      .def_readonly("face_a", &Py_distance_result::face_a)
      .def_readonly("face_b", &Py_distance_result::face_b)
      .def_readonly("status", &Py_distance_result::status)
      .def_readonly("certified", &Py_distance_result::certified)
      .def_readonly("body_a", &Py_distance_result::body_a,
                    "Name of the body of A the witness lies on (None without a witness).")
      .def_readonly("body_b", &Py_distance_result::body_b)
      .def_property_readonly(
          "element_a",
          [](const Py_distance_result& r) {
            return py::dict(py::arg("kind") = r.element_a.kind, py::arg("index") = r.element_a.index,
                            py::arg("params") = r.element_a.params);
          },
          "The witness's element on A: {kind: 'face' | 'curve' | 'point', index, params}.")
      .def_property_readonly("element_b", [](const Py_distance_result& r) {
        return py::dict(py::arg("kind") = r.element_b.kind, py::arg("index") = r.element_b.index,
                        py::arg("params") = r.element_b.params);
      })
      .def_readonly("tolerance", &Py_distance_result::tolerance)
      .def_readonly("signed", &Py_distance_result::is_signed)
      .def_readonly("overlap", &Py_distance_result::overlap,
                    "Signed only: 'none', 'surfaces_meet', 'a_inside_b' or 'b_inside_a'.")
      .def_readonly("depth", &Py_distance_result::depth,
                    "Signed and overlapping only: 'translation' (both bodies certified convex: "
                    "-distance is the minimum translation distance) or 'hull' (the convex "
                    "hulls' depth, an upper bound on it); None otherwise.")
      .def_readonly("closed_a", &Py_distance_result::closed_a,
                    "Signed only: whether A is a closed body (only a closed body contains anything).")
      .def_readonly("closed_a_reason", &Py_distance_result::closed_a_reason)
      .def_readonly("closed_b", &Py_distance_result::closed_b)
      .def_readonly("closed_b_reason", &Py_distance_result::closed_b_reason)
      .def("__repr__", [](const Py_distance_result& r) {
        std::ostringstream os;
        os.precision(17);
        os << "<extremal.DistanceResult " << r.distance << " (" << r.status << ": "
           << r.lower_bound << " <= d <= " << r.upper_bound << ")>";
        return os.str();
      });

  m.def("distance", &distance_py, py::arg("a"), py::arg("b"), py::arg("pose_a") = py::none(),
        py::arg("pose_b") = py::none(), py::arg("tolerance") = 1e-9, py::arg("signed") = false,
        py::arg("max_cells") = py::none(), py::arg("max_seconds") = k_default_seconds, R"doc(
The certified extremal distance between a and b, as `extremal distance` computes it.

a, b: a Body, a Model (all its bodies, as the command takes a file) or a list of bodies; a set
of several bodies gives the smallest distance over its body pairs, nearest boxes first, and
body_a, body_b name the pair's bodies. pose_a, pose_b: None (identity), (x, y, z) or (x, y, z,
qw, qx, qy, qz), the frame of the file (or shape) in the world; each body sits at pose times its
placement in the file. tolerance: absolute, in the bodies' unit (upper - lower within it).

signed=False: bodies that meet report 0 (status 'intersecting' or 'touching'). signed=True: the
signed distance, negative while the bodies overlap (the penetration depth; docs/cli.md,
"--signed"), with a certificate; max_cells bounds its direction cells (default
200000). max_seconds: the whole query's wall time (0: no limit), then the bounds so far.

Raises extremal.InvalidInput naming the argument for a bad body, pose or value. The GIL is
released while it computes: threads may measure at once (also the same bodies).
)doc");
}

}  // namespace extremal::python
