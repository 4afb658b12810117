#include "io/Scene.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "kernel/Error.h"
#include "kernel/Shapes.h"

namespace extremal::io {

namespace {

using nlohmann::json;

// Error naming the file and JSON path.
class Scene_error {
 public:
  explicit Scene_error(std::string file) : m_file(std::move(file)) {}
  [[noreturn]] void fail(const std::string& path, const std::string& reason) const {
    throw Invalid_input(m_file + ": " + (path.empty() ? "" : path + ": ") + reason);
  }
  const std::string& file() const { return m_file; }

 private:
  std::string m_file;
};

std::string type_name(const json& j) {
  if (j.is_number()) return "a number";
  if (j.is_string()) return "a string";
  if (j.is_array()) return "an array";
  if (j.is_object()) return "an object";
  if (j.is_boolean()) return "a boolean";
  return "null";
}

void check_keys(const json& obj, const std::string& path, std::initializer_list<const char*> keys,
                const Scene_error& err) {
  for (auto it = obj.begin(); it != obj.end(); ++it) {
    bool known = false;
    for (const char* k : keys) known = known || it.key() == k;
    if (!known) {
      std::string list;
      for (const char* k : keys) list += std::string(list.empty() ? "" : ", ") + k;
      err.fail(path.empty() ? it.key() : path + "." + it.key(),
               "unknown key (expected one of: " + list + ")");
    }
  }
}

const json& require(const json& obj, const char* key, const std::string& path,
                    const Scene_error& err) {
  const auto it = obj.find(key);
  if (it == obj.end()) err.fail(path, std::string("missing key '") + key + "'");
  return *it;
}

double number(const json& j, const std::string& path, const Scene_error& err) {
  if (!j.is_number()) err.fail(path, "expected a number, got " + type_name(j));
  const double x = j.get<double>();
  if (!std::isfinite(x)) err.fail(path, "not a finite number");
  return x;
}

double positive(const json& j, const std::string& path, const Scene_error& err) {
  const double x = number(j, path, err);
  if (!(x > 0.0)) err.fail(path, "must be > 0");
  return x;
}

int integer(const json& j, const std::string& path, int min_value, const Scene_error& err) {
  if (!j.is_number_integer() && !j.is_number_unsigned())
    err.fail(path, "expected an integer, got " + type_name(j));
  const long long v = j.get<long long>();
  if (v < min_value || v > 1000000000LL)
    err.fail(path, "must be an integer >= " + std::to_string(min_value));
  return static_cast<int>(v);
}

std::string string(const json& j, const std::string& path, const Scene_error& err) {
  if (!j.is_string()) err.fail(path, "expected a string, got " + type_name(j));
  return j.get<std::string>();
}

Vec3 vec3(const json& j, const std::string& path, const Scene_error& err) {
  if (!j.is_array() || j.size() != 3) err.fail(path, "expected an array of 3 numbers");
  Vec3 v;
  for (int i = 0; i < 3; ++i) v[i] = number(j[i], path + "[" + std::to_string(i) + "]", err);
  return v;
}

Rigid_pose_3 pose(const json& j, const std::string& path, const Scene_error& err) {
  if (!j.is_object()) err.fail(path, "expected an object with position and quaternion");
  check_keys(j, path, {"position", "quaternion"}, err);
  Vec3 p = Vec3::Zero();
  if (j.contains("position")) p = vec3(j["position"], path + ".position", err);
  if (!j.contains("quaternion")) return Rigid_pose_3(Mat3::Identity(), p);
  const json& q = j["quaternion"];
  const std::string qp = path + ".quaternion";
  if (!q.is_array() || q.size() != 4) err.fail(qp, "expected [qw, qx, qy, qz]");
  double c[4];
  for (int i = 0; i < 4; ++i) c[i] = number(q[i], qp + "[" + std::to_string(i) + "]", err);
  const double n = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2] + c[3] * c[3]);
  if (std::abs(n - 1.0) > 1e-6)
    err.fail(qp, "not a unit quaternion (norm " + std::to_string(n) + ")");
  return Rigid_pose_3::from_quaternion(p, c[0], c[1], c[2], c[3]);
}

Body shape_body(const json& j, const std::string& path, const std::string& name,
                const Scene_error& err) {
  if (!j.is_object()) err.fail(path, "expected an object with a type");
  const std::string type = string(require(j, "type", path, err), path + ".type", err);
  auto get = [&](const char* key) { return positive(require(j, key, path, err), path + "." + key, err); };
  try {
    if (type == "point") {
      check_keys(j, path, {"type"}, err);
      return make_point_body(name);
    }
    if (type == "sphere") {
      check_keys(j, path, {"type", "radius"}, err);
      return make_sphere_body(get("radius"), name);
    }
    if (type == "ellipsoid") {
      check_keys(j, path, {"type", "axes"}, err);
      const Vec3 a = vec3(require(j, "axes", path, err), path + ".axes", err);
      for (int i = 0; i < 3; ++i)
        if (!(a[i] > 0)) err.fail(path + ".axes[" + std::to_string(i) + "]", "must be > 0");
      return make_ellipsoid_body(a.x(), a.y(), a.z(), name);
    }
    if (type == "torus") {
      check_keys(j, path, {"type", "major", "minor"}, err);
      return make_torus_body(get("major"), get("minor"), name);
    }
    if (type == "cylinder") {
      check_keys(j, path, {"type", "radius", "height"}, err);
      return make_cylinder_body(get("radius"), get("height"), name);
    }
    if (type == "plane") {
      check_keys(j, path, {"type", "size"}, err);
      const json& s = require(j, "size", path, err);
      if (!s.is_array() || s.size() != 2) err.fail(path + ".size", "expected [w, h]");
      return make_plane_body(positive(s[0], path + ".size[0]", err),
                             positive(s[1], path + ".size[1]", err), name);
    }
  } catch (const Invalid_input& e) {
    const std::string msg = e.what();
    if (msg.rfind(err.file() + ":", 0) == 0) throw;
    err.fail(path, msg);
  }
  err.fail(path + ".type",
           "unknown shape type '" + type + "' (point, sphere, ellipsoid, torus, cylinder, plane)");
}

// A pose table file (parse_pose_table); errors name the scene file and the JSON path too.
std::vector<Keyframe> read_table(const std::string& file, const std::string& path,
                                 const Scene_error& err) {
  std::ifstream in(file);
  if (!in) err.fail(path, "cannot open pose table '" + file + "'");
  try {
    return parse_pose_table(in, file);
  } catch (const Invalid_input& e) {
    err.fail(path, e.what());
  }
}

Motion motion(const json& j, const std::string& path, const Rigid_pose_3& initial, double t0,
              const std::string& folder, const Scene_error& err) {
  if (!j.is_object()) err.fail(path, "expected an object with a type");
  const std::string type = string(require(j, "type", path, err), path + ".type", err);
  if (type == "static") {
    check_keys(j, path, {"type"}, err);
    return Motion::still(initial);
  }
  if (type == "twist") {
    check_keys(j, path, {"type", "velocity", "angular_velocity"}, err);
    Twist_3 tw;
    if (j.contains("velocity")) tw.linear = vec3(j["velocity"], path + ".velocity", err);
    if (j.contains("angular_velocity"))
      tw.angular = vec3(j["angular_velocity"], path + ".angular_velocity", err);
    return Motion::twist(initial, tw, t0);
  }
  if (type == "keyframes") {
    check_keys(j, path, {"type", "keyframes"}, err);
    const json& k = require(j, "keyframes", path, err);
    const std::string kp = path + ".keyframes";
    if (!k.is_array() || k.empty()) err.fail(kp, "expected a non-empty array of keyframes");
    std::vector<Keyframe> frames;
    for (std::size_t i = 0; i < k.size(); ++i) {
      const std::string ip = kp + "[" + std::to_string(i) + "]";
      if (!k[i].is_object()) err.fail(ip, "expected an object {t, position, quaternion}");
      check_keys(k[i], ip, {"t", "position", "quaternion"}, err);
      const double t = number(require(k[i], "t", ip, err), ip + ".t", err);
      if (!frames.empty() && !(t > frames.back().t)) err.fail(ip + ".t", "times must increase");
      if (!k[i].contains("position")) err.fail(ip, "missing key 'position'");
      json p = k[i];
      p.erase("t");
      frames.push_back({t, pose(p, ip, err)});
    }
    return Motion::keyframes(std::move(frames));
  }
  if (type == "table") {
    check_keys(j, path, {"type", "file"}, err);
    const std::string f = string(require(j, "file", path, err), path + ".file", err);
    const std::filesystem::path full = std::filesystem::path(folder) / f;
    return Motion::keyframes(read_table(full.string(), path + ".file", err), Motion::Type::Table);
  }
  err.fail(path + ".type", "unknown motion type '" + type + "' (static, twist, keyframes, table)");
}

// A JSON parser callback that rejects a key given twice in one object (the parser would keep
// the last silently), naming its JSON path.
class Duplicate_key_check {
 public:
  explicit Duplicate_key_check(const Scene_error& err) : m_err(&err) {}
  bool operator()(int /*depth*/, json::parse_event_t event, json& parsed) {
    using E = json::parse_event_t;
    if ((event == E::object_start || event == E::array_start || event == E::value) &&
        !m_frames.empty() && m_frames.back().is_array)
      ++m_frames.back().index;
    switch (event) {
      case E::object_start: m_frames.push_back({false, -1, {}, {}}); break;
      case E::array_start: m_frames.push_back({true, -1, {}, {}}); break;
      case E::object_end:
      case E::array_end: m_frames.pop_back(); break;
      case E::key: {
        Frame& f = m_frames.back();
        f.key = parsed.get<std::string>();
        if (!f.keys.insert(f.key).second) m_err->fail(path(), "key given twice");
        break;
      }
      case E::value: break;
    }
    return true;
  }

 private:
  struct Frame {
    bool is_array;
    long index;
    std::string key;
    std::set<std::string> keys;
  };
  std::string path() const {
    std::string p;
    for (const Frame& f : m_frames)
      p += f.is_array ? "[" + std::to_string(f.index) + "]" : (p.empty() ? "" : ".") + f.key;
    return p;
  }
  const Scene_error* m_err;
  std::vector<Frame> m_frames;
};

}  // namespace

double unit_in_mm(const std::string& unit) {
  static const std::map<std::string, double> units = {
      {"mm", 1.0}, {"cm", 10.0}, {"m", 1000.0}, {"in", 25.4}, {"ft", 304.8}, {"um", 1e-3}};
  const auto it = units.find(unit);
  if (it == units.end())
    throw Invalid_input("unknown unit '" + unit + "' (mm, cm, m, in, ft, um)");
  return it->second;
}

int Scene::step_count() const {
  return static_cast<int>(std::floor((end - start) / step * (1.0 + 1e-12) + 1e-9)) + 1;
}

double Scene::time_of(int i) const { return start + i * step; }

std::vector<Keyframe> parse_pose_table(std::istream& in, const std::string& name) {
  auto fail_line = [&](int line_no, const std::string& reason) {
    throw Invalid_input(name + ":" + std::to_string(line_no) + ": " + reason);
  };
  auto trim = [](std::string text) {
    const auto b = text.find_first_not_of(" \t\r");
    const auto e = text.find_last_not_of(" \t\r");
    return b == std::string::npos ? std::string() : text.substr(b, e - b + 1);
  };
  std::vector<Keyframe> frames;
  std::string line;
  int line_no = 0;
  bool first_content = true;
  while (std::getline(in, line)) {
    ++line_no;
    line = trim(line);
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) cells.push_back(trim(cell));
    if (!line.empty() && line.back() == ',') cells.push_back("");
    const bool header = first_content && !cells.empty() && !cells[0].empty() &&
                        std::isalpha(static_cast<unsigned char>(cells[0][0]));
    first_content = false;
    if (header) {
      static const char* const names[] = {"t", "x", "y", "z", "qw", "qx", "qy", "qz"};
      bool ok = cells.size() == 8;
      for (std::size_t i = 0; ok && i < 8; ++i) ok = cells[i] == names[i];
      if (!ok) fail_line(line_no, "header '" + line + "': expected t,x,y,z,qw,qx,qy,qz");
      continue;
    }
    if (cells.size() != 8)
      fail_line(line_no, "expected 8 columns t,x,y,z,qw,qx,qy,qz, got " +
                             std::to_string(cells.size()));
    double v[8];
    for (int i = 0; i < 8; ++i) {
      const std::string& c = cells[static_cast<std::size_t>(i)];
      char* end = nullptr;
      v[i] = std::strtod(c.c_str(), &end);
      if (c.empty() || end != c.c_str() + c.size() || !std::isfinite(v[i]))
        fail_line(line_no, "column " + std::to_string(i + 1) + ": '" + c +
                               "' is not a finite number");
    }
    if (!frames.empty() && !(v[0] > frames.back().t))
      fail_line(line_no, "times must increase");
    const double n = std::sqrt(v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7]);
    if (std::abs(n - 1.0) > 1e-6)
      fail_line(line_no, "not a unit quaternion (norm " + std::to_string(n) + ")");
    frames.push_back({v[0], Rigid_pose_3::from_quaternion(Vec3(v[1], v[2], v[3]), v[4], v[5],
                                                          v[6], v[7])});
  }
  if (frames.empty()) throw Invalid_input(name + ": pose table has no rows");
  return frames;
}

Scene parse_scene(const std::string& text, const std::string& path, const File_loader& load_file) {
  const Scene_error err(path);
  json root;
  try {
    root = json::parse(text, Duplicate_key_check(err));
  } catch (const json::exception& e) {  // parse_error, and out_of_range for numbers that overflow
    err.fail("", std::string("not valid JSON: ") + e.what());
  }
  if (!root.is_object()) err.fail("", "the scene must be a JSON object");
  check_keys(root, "", {"units", "time", "bodies", "pairs", "threshold", "tracker", "tolerance",
                    "clearance"}, err);
  Scene scene;
  scene.path = path;
  const std::string folder = std::filesystem::path(path).parent_path().string();
  if (root.contains("units")) {
    scene.units = string(root["units"], "units", err);
    try {
      unit_in_mm(scene.units);
    } catch (const Invalid_input& e) {
      err.fail("units", e.what());
    }
  }
  const json& time = require(root, "time", "", err);
  if (!time.is_object()) err.fail("time", "expected an object {start, end, step}");
  check_keys(time, "time", {"start", "end", "step"}, err);
  scene.start = time.contains("start") ? number(time["start"], "time.start", err) : 0.0;
  scene.end = number(require(time, "end", "time", err), "time.end", err);
  scene.step = positive(require(time, "step", "time", err), "time.step", err);
  if (scene.end < scene.start) err.fail("time.end", "must not be before time.start");
  if ((scene.end - scene.start) / scene.step > 1e8)
    err.fail("time.step", "more than 10^8 steps from start to end");

  const json& bodies = require(root, "bodies", "", err);
  if (!bodies.is_array() || bodies.empty()) err.fail("bodies", "expected a non-empty array");
  std::map<std::string, std::vector<int>> entries;  // entry name -> body indices
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const std::string bp = "bodies[" + std::to_string(i) + "]";
    const json& b = bodies[i];
    if (!b.is_object()) err.fail(bp, "expected an object");
    check_keys(b, bp, {"name", "shape", "file", "units", "pose", "motion"}, err);
    const std::string name = string(require(b, "name", bp, err), bp + ".name", err);
    if (name.empty()) err.fail(bp + ".name", "must not be empty");
    if (entries.count(name)) err.fail(bp + ".name", "duplicate body name '" + name + "'");
    const Rigid_pose_3 initial = b.contains("pose") ? pose(b["pose"], bp + ".pose", err)
                                                    : Rigid_pose_3();
    const Motion m = b.contains("motion")
                         ? motion(b["motion"], bp + ".motion", initial, scene.start, folder, err)
                         : Motion::still(initial);
    // Keyframes and tables place the body themselves; a pose beside them must agree.
    if (b.contains("pose") && (m.type() == Motion::Type::Keyframes || m.type() == Motion::Type::Table)) {
      const Rigid_pose_3 at_start = m.pose_at(scene.start);
      const double dp = (at_start.translation() - initial.translation()).norm();
      const double dr = (at_start.rotation() - initial.rotation()).norm();
      if (dp > 1e-9 * (1.0 + initial.translation().norm()) || dr > 1e-6) {
        std::ostringstream os;
        os << "differs from the pose the " << (m.type() == Motion::Type::Table ? "table" : "keyframes")
           << " give at time.start = " << scene.start << " (position " << at_start.translation().x()
           << ", " << at_start.translation().y() << ", " << at_start.translation().z()
           << "); drop 'pose' or make it agree";
        err.fail(bp + ".pose", os.str());
      }
    }
    std::vector<Body> loaded;
    std::string source;
    if (b.contains("shape") == b.contains("file"))
      err.fail(bp, "give exactly one of 'shape' and 'file'");
    if (b.contains("shape")) {
      if (b.contains("units")) err.fail(bp + ".units", "only file entries take units");
      loaded.push_back(shape_body(b["shape"], bp + ".shape", name, err));
      source = b["shape"].dump();
    } else {
      const std::string f = string(b["file"], bp + ".file", err);
      const std::string full = (std::filesystem::path(folder) / f).string();
      const std::string file_units =
          b.contains("units") ? string(b["units"], bp + ".units", err) : std::string();
      if (!file_units.empty()) {
        try {
          unit_in_mm(file_units);
        } catch (const Invalid_input& e) {
          err.fail(bp + ".units", e.what());
        }
      }
      if (!load_file) err.fail(bp + ".file", "CAD files are not supported in this build");
      try {
        loaded = load_file(full, file_units, scene.units);
      } catch (const Invalid_input& e) {
        err.fail(bp + ".file", e.what());
      }
      if (loaded.empty()) err.fail(bp + ".file", full + ": the file holds no bodies");
      source = full;
    }
    for (std::size_t k = 0; k < loaded.size(); ++k) {
      Scene_body sb;
      sb.name = loaded.size() == 1 ? name : name + "/" + std::to_string(k + 1);
      sb.entry = name;
      sb.source = source;
      sb.body = std::move(loaded[k]);
      sb.body.name = sb.name;
      sb.motion = m;
      entries[name].push_back(static_cast<int>(scene.bodies.size()));
      scene.bodies.push_back(std::move(sb));
    }
  }
  // Names of multi-solid bodies (NAME/k) resolve too.
  std::map<std::string, std::vector<int>> names = entries;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i)
    names[scene.bodies[i].name] = {static_cast<int>(i)};

  std::set<std::pair<int, int>> seen;
  auto add_pair = [&](int a, int b) {
    if (a == b) return;
    const auto key = std::minmax(a, b);
    if (seen.insert(key).second) scene.pairs.emplace_back(a, b);
  };
  const json pairs = root.contains("pairs") ? root["pairs"] : json("all");
  if (pairs.is_string()) {
    if (pairs.get<std::string>() != "all") err.fail("pairs", "expected \"all\" or a list of name pairs");
    for (std::size_t a = 0; a < scene.bodies.size(); ++a)
      for (std::size_t b = a + 1; b < scene.bodies.size(); ++b)
        add_pair(static_cast<int>(a), static_cast<int>(b));
  } else {
    if (!pairs.is_array()) err.fail("pairs", "expected \"all\" or a list of name pairs");
    std::set<std::pair<std::string, std::string>> listed;
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      const std::string pp = "pairs[" + std::to_string(i) + "]";
      if (!pairs[i].is_array() || pairs[i].size() != 2) err.fail(pp, "expected [name_a, name_b]");
      const std::string na = string(pairs[i][0], pp + "[0]", err);
      const std::string nb = string(pairs[i][1], pp + "[1]", err);
      if (!names.count(na)) err.fail(pp + "[0]", "no body named '" + na + "'");
      if (!names.count(nb)) err.fail(pp + "[1]", "no body named '" + nb + "'");
      // An entry paired with itself watches the pairs among its solids.
      if (na == nb && names[na].size() < 2) err.fail(pp, "a body cannot be paired with itself");
      const auto key = std::minmax(na, nb);
      if (!listed.insert(key).second)
        err.fail(pp, "the pair '" + na + "', '" + nb + "' is listed twice");
      for (int a : names[na])
        for (int b : names[nb]) add_pair(a, b);
    }
  }
  if (root.contains("threshold")) scene.threshold = positive(root["threshold"], "threshold", err);
  if (root.contains("clearance")) scene.clearance = positive(root["clearance"], "clearance", err);
  if (root.contains("tracker")) {
    const json& t = root["tracker"];
    if (!t.is_object()) err.fail("tracker", "expected an object");
    check_keys(t, "tracker",
               {"gain", "substeps", "audit_every", "own_basin_gap", "integrator", "memory_limit_mib"},
               err);
    if (t.contains("memory_limit_mib"))
      scene.tracker.memory_limit_mib = positive(t["memory_limit_mib"], "tracker.memory_limit_mib", err);
    if (t.contains("gain")) scene.tracker.gain = positive(t["gain"], "tracker.gain", err);
    if (t.contains("substeps"))
      scene.tracker.substeps = integer(t["substeps"], "tracker.substeps", 1, err);
    if (t.contains("audit_every"))
      scene.tracker.audit_every = integer(t["audit_every"], "tracker.audit_every", 0, err);
    if (t.contains("own_basin_gap")) {
      const double g = number(t["own_basin_gap"], "tracker.own_basin_gap", err);
      if (!(g >= 0.0 && g < 1.0)) err.fail("tracker.own_basin_gap", "must be >= 0 and < 1");
      scene.tracker.own_basin_gap = g;
    }
    if (t.contains("integrator")) {
      const std::string s = string(t["integrator"], "tracker.integrator", err);
      if (s != "euler" && s != "rk4") err.fail("tracker.integrator", "expected \"euler\" or \"rk4\"");
      scene.tracker.rk4 = s == "rk4";
    }
  }
  if (root.contains("tolerance")) {
    const json& t = root["tolerance"];
    if (!t.is_object()) err.fail("tolerance", "expected an object");
    check_keys(t, "tolerance", {"absolute", "relative"}, err);
    if (t.contains("absolute"))
      scene.tolerance.absolute = positive(t["absolute"], "tolerance.absolute", err);
    if (t.contains("relative")) {
      const double r = positive(t["relative"], "tolerance.relative", err);
      if (!(r < 1.0)) err.fail("tolerance.relative", "must be > 0 and < 1");
      scene.tolerance.relative = r;
    }
  }
  if (scene.pairs.empty())
    err.fail("pairs", "no pair of bodies to watch (a scene needs at least two bodies)");
  return scene;
}

Scene read_scene(const std::string& path, const File_loader& load_file) {
  std::ifstream in(path);
  if (!in) throw Invalid_input(path + ": cannot open the scene file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_scene(ss.str(), path, load_file);
}

}  // namespace extremal::io
