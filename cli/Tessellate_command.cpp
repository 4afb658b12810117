// `extremal tessellate FILE -o OUT.(stl|ply|obj) [--deflection D] [--relative]`: a triangle mesh
// of a CAD part at a guaranteed chordal deviation (kernel/Tessellation.h).
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "cli/Commands.h"
#include "io/Mesh_writer.h"
#include "io/Model_reader.h"
#include "io/Shape_spec.h"
#include "kernel/Error.h"
#include "kernel/Tessellation.h"

namespace extremal::cli {

namespace {

// Without --deflection: this fraction of the bounding-box diagonal.
constexpr double k_default_relative_deflection = 1e-3;

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int run_tessellate(const Tessellate_options& options) {
  const char* const who = "extremal tessellate: ";
  const auto t0 = std::chrono::steady_clock::now();
  double deflection = 0.0;
  std::string unit = "mm";  // the file's, once read (messages name it)
  try {
    // The output is checked first, before any long work.
    io::mesh_file_format(options.output);
    io::check_writable(options.output);

    std::vector<Body> bodies;
    std::size_t skipped = 0;
    if (io::is_shape_spec(options.target)) {
      bodies.push_back(io::parse_shape_spec(options.target));
    } else {
      io::Model model = io::read_model(options.target);
      bodies = std::move(model.bodies);
      unit = model.unit;
      skipped = model.skipped.size();
    }
    std::size_t faces = 0, mesh_triangles = 0;
    for (const Body& b : bodies) {
      faces += b.faces.size();
      mesh_triangles += b.mesh.triangles.size();
    }
    if (faces == 0 && mesh_triangles == 0)
      throw Invalid_input(options.target +
                          ": nothing to tessellate (no faces and no mesh triangles)");
    const bool relative = options.relative || options.deflection == 0.0;
    const double fraction =
        options.deflection == 0.0 ? k_default_relative_deflection : options.deflection;
    double diagonal = 0.0;  // of the bodies' box in the file frame, for a relative deflection
    if (relative) {
      Bbox_3 box;
      for (const Body& b : bodies)
        if (!b.faces.empty() || !b.mesh.empty()) box += b.trimmed_bbox(b.placement);
      diagonal = box_diagonal(box);
    }
    deflection = relative ? fraction * diagonal : fraction;
    if (!(std::isfinite(deflection) && deflection > 0.0)) {
      std::ostringstream os;
      os << options.target << ": deflection " << deflection << " " << unit
         << " is not a positive length (bounding-box diagonal " << diagonal << ")";
      throw Invalid_input(os.str());
    }

    const auto t_tess = std::chrono::steady_clock::now();
    Tessellation_options topt;
    topt.deflection = deflection;
    topt.max_triangles = options.max_triangles;
    Tessellation t;
    for (std::size_t k = 0; k < bodies.size(); ++k)
      tessellate(bodies[k], bodies[k].placement, static_cast<int>(k), topt, t);
    const double tess_seconds = seconds_since(t_tess);
    if (t.mesh.triangles.empty())
      throw Invalid_input(options.target +
                          ": the tessellation has no triangle (every face is "
                          "degenerate or trimmed away)");

    std::ostringstream comment;
    comment << "extremal tessellate " << std::filesystem::path(options.target).filename().string()
            << " deflection " << deflection << " " << unit;
    io::write_mesh(options.output, t.mesh, comment.str());

    std::error_code ec;
    const auto bytes = std::filesystem::file_size(options.output, ec);
    std::ostringstream os;
    os.precision(4);
    os << who << options.target << ": " << t.faces << " faces, " << t.mesh.triangles.size()
       << " triangles, " << t.mesh.vertices.size() << " vertices, deflection " << deflection << " "
       << unit;
    if (relative)
      os << " (" << fraction << " of the box diagonal " << diagonal << " " << unit << ")";
    os << ", " << tess_seconds << " s to tessellate, " << seconds_since(t0) << " s in all; wrote "
       << options.output;
    if (!ec) os << " (" << bytes << " bytes)";
    if (skipped > 0) os << "; the reader skipped " << skipped << " entities (see extremal info)";
    std::cerr << os.str() << "\n";
    return 0;
  } catch (const Tessellation_too_large& e) {
    std::cerr << who << options.target << ": at deflection " << deflection << " " << unit << ", " << e.what()
              << " (--max-triangles " << options.max_triangles
              << "); use a larger --deflection or raise --max-triangles\n";
    return 1;
  } catch (const Invalid_input& e) {
    std::cerr << who << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {  // anything unforeseen still exits 1 with a message
    std::cerr << who << "internal error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace extremal::cli
