// Errors. Invalid input throws Invalid_input with a message naming what is wrong; API misuse
// (parameter outside a domain, negative gain) throws Precondition_violation with the expression,
// file and line. Numerical trouble is never an exception: it is a status in a result.
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

namespace extremal {

class Invalid_input : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

class Precondition_violation : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

namespace internal {
[[noreturn]] inline void throw_precondition(const char* expr, const char* file, int line,
                                            const std::string& detail) {
  std::ostringstream os;
  os << "precondition violated: " << expr << " (" << file << ":" << line << ")";
  if (!detail.empty()) os << ": " << detail;
  throw Precondition_violation(os.str());
}
}  // namespace internal

}  // namespace extremal

// Always on, including release builds: the checks are cheap next to the work they guard.
#define EXTREMAL_PRECONDITION(expr)                                                    \
  do {                                                                                 \
    if (!(expr)) ::extremal::internal::throw_precondition(#expr, __FILE__, __LINE__, ""); \
  } while (false)

#define EXTREMAL_PRECONDITION_MSG(expr, msg)                                          \
  do {                                                                                \
    if (!(expr)) {                                                                    \
      std::ostringstream extremal_os_;                                                \
      extremal_os_ << msg;                                                            \
      ::extremal::internal::throw_precondition(#expr, __FILE__, __LINE__, extremal_os_.str()); \
    }                                                                                 \
  } while (false)
