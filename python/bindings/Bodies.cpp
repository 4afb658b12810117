// extremal.Body, extremal.Model, read_model and the shapes.
#include <string>

#include <pybind11/stl.h>

#include "Convert.h"

namespace extremal::python {

namespace {

// A path argument: str or os.PathLike.
std::string path_text(const py::handle& path, const char* argument) {
  try {
    return py::str(py::module_::import("os").attr("fspath")(path)).cast<std::string>();
  } catch (const py::error_already_set&) {
    throw Invalid_input(std::string(argument) + ": expected a path (str or os.PathLike), got " +
                        std::string(py::str(py::type::handle_of(path).attr("__name__"))));
  }
}

std::string unit_argument(const std::string& unit, const char* argument) {
  if (io::unit_in_millimetres(unit) <= 0.0)
    throw Invalid_input(std::string(argument) + ": unknown unit '" + unit + "'");
  return unit;
}

Py_model read_model_py(const py::object& path_object, const std::string& units,
                       const std::string& file_units, double trim_tolerance) {
  const std::string path = path_text(path_object, "path");
  io::Read_options options;
  options.scene_unit = unit_argument(units, "units");
  options.unitless_file_unit = unit_argument(file_units, "file_units");
  if (!(trim_tolerance > 0.0 && trim_tolerance < 1.0))
    throw Invalid_input("trim_tolerance: must be > 0 and < 1, got " + number_text(trim_tolerance));
  options.trim_tolerance = trim_tolerance;
  Py_model out;
  {
    py::gil_scoped_release release;
    try {
      out.info = io::read_model(path, options);
    } catch (const Invalid_input&) {
      throw;
    } catch (const std::exception& e) {  // a reader's own failure, as `extremal distance` says it
      throw Invalid_input(path + ": cannot read: " + e.what());
    }
    for (Body& b : out.info.bodies) out.bodies.push_back(std::make_shared<Py_body>(std::move(b)));
    out.info.bodies.clear();
  }
  return out;
}

// A shape body, the kernel's message (which names the size) prefixed with the function.
template <class Make>
Body_ptr shape(const char* function, Make make) {
  try {
    return std::make_shared<Py_body>(make());
  } catch (const Invalid_input& e) {
    throw Invalid_input(std::string("extremal.") + function + ": " + e.what());
  }
}

py::array_t<double> bbox_array(const Bbox_3& b) {
  py::array_t<double> a({2, 3});
  double* p = a.mutable_data();
  for (int i = 0; i < 3; ++i) {
    p[i] = b.min(i);
    p[3 + i] = b.max(i);
  }
  return a;
}

}  // namespace

void bind_bodies(py::module_& m) {
  py::class_<Py_body, Body_ptr>(m, "Body", R"doc(
A rigid body: the NURBS faces, curves, point or triangles that bound it, in its own frame.

Made by read_model (one per solid of a file) or by the shapes (sphere, ellipsoid, torus,
cylinder, plane, point). A body never changes once made; the prepared forms the queries need
are made on first use and shared by every query and tracker of the body (from any thread).
)doc")
      .def_property_readonly("name", [](const Py_body& b) { return b.body().name; },
                             "The body's name (unique among the bodies of its file).")
      .def_property_readonly("source_name", [](const Py_body& b) { return b.body().source_name; },
                             "The name the file gives it (product or instance name).")
      .def_property_readonly("is_point", [](const Py_body& b) { return b.body().is_point; },
                             "A point body: just its origin (a probe, a tool tip).")
      .def_property_readonly("face_count",
                             [](const Py_body& b) { return b.body().faces.size(); })
      .def_property_readonly("curve_count",
                             [](const Py_body& b) { return b.body().curves.size(); })
      .def_property_readonly("edge_count", [](const Py_body& b) { return b.body().edges.size(); },
                             "B-rep edges (imported CAD bodies).")
      .def_property_readonly("triangle_count",
                             [](const Py_body& b) { return b.body().mesh.triangles.size(); },
                             "Triangles of a mesh body.")
      .def_property_readonly(
          "face_kinds",
          [](const Py_body& b) {
            std::vector<std::string> k;
            for (const Face& f : b.body().faces) k.push_back(f.kind);
            return k;
          },
          "The kind of surface each face came from ('sphere', 'plane', 'bspline', ...), in face "
          "order (the face indices of distances and reports).")
      .def_property_readonly(
          "placement", [](const Py_body& b) { return pose_array(b.body().placement); },
          "Where the file places the body's frame: x, y, z, qw, qx, qy, qz. Poses given to "
          "distance and the trackers place the file's frame; the body sits at pose * placement.")
      .def(
          "bbox",
          [](const Py_body& b) {
            Bbox_3 box;
            {
              py::gil_scoped_release release;
              box = b.body().trimmed_bbox();
            }
            return bbox_array(box);
          },
          "The tight box of the trimmed body in its own frame: [[xmin, ymin, zmin], [xmax, ymax, "
          "zmax]].")
      .def("__repr__", [](const Py_body& b) {
        const Body& body = b.body();
        std::string what = body.is_point ? "a point"
                           : !body.mesh.empty()
                               ? std::to_string(body.mesh.triangles.size()) + " triangles"
                               : std::to_string(body.faces.size()) + " faces";
        if (!body.curves.empty()) what += ", " + std::to_string(body.curves.size()) + " curves";
        return "<extremal.Body '" + body.name + "': " + what + ">";
      });

  py::class_<Py_model>(m, "Model", R"doc(
A CAD or mesh file as read_model reads it: its bodies (one per solid) and what the reader says
about the file. Iterating, len() and indexing go over the bodies.
)doc")
      .def_property_readonly("file", [](const Py_model& x) { return x.info.file; })
      .def_property_readonly("format", [](const Py_model& x) { return x.info.format_name; },
                             "e.g. 'STEP AP214', 'IGES', 'OBJ free-form', 'STL (assimp)'.")
      .def_property_readonly("file_unit", [](const Py_model& x) { return x.info.file_unit; },
                             "The unit the file declares, or the one assumed (file_units).")
      .def_property_readonly("unit", [](const Py_model& x) { return x.info.unit; },
                             "The unit the bodies' lengths are in (units).")
      .def_property_readonly("scale_to_unit", [](const Py_model& x) { return x.info.scale_to_unit; })
      .def_property_readonly("bodies", [](const Py_model& x) { return x.bodies; })
      .def_property_readonly(
          "skipped",
          [](const Py_model& x) {
            py::list out;
            for (const auto& s : x.info.skipped)
              out.append(py::dict(py::arg("entity") = s.entity, py::arg("reason") = s.reason,
                                  py::arg("action") = s.action));
            return out;
          },
          "Entities not in the model (or only partly): dicts {entity, reason, action}.")
      .def_property_readonly("warnings", [](const Py_model& x) { return x.info.warnings; })
      .def("__len__", [](const Py_model& x) { return x.bodies.size(); })
      .def("__getitem__",
           [](const Py_model& x, py::ssize_t i) {
             const auto n = static_cast<py::ssize_t>(x.bodies.size());
             if (i < 0) i += n;
             if (i < 0 || i >= n) throw py::index_error("body index out of range");
             return x.bodies[static_cast<std::size_t>(i)];
           })
      .def("__iter__",
           [](const Py_model& x) { return py::make_iterator(x.bodies.begin(), x.bodies.end()); },
           py::keep_alive<0, 1>())
      .def("__repr__", [](const Py_model& x) {
        return "<extremal.Model '" + x.info.file + "': " + x.info.format_name + ", " +
               std::to_string(x.bodies.size()) + " bodies in " + x.info.unit + ">";
      });

  m.def("read_model", &read_model_py, py::arg("path"), py::arg("units") = "mm",
        py::arg("file_units") = "mm", py::arg("trim_tolerance") = 1e-5, R"doc(
Reads a CAD or mesh file: STEP, IGES, OpenCASCADE .brep, free-form OBJ (through our own reader)
and the triangle meshes assimp reads (STL, OBJ, PLY, OFF, glTF, ...). Returns a Model, whose
bodies are one per solid, in `units`. `file_units` is the unit assumed for files that declare
none (STEP and IGES declare theirs). `trim_tolerance`: the band about trim boundaries within
which a point counts as on its face, relative to each face's parameter extent (the scene files'
reading uses the default; `extremal distance` reads with 1e-9, for its certificate).
Raises extremal.InvalidInput naming the file and the reason when it cannot be read.
The GIL is released while the file is read.
)doc");

  m.def("sphere", [](double r, const std::string& name) {
          return shape("sphere", [&] { return make_sphere_body(r, name); });
        }, py::arg("r"), py::arg("name") = "sphere",
        "A ball of radius r centred at the origin (one exact rational face).");
  m.def("ellipsoid", [](double a, double b, double c, const std::string& name) {
          return shape("ellipsoid", [&] { return make_ellipsoid_body(a, b, c, name); });
        }, py::arg("a"), py::arg("b"), py::arg("c"), py::arg("name") = "ellipsoid",
        "An ellipsoid with semi-axes a, b, c along x, y, z, centred at the origin.");
  m.def("torus", [](double R, double r, const std::string& name) {
          return shape("torus", [&] { return make_torus_body(R, r, name); });
        }, py::arg("R"), py::arg("r"), py::arg("name") = "torus",
        "A torus about the z axis, centred at the origin: major radius R, tube radius r.");
  m.def("cylinder", [](double r, double h, const std::string& name) {
          return shape("cylinder", [&] { return make_cylinder_body(r, h, name); });
        }, py::arg("r"), py::arg("h"), py::arg("name") = "cylinder",
        "A closed cylinder of radius r about the z axis, from z = 0 to z = h (side and caps).");
  m.def("plane", [](double w, double h, const std::string& name) {
          return shape("plane", [&] { return make_plane_body(w, h, name); });
        }, py::arg("w"), py::arg("h"), py::arg("name") = "plane",
        "A w x h rectangle in z = 0 centred at the origin, outward normal +z (an open sheet).");
  m.def("point", [](const std::string& name) {
          return shape("point", [&] { return make_point_body(name); });
        }, py::arg("name") = "point", "A body that is just its origin (a probe, a tool tip).");
}

}  // namespace extremal::python
