// read_occt in a child process (Readers.h, docs/import.md "Limits and containment").
//
// OpenCASCADE's readers are not written for hostile input: a malformed file can make them
// crash, loop or allocate without bound. The child is a fork of this process that runs
// read_occt and sends the model back through a pipe; the parent watches it: it kills the child
// when its resident memory grows by more than Import_limits::max_memory_mb or the reading takes
// longer than Import_limits::max_seconds, and turns a crash (a signal), an exception or a limit
// into an Invalid_input naming the file. Outside sanitizer builds the child also caps its own
// address space (the same amount), so that a single huge allocation fails at once.
// Sanitizer builds (EXTREMAL_SANITIZE, the fuzzers): a sanitizer report in the child (a memory
// error or undefined behaviour in our own code, which is instrumented) ends it with
// kSanitizerExit, and the parent aborts too, so that the finding is not contained.
#include "io/internal/Readers.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <new>
#include <sstream>

#include "kernel/Error.h"

#if defined(__SANITIZE_ADDRESS__)
#define EXTREMAL_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define EXTREMAL_SANITIZED 1
#endif
#endif
#ifdef EXTREMAL_SANITIZED
#include <sanitizer/common_interface_defs.h>
#endif

namespace extremal::io::internal {

namespace {

// How often the parent looks at the child's memory and the clock while it waits.
constexpr int kWatchIntervalMs = 20;
// The child's exit status when a sanitizer reported an error in it.
constexpr int kSanitizerExit = 86;
// OpenCASCADE's readers catch a failed allocation themselves and report a generic failure
// ("not a readable STEP file"): a failure in a child whose address space came within this much
// of its cap is reported as the memory limit instead (test_hostile_files,
// TinyMemoryLimitStopsTheReaderProcess).
constexpr long long kCapSlackBytes = 64LL << 20;

// ---- The model as bytes ---------------------------------------------------------------------

class Writer {
 public:
  void u8(std::uint8_t v) { m_out.push_back(static_cast<char>(v)); }
  void i64(std::int64_t v) { raw(&v, sizeof v); }
  void f64(double v) { raw(&v, sizeof v); }
  void str(const std::string& s) {
    i64(static_cast<std::int64_t>(s.size()));
    m_out.append(s);
  }
  void reals(const std::vector<double>& v) {
    i64(static_cast<std::int64_t>(v.size()));
    if (!v.empty()) raw(v.data(), v.size() * sizeof(double));
  }
  void points(const std::vector<Point_3>& v) {
    i64(static_cast<std::int64_t>(v.size()));
    for (const Point_3& p : v) {
      f64(p.x());
      f64(p.y());
      f64(p.z());
    }
  }
  void curve(const Nurbs_curve_3& c) {
    i64(c.degree());
    points(c.poles());
    reals(c.knots());
    reals(c.weights());
    u8(c.is_closed());
  }
  void surface(const Nurbs_surface_3& s) {
    i64(s.degree_u());
    i64(s.degree_v());
    i64(s.number_of_poles_u());
    i64(s.number_of_poles_v());
    points(s.poles());
    reals(s.knots_u());
    reals(s.knots_v());
    reals(s.weights());
    u8(s.is_closed_u());
    u8(s.is_closed_v());
    i64(s.outward_sign());
  }
  std::string& bytes() { return m_out; }

 private:
  void raw(const void* p, std::size_t n) { m_out.append(static_cast<const char*>(p), n); }
  std::string m_out;
};

class Reader {
 public:
  explicit Reader(const std::string& in) : m_in(in) {}
  std::uint8_t u8() {
    need(1);
    return static_cast<std::uint8_t>(m_in[m_pos++]);
  }
  std::int64_t i64() {
    std::int64_t v;
    raw(&v, sizeof v);
    return v;
  }
  double f64() {
    double v;
    raw(&v, sizeof v);
    return v;
  }
  std::size_t count(std::size_t item_bytes) {
    const std::int64_t n = i64();
    if (n < 0 || static_cast<std::uint64_t>(n) > (m_in.size() - m_pos) / item_bytes) corrupt();
    return static_cast<std::size_t>(n);
  }
  std::string str() {
    const std::size_t n = count(1);
    std::string s = m_in.substr(m_pos, n);
    m_pos += n;
    return s;
  }
  std::vector<double> reals() {
    std::vector<double> v(count(sizeof(double)));
    if (!v.empty()) raw(v.data(), v.size() * sizeof(double));
    return v;
  }
  std::vector<Point_3> points() {
    const std::size_t n = count(3 * sizeof(double));
    std::vector<Point_3> v;
    v.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double x = f64(), y = f64(), z = f64();
      v.emplace_back(x, y, z);
    }
    return v;
  }
  int small_int() {
    const std::int64_t v = i64();
    if (v < -1 || v > std::numeric_limits<int>::max()) corrupt();
    return static_cast<int>(v);
  }
  Nurbs_curve_3 curve() {
    const int degree = small_int();
    std::vector<Point_3> poles = points();
    std::vector<double> knots = reals();
    std::vector<double> weights = reals();
    Nurbs_curve_3 c(degree, std::move(poles), std::move(knots), std::move(weights));
    c.set_closed(u8() != 0);
    return c;
  }
  Nurbs_surface_3 surface() {
    const int du = small_int(), dv = small_int(), nu = small_int(), nv = small_int();
    std::vector<Point_3> poles = points();
    std::vector<double> ku = reals();
    std::vector<double> kv = reals();
    std::vector<double> w = reals();
    Nurbs_surface_3 s(du, dv, nu, nv, std::move(poles), std::move(ku), std::move(kv), std::move(w));
    const bool cu = u8() != 0, cv = u8() != 0;
    s.set_closed(cu, cv);
    s.set_outward_sign(static_cast<int>(i64()));
    return s;
  }
  bool done() const { return m_pos == m_in.size(); }
  [[noreturn]] static void corrupt() {
    throw Invalid_input("the reader process sent a malformed model");
  }

 private:
  void need(std::size_t n) const {
    if (n > m_in.size() - m_pos) corrupt();
  }
  void raw(void* p, std::size_t n) {
    need(n);
    std::memcpy(p, m_in.data() + m_pos, n);
    m_pos += n;
  }
  const std::string& m_in;
  std::size_t m_pos = 0;
};

// ---- The child ------------------------------------------------------------------------------

enum Frame : char { Model_frame = 'M', Invalid_frame = 'E', Precondition_frame = 'P',
                    Memory_frame = 'O', Other_frame = 'X' };

void write_all(int fd, const std::string& s) {
  std::size_t done = 0;
  while (done < s.size()) {
    const ssize_t n = ::write(fd, s.data() + done, s.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    done += static_cast<std::size_t>(n);
  }
}

long page_bytes() { return ::sysconf(_SC_PAGESIZE); }

// Field `field` (0: size, 1: resident) of /proc/<pid>/statm in bytes, or -1.
long long statm_bytes(pid_t pid, int field) {
  char path[64];
  std::snprintf(path, sizeof path, "/proc/%d/statm", static_cast<int>(pid));
  FILE* f = std::fopen(path, "r");
  if (!f) return -1;
  long long v[2] = {-1, -1};
  const int got = std::fscanf(f, "%lld %lld", &v[0], &v[1]);
  std::fclose(f);
  return got == 2 ? v[field] * page_bytes() : -1;
}

// The peak address-space size of this process (VmPeak), in bytes, or -1.
long long peak_address_space() {
  FILE* f = std::fopen("/proc/self/status", "r");
  if (!f) return -1;
  char line[256];
  long long kib = -1;
  while (std::fgets(line, sizeof line, f))
    if (std::sscanf(line, "VmPeak: %lld kB", &kib) == 1) break;
  std::fclose(f);
  return kib < 0 ? -1 : kib * 1024;
}

[[noreturn]] void run_child(int fd, pid_t parent, const std::string& path, Model_format format,
                            const Read_options& options, const Cad_scan& scan, Model model) {
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != parent) ::_exit(1);
  // A crash ends the child with its signal, which the parent reports (a sanitizer's handler
  // would print a report for a fault in OpenCASCADE's uninstrumented code instead).
  for (const int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL}) ::signal(sig, SIG_DFL);
#ifdef EXTREMAL_SANITIZED
  __sanitizer_set_death_callback([] { ::_exit(kSanitizerExit); });
#endif
  // At most max_memory_mb more address space than the child starts with.
  long long cap = 0;
#ifndef EXTREMAL_SANITIZED
  const long long size = statm_bytes(::getpid(), 0);
  if (options.limits.max_memory_mb > 0 && size > 0) {
    cap = size + static_cast<long long>(options.limits.max_memory_mb) * (1LL << 20);
    const rlimit r{static_cast<rlim_t>(cap), static_cast<rlim_t>(cap)};
    if (::setrlimit(RLIMIT_AS, &r) != 0) cap = 0;
  }
#endif
  const auto at_cap = [cap] {
    const long long peak = cap > 0 ? peak_address_space() : -1;
    return peak > 0 && peak >= cap - kCapSlackBytes;
  };
  std::string frame(8, '\0');  // the payload's length, then a Frame tag and the payload
  try {
    read_occt(path, format, options, scan, model);
    frame += static_cast<char>(Model_frame);
    frame += encode_model(model);
  } catch (const Invalid_input& e) {
    frame += static_cast<char>(at_cap() ? Memory_frame : Invalid_frame);
    if (frame.back() == Invalid_frame) frame += e.what();
  } catch (const Precondition_violation& e) {
    frame += static_cast<char>(at_cap() ? Memory_frame : Precondition_frame);
    if (frame.back() == Precondition_frame) frame += e.what();
  } catch (const std::bad_alloc&) {
    frame.resize(8);
    frame += static_cast<char>(Memory_frame);
  } catch (const std::exception& e) {
    frame += static_cast<char>(Other_frame);
    frame += e.what();
  } catch (...) {
    frame += static_cast<char>(Other_frame);
    frame += "an unknown exception";
  }
  const std::uint64_t n = frame.size() - 8;
  std::memcpy(frame.data(), &n, 8);
  write_all(fd, frame);
  ::close(fd);
  ::_exit(0);
}

std::string signal_text(int sig) {
  const char* d = ::strsignal(sig);
  return "signal " + std::to_string(sig) + (d ? std::string(", ") + d : std::string());
}

std::string mib(std::size_t n) { return std::to_string(n) + " MiB"; }

}  // namespace

std::string encode_model(const Model& m) {
  Writer w;
  w.i64(static_cast<std::int64_t>(m.format));
  w.str(m.format_name);
  w.str(m.file_unit);
  w.str(m.unit);
  w.f64(m.scale_to_unit);
  w.i64(static_cast<std::int64_t>(m.skipped.size()));
  for (const Skipped_entity& s : m.skipped) {
    w.str(s.entity);
    w.str(s.reason);
    w.str(s.action);
  }
  w.i64(static_cast<std::int64_t>(m.warnings.size()));
  for (const std::string& s : m.warnings) w.str(s);
  w.i64(static_cast<std::int64_t>(m.bodies.size()));
  for (const Body& b : m.bodies) {
    w.str(b.name);
    w.str(b.source_name);
    w.u8(b.is_point);
    const Mat3& R = b.placement.rotation();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) w.f64(R(i, j));
    for (int i = 0; i < 3; ++i) w.f64(b.placement.translation()(i));
    w.i64(static_cast<std::int64_t>(b.faces.size()));
    for (const Face& f : b.faces) {
      w.surface(f.surface);
      w.str(f.kind);
      w.str(f.source);
      w.f64(f.approximation_error);
      w.f64(f.trim_region.tolerance());
      w.i64(static_cast<std::int64_t>(f.trims.size()));
      for (const Trim_loop& loop : f.trims) {
        w.u8(loop.is_outer);
        w.i64(static_cast<std::int64_t>(loop.curves.size()));
        for (const Trim_curve& tc : loop.curves) {
          w.curve(tc.uv);
          w.i64(tc.edge);
          w.u8(tc.reversed);
        }
      }
    }
    w.i64(static_cast<std::int64_t>(b.curves.size()));
    for (const Nurbs_curve_3& c : b.curves) w.curve(c);
    w.i64(static_cast<std::int64_t>(b.edges.size()));
    for (const Edge& e : b.edges) {
      w.u8(e.curve.has_value());
      if (e.curve) w.curve(*e.curve);
      w.u8(e.degenerate);
      w.f64(e.t_min);
      w.f64(e.t_max);
      w.u8(e.same_parameter);
      w.f64(e.tolerance);
      w.i64(static_cast<std::int64_t>(e.uses.size()));
      for (const Edge_use& u : e.uses) {
        w.i64(u.face);
        w.i64(u.loop);
        w.i64(u.curve);
      }
    }
    w.points(b.mesh.vertices);
    w.i64(static_cast<std::int64_t>(b.mesh.triangles.size()));
    for (const auto& t : b.mesh.triangles)
      for (int k = 0; k < 3; ++k) w.i64(t[k]);
  }
  return std::move(w.bytes());
}

Model decode_model(const std::string& bytes) {
  Reader r(bytes);
  Model m;
  m.format = static_cast<Model_format>(r.small_int());
  m.format_name = r.str();
  m.file_unit = r.str();
  m.unit = r.str();
  m.scale_to_unit = r.f64();
  for (std::size_t n = r.count(24); n > 0; --n) {
    Skipped_entity s;
    s.entity = r.str();
    s.reason = r.str();
    s.action = r.str();
    m.skipped.push_back(std::move(s));
  }
  for (std::size_t n = r.count(8); n > 0; --n) m.warnings.push_back(r.str());
  for (std::size_t n = r.count(8); n > 0; --n) {
    Body b;
    b.name = r.str();
    b.source_name = r.str();
    b.is_point = r.u8() != 0;
    Mat3 R;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) R(i, j) = r.f64();
    Vec3 t;
    for (int i = 0; i < 3; ++i) t(i) = r.f64();
    b.placement = Rigid_pose_3(R, t);
    for (std::size_t nf = r.count(8); nf > 0; --nf) {
      Nurbs_surface_3 s = r.surface();
      std::string kind = r.str();
      Face f(std::move(s), std::move(kind));
      f.source = r.str();
      f.approximation_error = r.f64();
      const double trim_tolerance = r.f64();
      for (std::size_t nl = r.count(9); nl > 0; --nl) {
        Trim_loop loop;
        loop.is_outer = r.u8() != 0;
        for (std::size_t nc = r.count(8); nc > 0; --nc) {
          Nurbs_curve_3 uv = r.curve();
          const int edge = r.small_int();
          const bool reversed = r.u8() != 0;
          loop.curves.push_back(Trim_curve{std::move(uv), edge, reversed});
        }
        f.trims.push_back(std::move(loop));
      }
      f.update_trim_region(trim_tolerance);
      b.faces.push_back(std::move(f));
    }
    for (std::size_t nc = r.count(8); nc > 0; --nc) b.curves.push_back(r.curve());
    for (std::size_t ne = r.count(8); ne > 0; --ne) {
      Edge e;
      if (r.u8() != 0) e.curve = r.curve();
      e.degenerate = r.u8() != 0;
      e.t_min = r.f64();
      e.t_max = r.f64();
      e.same_parameter = r.u8() != 0;
      e.tolerance = r.f64();
      for (std::size_t nu = r.count(24); nu > 0; --nu) {
        Edge_use u;
        u.face = r.small_int();
        u.loop = r.small_int();
        u.curve = r.small_int();
        e.uses.push_back(u);
      }
      b.edges.push_back(std::move(e));
    }
    b.mesh.vertices = r.points();
    for (std::size_t nt = r.count(24); nt > 0; --nt) {
      std::array<int, 3> t3{};
      for (int k = 0; k < 3; ++k) t3[k] = r.small_int();
      b.mesh.triangles.push_back(t3);
    }
    m.bodies.push_back(std::move(b));
  }
  if (!r.done()) Reader::corrupt();
  return m;
}

void read_occt_isolated(const std::string& path, const std::string& name, Model_format format,
                        const Read_options& options, const Cad_scan& scan, Model& model) {
  const Import_limits& limits = options.limits;
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0)
    throw Invalid_input(name + ": cannot start the reader process (pipe: " +
                        std::strerror(errno) + ")");
  const long long baseline = statm_bytes(::getpid(), 1);
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int err = errno;
    ::close(fds[0]);
    ::close(fds[1]);
    throw Invalid_input(name + ": cannot start the reader process (fork: " + std::strerror(err) +
                        ")");
  }
  if (pid == 0) {
    ::close(fds[0]);
    run_child(fds[1], parent, path, format, options, scan, model);
  }
  ::close(fds[1]);

  enum class Stop { None, Memory, Time } stop = Stop::None;
  const auto start = std::chrono::steady_clock::now();
  const long long memory_cap = static_cast<long long>(limits.max_memory_mb) << 20;
  std::string buf;
  char chunk[1 << 16];
  auto last_check = start;
  while (true) {
    pollfd p{fds[0], POLLIN, 0};
    const int r = ::poll(&p, 1, kWatchIntervalMs);
    if (r > 0) {
      const ssize_t n = ::read(fds[0], chunk, sizeof chunk);
      if (n > 0) buf.append(chunk, static_cast<std::size_t>(n));
      else if (n == 0) break;  // the child closed its end: it is done or dead
      else if (errno != EINTR && errno != EAGAIN) break;
    } else if (r < 0 && errno != EINTR) {
      break;
    }
    const auto now = std::chrono::steady_clock::now();
    if (now - last_check < std::chrono::milliseconds(kWatchIntervalMs)) continue;
    last_check = now;
    const long long rss = statm_bytes(pid, 1);
    if (limits.max_memory_mb > 0 && rss > 0 && baseline > 0 && rss - baseline > memory_cap) {
      stop = Stop::Memory;
      break;
    }
    if (limits.max_seconds > 0 &&
        std::chrono::duration<double>(now - start).count() > limits.max_seconds) {
      stop = Stop::Time;
      break;
    }
  }
  ::close(fds[0]);
  if (stop != Stop::None) ::kill(pid, SIGKILL);
  int status = 0;
  pid_t waited;
  do {
    waited = ::waitpid(pid, &status, 0);
  } while (waited < 0 && errno == EINTR);

  const std::string what = format == Model_format::Step ? "STEP" : format == Model_format::Iges ? "IGES" : "BREP";
  if (stop == Stop::Memory)
    throw Invalid_input(name + ": reading needs more than " + mib(limits.max_memory_mb) +
                        " of memory, the limit (Import_limits::max_memory_mb, extremal "
                        "--import-memory-mb)");
  if (stop == Stop::Time) {
    std::ostringstream os;
    os << name << ": reading takes longer than " << limits.max_seconds
       << " s, the limit (Import_limits::max_seconds, extremal --import-seconds)";
    throw Invalid_input(os.str());
  }
#ifdef EXTREMAL_SANITIZED
  if (waited == pid && WIFEXITED(status) && WEXITSTATUS(status) == kSanitizerExit) {
    std::fprintf(stderr, "extremal: a sanitizer reported an error in the reader process for %s "
                         "(report above)\n", name.c_str());
    std::abort();
  }
#endif
  std::uint64_t length = 0;
  const bool complete = buf.size() > 8 && (std::memcpy(&length, buf.data(), 8), length == buf.size() - 8);
  if (!complete || (waited == pid && !(WIFEXITED(status) && WEXITSTATUS(status) == 0))) {
    if (waited == pid && WIFSIGNALED(status))
      throw Invalid_input(name + ": OpenCASCADE's " + what + " reader crashed on this file (" +
                          signal_text(WTERMSIG(status)) + "); the file is malformed or beyond "
                          "what OpenCASCADE reads");
    if (waited == pid && WIFEXITED(status) && WEXITSTATUS(status) != 0)
      throw Invalid_input(name + ": the " + what + " reader process failed (exit status " +
                          std::to_string(WEXITSTATUS(status)) + ")");
    throw Invalid_input(name + ": the " + what + " reader process ended without a result");
  }
  const char tag = buf[8];
  const std::string payload = buf.substr(9);
  switch (tag) {
    case Model_frame: {
      Model read = decode_model(payload);
      read.file = model.file;
      model = std::move(read);
      return;
    }
    case Invalid_frame: throw Invalid_input(payload);
    case Precondition_frame: throw Precondition_violation(payload);
    case Memory_frame:
      if (limits.max_memory_mb == 0) throw Invalid_input(name + ": reading ran out of memory");
      throw Invalid_input(name + ": reading needs more than " + mib(limits.max_memory_mb) +
                          " of memory, the limit (an allocation failed; Import_limits::"
                          "max_memory_mb, extremal --import-memory-mb)");
    default:
      throw Invalid_input(name + ": the " + what + " reader failed: " + payload);
  }
}

}  // namespace extremal::io::internal
