// The body of the STEP and IGES fuzz targets: the input goes to a file (one per process, reused)
// and through io::read_model exactly as `extremal info FILE` reads it: the scan of the text,
// then OpenCASCADE in its child process (io/internal/Isolated_reader.cpp). Any input must give
// a model or an Invalid_input naming the file; a crash, a sanitizer report (in this process, or
// in the reader's child, which aborts this one), a leak or a Precondition_violation is a bug.
// The limits are lowered so that a slow or greedy reading is refused well inside libFuzzer's
// -timeout=10 and -rss_limit_mb.
#pragma once

#include <sys/types.h>
#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "io/Model_reader.h"
#include "kernel/Error.h"
#include "Use_model.h"

namespace extremal::fuzz {

// Wall-clock and memory limits of one reading under fuzzing (libFuzzer's -timeout is 10 s).
constexpr double kFuzzReadSeconds = 5.0;
constexpr std::size_t kFuzzReadMemoryMb = 1024;

class Scratch_file {
 public:
  explicit Scratch_file(const char* ext) {
    const char* dir = std::getenv("TMPDIR");
    std::string templ = std::string(dir && *dir ? dir : "/tmp") + "/extremal-fuzz-XXXXXX." + ext;
    std::vector<char> buf(templ.begin(), templ.end());
    buf.push_back('\0');
    const int fd = ::mkstemps(buf.data(), static_cast<int>(std::string(ext).size() + 1));
    if (fd < 0) {
      std::perror("fuzz: cannot create the scratch file");
      std::abort();
    }
    ::close(fd);
    m_path = buf.data();
  }
  ~Scratch_file() { std::remove(m_path.c_str()); }

  const std::string& write(const std::uint8_t* data, std::size_t size) {
    std::FILE* f = std::fopen(m_path.c_str(), "wb");
    if (!f || (size > 0 && std::fwrite(data, 1, size, f) != size) || std::fclose(f) != 0) {
      std::perror("fuzz: cannot write the scratch file");
      std::abort();
    }
    return m_path;
  }

 private:
  std::string m_path;
};

inline int read_cad_file(const std::uint8_t* data, std::size_t size, io::Model_format format,
                         const char* ext) {
  static Scratch_file file(ext);
  const std::string& path = file.write(data, size);
  io::Read_options options;
  options.format = format;
  options.limits.max_seconds = kFuzzReadSeconds;
  options.limits.max_memory_mb = kFuzzReadMemoryMb;
  try {
    const io::Model m = io::read_model(path, options);
    use_model(m);
  } catch (const Invalid_input& e) {
    // Every refusal names the file.
    if (std::string(e.what()).find(path) == std::string::npos) {
      std::fprintf(stderr, "fuzz: an error that does not name the file: %s\n", e.what());
      std::abort();
    }
  }
  return 0;
}

}  // namespace extremal::fuzz
