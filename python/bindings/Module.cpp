// The extremal module's C++ part, extremal._core (python/extremal/__init__.py re-exports it).
#include "Convert.h"

PYBIND11_MODULE(_core, m) {
  namespace py = pybind11;
  m.doc() = "Extremal's C++ library: bodies, certified distances, trackers, scene reports.";
  m.attr("__version__") = EXTREMAL_VERSION;
  // Bad input (a file, a scene's key, an argument): the message names it, as the command's do.
  py::register_exception<extremal::Invalid_input>(m, "InvalidInput", PyExc_ValueError);
  // API misuse the library checks (a precondition): a bug, not bad input.
  py::register_exception<extremal::Precondition_violation>(m, "PreconditionViolation",
                                                            PyExc_RuntimeError);
  extremal::python::bind_bodies(m);
  extremal::python::bind_distance(m);
  extremal::python::bind_tracker(m);
  extremal::python::bind_report(m);
}
