#include "Convert.h"

#include <cmath>
#include <sstream>

namespace extremal::python {

const Distance_hierarchy& Py_body::hierarchy() const {
  std::call_once(m_hierarchy_once,
                 [this] { m_hierarchy = std::make_unique<Distance_hierarchy>(m_body); });
  return *m_hierarchy;
}

std::shared_ptr<const Tracking_model> Py_body::tracking_model() const {
  std::call_once(m_model_once, [this] { m_model = std::make_shared<const Tracking_model>(m_body); });
  return m_model;
}

namespace {

std::string shape_text(const py::array& a) {
  std::ostringstream os;
  os << "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) os << (i ? ", " : "") << a.shape(i);
  os << (a.ndim() == 1 ? ",)" : ")");
  return os.str();
}

}  // namespace

std::string number_text(double x) {
  std::ostringstream os;
  os << x;
  return os.str();
}

py::array_t<double, py::array::c_style> double_array(const py::handle& value,
                                                     const std::string& argument) {
  if (py::isinstance<py::str>(value) || py::isinstance<py::bytes>(value))
    throw Invalid_input(argument + ": expected numbers, got a string");
  auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
  if (!a) {
    PyErr_Clear();
    throw Invalid_input(argument + ": expected an array of numbers, got " +
                        std::string(py::str(py::type::handle_of(value).attr("__name__"))));
  }
  return a;
}

Rigid_pose_3 pose_from_numbers(const double* p, const std::string& argument) {
  for (int i = 0; i < 7; ++i)
    if (!std::isfinite(p[i])) {
      std::ostringstream os;
      os << argument << "[" << i << "]: not a finite number (" << p[i] << ")";
      throw Invalid_input(os.str());
    }
  try {
    return Rigid_pose_3::from_quaternion(Vec3(p[0], p[1], p[2]), p[3], p[4], p[5], p[6]);
  } catch (const Invalid_input& e) {
    throw Invalid_input(argument + ": " + e.what());
  }
}

Rigid_pose_3 pose_from(const py::handle& value, const std::string& argument) {
  if (value.is_none()) return Rigid_pose_3();
  const auto a = double_array(value, argument);
  if (a.ndim() != 1 || (a.size() != 3 && a.size() != 7))
    throw Invalid_input(argument + ": expected 3 numbers (x, y, z) or 7 (x, y, z, qw, qx, qy, " +
                        "qz), got shape " + shape_text(a));
  double p[7] = {0, 0, 0, 1, 0, 0, 0};
  for (py::ssize_t i = 0; i < a.size(); ++i) p[i] = a.data()[i];
  return pose_from_numbers(p, argument);
}

Twist_3 twist_from(const py::handle& value, const std::string& argument) {
  Twist_3 v;
  if (value.is_none()) return v;
  const auto a = double_array(value, argument);
  if (a.ndim() != 1 || a.size() != 6)
    throw Invalid_input(argument + ": expected 6 numbers (vx, vy, vz, wx, wy, wz), got shape " +
                        shape_text(a));
  for (int i = 0; i < 6; ++i)
    if (!std::isfinite(a.data()[i])) {
      std::ostringstream os;
      os << argument << "[" << i << "]: not a finite number (" << a.data()[i] << ")";
      throw Invalid_input(os.str());
    }
  v.linear = Vec3(a.data()[0], a.data()[1], a.data()[2]);
  v.angular = Vec3(a.data()[3], a.data()[4], a.data()[5]);
  return v;
}

void place_body(const Body& body, const Rigid_pose_3& X_WE, const Twist_3& V_E, Rigid_pose_3& X_WB,
                Twist_3& V_B) {
  X_WB = X_WE * body.placement;
  V_B.angular = V_E.angular;
  V_B.linear = V_E.linear + V_E.angular.cross(X_WB.translation() - X_WE.translation());
}

py::array_t<double> vec_array(const Vec3& v) {
  py::array_t<double> a(3);
  for (int i = 0; i < 3; ++i) a.mutable_data()[i] = v[i];
  return a;
}

py::array_t<double> pose_array(const Rigid_pose_3& X) {
  py::array_t<double> a(7);
  double* p = a.mutable_data();
  const Eigen::Quaterniond q = X.quaternion();
  const Vec3& t = X.translation();
  const double out[7] = {t.x(), t.y(), t.z(), q.w(), q.x(), q.y(), q.z()};
  for (int i = 0; i < 7; ++i) p[i] = out[i];
  return a;
}

std::vector<Body_ptr> bodies_from(const py::handle& value, const std::string& argument) {
  std::vector<Body_ptr> out;
  auto add = [&](const Body_ptr& b, const std::string& which) {
    if (b->body().is_empty())
      throw Invalid_input(which + ": body '" + b->body().name +
                          "' has no face, curve, point or triangle");
    out.push_back(b);
  };
  if (py::isinstance<Py_body>(value)) {
    add(value.cast<Body_ptr>(), argument);
    return out;
  }
  if (py::isinstance<Py_model>(value)) {
    // As `extremal distance` takes a file: all its bodies that hold anything.
    const Py_model& model = value.cast<const Py_model&>();
    for (const Body_ptr& b : model.bodies)
      if (!b->body().is_empty()) out.push_back(b);
    if (out.empty())
      throw Invalid_input(argument + " '" + model.info.file +
                          "': the file holds no body with a face, curve or triangle");
    return out;
  }
  if (py::isinstance<py::sequence>(value) && !py::isinstance<py::str>(value)) {
    const py::sequence s = value.cast<py::sequence>();
    for (std::size_t i = 0; i < s.size(); ++i) {
      const std::string which = argument + "[" + std::to_string(i) + "]";
      if (!py::isinstance<Py_body>(s[i])) throw Invalid_input(which + ": expected an extremal.Body");
      add(s[i].cast<Body_ptr>(), which);
    }
    if (out.empty()) throw Invalid_input(argument + ": an empty list of bodies");
    return out;
  }
  throw Invalid_input(argument + ": expected an extremal.Body, a Model or a list of bodies, got " +
                      std::string(py::str(py::type::handle_of(value).attr("__name__"))));
}

Body_ptr one_body(const py::handle& value, const std::string& argument) {
  if (py::isinstance<Py_model>(value) || py::isinstance<Py_body>(value)) {
    const std::vector<Body_ptr> bodies = bodies_from(value, argument);
    if (bodies.size() != 1)
      throw Invalid_input(argument + ": a Model of " + std::to_string(bodies.size()) +
                          " bodies; give one of them (model[k])");
    return bodies.front();
  }
  throw Invalid_input(argument + ": expected an extremal.Body (or a Model of one body), got " +
                      std::string(py::str(py::type::handle_of(value).attr("__name__"))));
}

}  // namespace extremal::python
