#include "io/Model_reader.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>

#include "io/internal/Readers.h"
#include "kernel/Error.h"

namespace extremal::io {

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string extension(const std::string& name) {
  const std::string base = name.substr(name.find_last_of("/\\") + 1);
  const auto dot = base.find_last_of('.');
  return dot == std::string::npos ? std::string() : lower(base.substr(dot + 1));
}

std::string stem(const std::string& name) {
  std::string s = name.substr(name.find_last_of("/\\") + 1);
  const auto dot = s.find_last_of('.');
  return dot == std::string::npos || dot == 0 ? s : s.substr(0, dot);
}

bool starts_with(const std::string& s, const char* prefix) {
  return s.compare(0, std::strlen(prefix), prefix) == 0;
}

std::string skip_blank(const std::string& s) {
  std::size_t i = 0;
  if (s.size() >= 3 && static_cast<unsigned char>(s[0]) == 0xEF &&
      static_cast<unsigned char>(s[1]) == 0xBB && static_cast<unsigned char>(s[2]) == 0xBF)
    i = 3;  // UTF-8 byte order mark
  while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
  return s.substr(i);
}

// True when some line of `text` starts with a free-form OBJ statement.
bool has_freeform_statement(const std::string& text) {
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    std::size_t i = pos;
    while (i < end && (text[i] == ' ' || text[i] == '\t')) ++i;
    const std::string word = text.substr(i, std::min<std::size_t>(8, end - i));
    if (starts_with(word, "cstype") || starts_with(word, "surf ") || starts_with(word, "curv ") ||
        starts_with(word, "curv2 "))
      return true;
    pos = end + 1;
  }
  return false;
}

bool looks_like_iges(const std::string& head) {
  // Fixed 80-column records; the first is the Start section: 'S' in column 73.
  const std::size_t eol = head.find_first_of("\r\n");
  const std::string first = head.substr(0, eol);
  return first.size() >= 73 && first.size() <= 82 && first[72] == 'S';
}

std::string read_all(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw Invalid_input(path + ": cannot open file (" + std::strerror(errno) + ")");
  if (S_ISDIR(st.st_mode)) throw Invalid_input(path + ": is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Invalid_input(path + ": cannot open file (" + std::strerror(errno) + ")");
  std::ostringstream os;
  os << in.rdbuf();
  if (in.bad()) throw Invalid_input(path + ": read error");
  return os.str();
}

class Temp_file {
 public:
  Temp_file(const std::string& ext, const std::string& bytes) {
    const char* dir = std::getenv("TMPDIR");
    std::string templ = std::string(dir && *dir ? dir : "/tmp") + "/extremal-XXXXXX." + ext;
    std::vector<char> buf(templ.begin(), templ.end());
    buf.push_back('\0');
    const int fd = ::mkstemps(buf.data(), static_cast<int>(ext.size() + 1));
    if (fd < 0) throw Invalid_input("cannot create a temporary file: " + std::string(std::strerror(errno)));
    m_path = buf.data();
    std::size_t done = 0;
    while (done < bytes.size()) {
      const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
      if (n <= 0) break;
      done += static_cast<std::size_t>(n);
    }
    ::close(fd);
  }
  ~Temp_file() { std::remove(m_path.c_str()); }
  const std::string& path() const { return m_path; }

 private:
  std::string m_path;
};

void finish(Model& model, const std::string& name, const Read_options& options) {
  model.unit = options.scene_unit;
  if (model.bodies.empty()) {
    std::ostringstream os;
    os << name << ": no usable body in the file";
    if (!model.skipped.empty()) {
      os << " (";
      for (std::size_t i = 0; i < model.skipped.size() && i < 3; ++i)
        os << (i ? "; " : "") << model.skipped[i].entity << ": " << model.skipped[i].reason;
      if (model.skipped.size() > 3) os << "; and " << model.skipped.size() - 3 << " more";
      os << ")";
    }
    throw Invalid_input(os.str());
  }
  internal::make_names_unique(model, stem(name));
}

Model read_impl(const std::string& name, const std::string& bytes, bool on_disk,
                const Read_options& options) {
  if (bytes.empty()) throw Invalid_input(name + ": file is empty");
  if (unit_in_millimetres(options.scene_unit) <= 0.0)
    throw Invalid_input("unknown scene unit '" + options.scene_unit + "'");
  Model model;
  model.file = name;
  Model_format f = options.format;
  if (f == Model_format::Automatic) f = detect_format(name, bytes.substr(0, 4096));
  if (f == Model_format::Mesh && extension(name) == "obj" && has_freeform_statement(bytes))
    f = Model_format::Obj_freeform;
  if (f == Model_format::Automatic && has_freeform_statement(bytes.substr(0, 1 << 16)))
    f = Model_format::Obj_freeform;
  model.format = f;
  switch (f) {
    case Model_format::Step:
    case Model_format::Iges:
    case Model_format::Brep: {
      // The text is checked before OpenCASCADE sees it; OpenCASCADE runs in a child process
      // (docs/import.md, "Limits and containment").
      internal::Cad_scan scan;
      if (f == Model_format::Step) internal::scan_step(name, bytes, options.limits, scan);
      if (f == Model_format::Iges) internal::scan_iges(name, bytes, options.limits, scan);
      const auto read = [&](const std::string& path) {
        if (options.limits.isolate)
          internal::read_occt_isolated(path, name, f, options, scan, model);
        else
          internal::read_occt(path, f, options, scan, model);
      };
      if (on_disk) {
        read(name);
      } else {
        const Temp_file tmp(f == Model_format::Step ? "stp" : f == Model_format::Iges ? "igs" : "brep",
                            bytes);
        try {
          read(tmp.path());
        } catch (const Invalid_input& e) {
          std::string msg = e.what();
          const auto at = msg.find(tmp.path());
          if (at != std::string::npos) msg.replace(at, tmp.path().size(), name);
          throw Invalid_input(msg);
        }
        for (auto& b : model.bodies)
          if (b.source_name.find("extremal-") == 0) b.source_name = stem(name);
      }
      break;
    }
    case Model_format::Obj_freeform:
      internal::read_obj_freeform(name, bytes, options, model);
      break;
    case Model_format::Mesh:
    case Model_format::Automatic:
      internal::read_mesh(name, on_disk ? nullptr : &bytes, options, model);
      break;
  }
  finish(model, name, options);
  return model;
}

}  // namespace

namespace {

std::mutex& limits_mutex() {
  static std::mutex m;
  return m;
}

Import_limits& process_limits() {
  static Import_limits limits;
  return limits;
}

}  // namespace

Import_limits default_import_limits() {
  const std::lock_guard<std::mutex> lock(limits_mutex());
  return process_limits();
}

void set_default_import_limits(const Import_limits& limits) {
  const std::lock_guard<std::mutex> lock(limits_mutex());
  process_limits() = limits;
}

double unit_in_millimetres(const std::string& unit) {
  static const std::map<std::string, double> units = {
      {"mm", 1.0},         {"millimetre", 1.0},   {"millimeter", 1.0},   {"millimetres", 1.0},
      {"millimeters", 1.0}, {"cm", 10.0},         {"centimetre", 10.0},  {"centimeter", 10.0},
      {"dm", 100.0},       {"m", 1000.0},        {"metre", 1000.0},     {"meter", 1000.0},
      {"metres", 1000.0},  {"meters", 1000.0},   {"km", 1e6},           {"kilometre", 1e6},
      {"kilometer", 1e6},  {"um", 1e-3},         {"micron", 1e-3},      {"micrometre", 1e-3},
      {"micrometer", 1e-3}, {"nm", 1e-6},        {"nanometre", 1e-6},   {"nanometer", 1e-6},
      {"in", 25.4},        {"inch", 25.4},       {"inches", 25.4},      {"ft", 304.8},
      {"foot", 304.8},     {"feet", 304.8},      {"yd", 914.4},         {"yard", 914.4},
      {"mi", 1609344.0},   {"mile", 1609344.0},  {"mil", 0.0254},       {"uin", 25.4e-6},
      {"microinch", 25.4e-6}};
  const auto it = units.find(lower(unit));
  return it == units.end() ? 0.0 : it->second;
}

std::string format_name(Model_format f) {
  switch (f) {
    case Model_format::Automatic: return "automatic";
    case Model_format::Step: return "STEP";
    case Model_format::Iges: return "IGES";
    case Model_format::Brep: return "OpenCASCADE BREP";
    case Model_format::Obj_freeform: return "OBJ free-form";
    case Model_format::Mesh: return "mesh";
  }
  return "unknown";
}

Model_format detect_format(const std::string& name, const std::string& head_bytes) {
  const std::string head = skip_blank(head_bytes);
  if (starts_with(head, "ISO-10303-21")) return Model_format::Step;
  if (starts_with(head, "DBRep_DrawableShape") || starts_with(head, "CASCADE Topology V"))
    return Model_format::Brep;
  if (looks_like_iges(head_bytes)) return Model_format::Iges;
  if (starts_with(head_bytes, "glTF") || starts_with(head, "ply") || starts_with(head, "OFF") ||
      starts_with(head, "solid"))
    return Model_format::Mesh;
  const std::string ext = extension(name);
  if (ext == "step" || ext == "stp" || ext == "p21") return Model_format::Step;
  if (ext == "iges" || ext == "igs") return Model_format::Iges;
  if (ext == "brep" || ext == "brp") return Model_format::Brep;
  if (ext == "obj") return has_freeform_statement(head) ? Model_format::Obj_freeform : Model_format::Mesh;
  if (has_freeform_statement(head)) return Model_format::Obj_freeform;
  static const char* mesh_ext[] = {"stl", "ply", "off", "gltf", "glb", "fbx", "dae", "3ds", "x",
                                   "ase", "lwo", "ms3d", "md2", "md3", "smd", "ac", "nff",
                                   "raw", "ter", "hmp", "mesh", "xml", "irr", "q3o", "q3s",
                                   "3mf", "amf", "ifc", "b3d", "cob", "csm", "dxf", "lws",
                                   "ogex", "sib", "x3d", "xgl", "zgl"};
  for (const char* e : mesh_ext)
    if (ext == e) return Model_format::Mesh;
  return Model_format::Automatic;
}

Model read_model(const std::string& path, const Read_options& options) {
  return read_impl(path, read_all(path), true, options);
}

Model read_model_from_memory(const std::string& name, const std::string& bytes,
                             const Read_options& options) {
  return read_impl(name, bytes, false, options);
}

std::vector<Body> load_bodies(const std::string& path, const std::string& file_units,
                              const std::string& scene_units) {
  Read_options options;
  options.unitless_file_unit = file_units.empty() ? "mm" : file_units;
  options.scene_unit = scene_units.empty() ? "mm" : scene_units;
  if (unit_in_millimetres(options.unitless_file_unit) <= 0.0)
    throw Invalid_input(path + ": unknown unit '" + options.unitless_file_unit + "'");
  return read_model(path, options).bodies;
}

namespace internal {

double scene_scale(const std::string& file_unit, const Read_options& options) {
  const double f = unit_in_millimetres(file_unit);
  const double s = unit_in_millimetres(options.scene_unit);
  if (f <= 0.0) throw Invalid_input("unknown unit '" + file_unit + "'");
  if (s <= 0.0) throw Invalid_input("unknown scene unit '" + options.scene_unit + "'");
  return f / s;
}

void make_names_unique(Model& model, const std::string& fallback) {
  std::map<std::string, int> count, seen;
  for (auto& b : model.bodies) {
    if (b.source_name.empty()) b.source_name = fallback;
    ++count[b.source_name];
  }
  for (auto& b : model.bodies) {
    if (count[b.source_name] == 1)
      b.name = b.source_name;
    else
      b.name = b.source_name + "#" + std::to_string(++seen[b.source_name]);
  }
}

}  // namespace internal

}  // namespace extremal::io
