// Binary STL, ASCII PLY and OBJ writers (io/Mesh_writer.h).
#include "io/Mesh_writer.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>

#include "kernel/Error.h"

namespace extremal::io {

namespace {

std::string extension(const std::string& path) {
  const std::string base = std::filesystem::path(path).filename().string();
  const auto dot = base.find_last_of('.');
  if (dot == std::string::npos || dot == 0) return "";
  std::string e = base.substr(dot + 1);
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

struct File_closer {
  void operator()(std::FILE* f) const {
    if (f) std::fclose(f);
  }
};

// Buffered output with the file's name in every error.
class Output {
 public:
  Output(const std::string& path, const char* mode)
      : m_path(path), m_file(std::fopen(path.c_str(), mode)) {
    if (!m_file) fail("cannot open for writing");
    std::setvbuf(m_file.get(), nullptr, _IOFBF, 1 << 20);
  }
  void bytes(const void* data, std::size_t n) {
    if (std::fwrite(data, 1, n, m_file.get()) != n) fail("write failed");
  }
  void text(const char* s) { bytes(s, std::strlen(s)); }
  void close() {
    std::FILE* f = m_file.release();
    if (std::ferror(f)) {
      std::fclose(f);
      fail("write failed");
    }
    if (std::fclose(f) != 0) fail("write failed");
  }
  [[noreturn]] void fail(const char* what) const {
    const int e = errno;
    throw Invalid_input(m_path + ": " + what + (e ? std::string(": ") + std::strerror(e) : ""));
  }

 private:
  std::string m_path;
  std::unique_ptr<std::FILE, File_closer> m_file;
};

// Appends x in the shortest text that reads back to the same double.
char* put_double(char* at, char* end, double x) { return std::to_chars(at, end, x).ptr; }

char* put_int(char* at, char* end, long long x) { return std::to_chars(at, end, x).ptr; }

void put_le32(unsigned char* at, std::uint32_t x) {
  for (int k = 0; k < 4; ++k) at[k] = static_cast<unsigned char>(x >> (8 * k));
}

void put_float(unsigned char* at, double x) {
  const float f = static_cast<float>(x);
  std::uint32_t bits;
  std::memcpy(&bits, &f, 4);
  put_le32(at, bits);
}

void check_indices(const Triangle_mesh& mesh) {
  const long long n = static_cast<long long>(mesh.vertices.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int k : mesh.triangles[t])
      EXTREMAL_PRECONDITION_MSG(k >= 0 && k < n, "triangle " << t << " has vertex index " << k
                                                             << " of " << n << " vertices");
}

std::string one_line(std::string s) {
  std::replace(s.begin(), s.end(), '\n', ' ');
  std::replace(s.begin(), s.end(), '\r', ' ');
  return s;
}

void write_stl(Output& out, const Triangle_mesh& mesh, const std::string& comment) {
  EXTREMAL_PRECONDITION_MSG(mesh.triangles.size() <= 0xffffffffu,
                            "binary STL holds at most 2^32 - 1 triangles");
  unsigned char header[84] = {};
  // Readers take a header that starts with "solid" for ASCII STL.
  std::string h = "binary STL " + one_line(comment);
  std::memcpy(header, h.data(), std::min<std::size_t>(h.size(), 80));
  put_le32(header + 80, static_cast<std::uint32_t>(mesh.triangles.size()));
  out.bytes(header, 84);
  unsigned char facet[50] = {};
  for (const auto& t : mesh.triangles) {
    const Vec3 a = to_vec3(mesh.vertices[t[0]]), b = to_vec3(mesh.vertices[t[1]]),
               c = to_vec3(mesh.vertices[t[2]]);
    Vec3 n = (b - a).cross(c - a);
    const double len = n.norm();
    n = len > 0.0 ? Vec3(n / len) : Vec3::Zero();
    for (int k = 0; k < 3; ++k) {
      put_float(facet + 4 * k, n[k]);
      put_float(facet + 12 + 4 * k, a[k]);
      put_float(facet + 24 + 4 * k, b[k]);
      put_float(facet + 36 + 4 * k, c[k]);
    }
    out.bytes(facet, 50);
  }
}

void write_ply(Output& out, const Triangle_mesh& mesh, const std::string& comment) {
  out.text("ply\nformat ascii 1.0\ncomment ");
  out.text(one_line(comment).c_str());
  out.text(("\nelement vertex " + std::to_string(mesh.vertices.size()) +
            "\nproperty double x\nproperty double y\nproperty double z\nelement face " +
            std::to_string(mesh.triangles.size()) +
            "\nproperty list uchar int vertex_indices\nend_header\n")
               .c_str());
  char line[128];
  char* const end = line + sizeof line;
  for (const Point_3& p : mesh.vertices) {
    char* at = put_double(line, end, p.x());
    *at++ = ' ';
    at = put_double(at, end, p.y());
    *at++ = ' ';
    at = put_double(at, end, p.z());
    *at++ = '\n';
    out.bytes(line, static_cast<std::size_t>(at - line));
  }
  for (const auto& t : mesh.triangles) {
    char* at = line;
    *at++ = '3';
    for (int k : t) {
      *at++ = ' ';
      at = put_int(at, end, k);
    }
    *at++ = '\n';
    out.bytes(line, static_cast<std::size_t>(at - line));
  }
}

void write_obj(Output& out, const Triangle_mesh& mesh, const std::string& comment) {
  out.text("# ");
  out.text(one_line(comment).c_str());
  out.text("\n");
  char line[128];
  char* const end = line + sizeof line;
  for (const Point_3& p : mesh.vertices) {
    char* at = line;
    *at++ = 'v';
    for (double x : {p.x(), p.y(), p.z()}) {
      *at++ = ' ';
      at = put_double(at, end, x);
    }
    *at++ = '\n';
    out.bytes(line, static_cast<std::size_t>(at - line));
  }
  for (const auto& t : mesh.triangles) {
    char* at = line;
    *at++ = 'f';
    for (int k : t) {
      *at++ = ' ';
      at = put_int(at, end, static_cast<long long>(k) + 1);  // OBJ counts from 1
    }
    *at++ = '\n';
    out.bytes(line, static_cast<std::size_t>(at - line));
  }
}

}  // namespace

Mesh_file_format mesh_file_format(const std::string& path) {
  const std::string e = extension(path);
  if (e == "stl") return Mesh_file_format::Stl;
  if (e == "ply") return Mesh_file_format::Ply;
  if (e == "obj") return Mesh_file_format::Obj;
  throw Invalid_input(path + ": cannot write a mesh with " +
                      (e.empty() ? std::string("no extension") : "the extension '." + e + "'") +
                      " (use .stl, .ply or .obj)");
}

void check_writable(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path p(path);
  if (fs::is_directory(p, ec)) throw Invalid_input(path + ": cannot write: it is a folder");
  if (fs::exists(p, ec)) {
    if (::access(path.c_str(), W_OK) != 0)
      throw Invalid_input(path + ": cannot write: " + std::strerror(errno));
    return;
  }
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  if (!fs::is_directory(dir, ec))
    throw Invalid_input(path + ": cannot write: folder '" + dir.string() + "' does not exist");
  if (::access(dir.c_str(), W_OK) != 0)
    throw Invalid_input(path + ": cannot write in folder '" + dir.string() +
                        "': " + std::strerror(errno));
}

void write_mesh(const std::string& path, const Triangle_mesh& mesh, const std::string& comment) {
  const Mesh_file_format format = mesh_file_format(path);
  check_indices(mesh);
  errno = 0;
  Output out(path, format == Mesh_file_format::Stl ? "wb" : "w");
  switch (format) {
    case Mesh_file_format::Stl:
      write_stl(out, mesh, comment);
      break;
    case Mesh_file_format::Ply:
      write_ply(out, mesh, comment);
      break;
    case Mesh_file_format::Obj:
      write_obj(out, mesh, comment);
      break;
  }
  out.close();
}

}  // namespace extremal::io
