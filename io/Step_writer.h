// Writing bodies as STEP (ISO 10303-21, AP214 AUTOMOTIVE_DESIGN) text of our own: OpenCASCADE is
// for reading only. Each body must be a closed B-rep solid: faces with trim loops whose curves
// reference Body::edges, every edge with a 3D curve and used twice, in opposite directions, by
// the faces' loops taken about the outward normals. Surfaces go out as
// B_SPLINE_SURFACE_WITH_KNOTS (rational ones as the complex entity with
// RATIONAL_B_SPLINE_SURFACE), edges as shared EDGE_CURVEs on B_SPLINE_CURVE_WITH_KNOTS, faces as
// ADVANCED_FACE with same_sense from outward_sign, in a CLOSED_SHELL / MANIFOLD_SOLID_BREP, one
// product whose shape representation is in millimetres (the scene unit is taken to be mm).
// Numbers are written in the shortest form that reads back to the same double, so the geometry
// survives a round trip exactly.
#pragma once

#include <string>
#include <vector>

#include "kernel/Body.h"

namespace extremal::io {

struct Step_write_options {
  // PRODUCT name; empty: the first body's name.
  std::string product_name;
  // FILE_NAME's name; write_step uses the file's name when this is empty.
  std::string file_name;
  // FILE_NAME time stamp. Fixed by default so that generated files are reproducible.
  std::string time_stamp = "2026-01-01T00:00:00";
};

// The STEP text for `bodies` (each placed by its Body::placement). Throws Invalid_input naming
// the body, face or edge and the reason when a body is not a closed, consistently oriented
// B-rep solid (no edges, a degenerate edge, an edge used once or in the same direction twice).
std::string write_step_string(const std::vector<Body>& bodies,
                              const Step_write_options& options = {});

// The same written to `path`; FILE_NAME holds the file's name. Throws Invalid_input when the
// file cannot be written.
void write_step(const std::string& path, const std::vector<Body>& bodies,
                const Step_write_options& options = {});

}  // namespace extremal::io
