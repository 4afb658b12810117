// What every part of the Python module shares: the bodies as Python holds them, and the
// conversions between NumPy arrays and poses, twists and vectors.
//
// Conventions (as the scene files and `extremal distance`): a pose is 7 numbers x, y, z, qw, qx,
// qy, qz (the body frame's placement in the world, unit quaternion w first; 3 numbers x, y, z
// leave it unturned), a twist 6 numbers vx, vy, vz, wx, wy, wz (the world-frame velocity of the
// frame's origin and the world-frame angular velocity). Every bad value throws Invalid_input
// naming the argument, which Python sees as extremal.InvalidInput.
#pragma once

#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "Extremal.h"

namespace extremal::python {

namespace py = pybind11;

// A body as Python holds it (shared, never changed once made), with the prepared forms the
// queries need, each made on first use and safe to ask for from several threads at once.
class Py_body {
 public:
  explicit Py_body(Body body) : m_body(std::move(body)) {}
  const Body& body() const { return m_body; }
  // The certified solver's hierarchy (throws Invalid_input for a body with nothing to measure).
  const Distance_hierarchy& hierarchy() const;
  // The tracker's model, shared by every tracker of this body.
  std::shared_ptr<const Tracking_model> tracking_model() const;

 private:
  Body m_body;
  mutable std::once_flag m_hierarchy_once, m_model_once;
  mutable std::unique_ptr<Distance_hierarchy> m_hierarchy;
  mutable std::shared_ptr<const Tracking_model> m_model;
};
using Body_ptr = std::shared_ptr<Py_body>;  // Python holds these; nothing changes them

// A file as read_model reads it: its bodies and what it says about itself.
struct Py_model {
  io::Model info;  // everything but the bodies
  std::vector<Body_ptr> bodies;
};

// A pose from None (the identity), 3 or 7 numbers; `argument` names it in errors.
Rigid_pose_3 pose_from(const py::handle& value, const std::string& argument);
// A twist from None (at rest) or 6 numbers.
Twist_3 twist_from(const py::handle& value, const std::string& argument);
// A pose from 7 doubles (x, y, z, qw, qx, qy, qz); throws Invalid_input naming `argument` for a
// value that is not finite or a zero quaternion.
Rigid_pose_3 pose_from_numbers(const double* p, const std::string& argument);
// The pose and twist of a body's own frame when its file frame is at X_WE moving with V_E: the
// body sits at X_WE * placement, its origin moving at v + w x (origin - file origin), as
// Scene_stepper places scene bodies.
void place_body(const Body& body, const Rigid_pose_3& X_WE, const Twist_3& V_E, Rigid_pose_3& X_WB,
                Twist_3& V_B);

// A number as messages show it (shortest form: 0.5, 1e-09, inf).
std::string number_text(double x);

// A C-contiguous float64 array from any array-like (lists, tuples, arrays of other types), or an
// Invalid_input naming `argument`.
py::array_t<double, py::array::c_style> double_array(const py::handle& value,
                                                     const std::string& argument);

py::array_t<double> vec_array(const Vec3& v);
py::array_t<double> pose_array(const Rigid_pose_3& X);  // x, y, z, qw, qx, qy, qz

// A NumPy array that takes over `data` (no copy), of the given shape.
template <class T>
py::array_t<T> take_array(std::vector<T>&& data, std::vector<py::ssize_t> shape) {
  auto* owned = new std::vector<T>(std::move(data));
  py::capsule free_when_done(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>(shape, owned->data(), free_when_done);
}

// The bodies a distance argument stands for: a Body, a Model (all its bodies, as `extremal
// distance` takes a file) or a sequence of Body.
std::vector<Body_ptr> bodies_from(const py::handle& value, const std::string& argument);
// One body: a Body, or a Model that holds one.
Body_ptr one_body(const py::handle& value, const std::string& argument);

// The module's parts (Module.cpp calls them in this order).
void bind_bodies(py::module_& m);
void bind_distance(py::module_& m);
void bind_tracker(py::module_& m);
void bind_report(py::module_& m);

}  // namespace extremal::python
