#include "io/Shape_spec.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "kernel/Error.h"
#include "kernel/Shapes.h"

namespace extremal::io {

namespace {

const char* const k_kinds[] = {"sphere", "ellipsoid", "torus", "cylinder", "plane"};

// Comma-separated finite numbers; throws naming `context` on anything else.
std::vector<double> parse_numbers(const std::string& list, const std::string& context) {
  std::vector<double> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = list.find(',', start);
    const std::string item = list.substr(start, comma == std::string::npos ? std::string::npos
                                                                           : comma - start);
    char* end = nullptr;
    errno = 0;
    const double x = std::strtod(item.c_str(), &end);
    if (item.empty() || end != item.c_str() + item.size() || errno == ERANGE ||
        !std::isfinite(x))
      throw Invalid_input(context + ": '" + item + "' is not a finite number");
    out.push_back(x);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

}  // namespace

bool is_shape_spec(const std::string& text) {
  if (text == "point") return true;
  const std::size_t colon = text.find(':');
  if (colon == std::string::npos) return false;
  const std::string kind = text.substr(0, colon);
  for (const char* k : k_kinds)
    if (kind == k) return true;
  return false;
}

Body parse_shape_spec(const std::string& text) {
  if (text == "point") return make_point_body("point");
  const std::size_t colon = text.find(':');
  const std::string kind = colon == std::string::npos ? text : text.substr(0, colon);
  const std::string context = "shape spec '" + text + "'";
  if (colon == std::string::npos) throw Invalid_input(context + ": expected KIND:NUMBERS");
  const std::vector<double> v = parse_numbers(text.substr(colon + 1), context);
  auto expect = [&](std::size_t n, const char* form) {
    if (v.size() != n)
      throw Invalid_input(context + ": " + kind + " takes " + std::to_string(n) +
                          " numbers (" + form + "), got " + std::to_string(v.size()));
  };
  try {
    if (kind == "sphere") {
      expect(1, "sphere:r");
      return make_sphere_body(v[0], text);
    }
    if (kind == "ellipsoid") {
      expect(3, "ellipsoid:a,b,c");
      return make_ellipsoid_body(v[0], v[1], v[2], text);
    }
    if (kind == "torus") {
      expect(2, "torus:R,r");
      return make_torus_body(v[0], v[1], text);
    }
    if (kind == "cylinder") {
      expect(2, "cylinder:r,h");
      return make_cylinder_body(v[0], v[1], text);
    }
    if (kind == "plane") {
      expect(2, "plane:w,h");
      return make_plane_body(v[0], v[1], text);
    }
  } catch (const Invalid_input& e) {
    const std::string msg = e.what();
    if (msg.rfind(context, 0) == 0) throw;
    throw Invalid_input(context + ": " + msg);
  }
  throw Invalid_input(context + ": unknown shape kind '" + kind +
                      "' (point, sphere, ellipsoid, torus, cylinder, plane)");
}

Rigid_pose_3 parse_pose(const std::string& text) {
  const std::string context = "pose '" + text + "'";
  const std::vector<double> v = parse_numbers(text, context);
  if (v.size() != 3 && v.size() != 7)
    throw Invalid_input(context + ": expected x,y,z or x,y,z,qw,qx,qy,qz (" +
                        std::to_string(v.size()) + " numbers given)");
  const Vec3 t(v[0], v[1], v[2]);
  if (v.size() == 3) return Rigid_pose_3(Mat3::Identity(), t);
  try {
    return Rigid_pose_3::from_quaternion(t, v[3], v[4], v[5], v[6]);
  } catch (const Invalid_input& e) {
    throw Invalid_input(context + ": " + e.what());
  }
}

}  // namespace extremal::io
