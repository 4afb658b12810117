// libFuzzer target: the `extremal` command line parser (cli/Command_line.h) on any argument
// vector. The input is split at newlines into arguments (at most kMaxArguments); parsing runs
// no command. It must never throw, and must end either in a command or in exit code 0 (help)
// or 2 (usage error, with a message).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "cli/Command_line.h"

namespace {
// Arguments taken from one input: more only repeats what a shorter vector exercises.
constexpr std::size_t kMaxArguments = 64;
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> args{"extremal"};
  std::size_t pos = 0;
  while (pos <= text.size() && args.size() <= kMaxArguments) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    args.push_back(text.substr(pos, end - pos));
    pos = end + 1;
  }
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  std::ostringstream out, err;
  using extremal::cli::Command_line;
  const Command_line cl =
      extremal::cli::parse_command_line(static_cast<int>(argv.size()), argv.data(), out, err);
  const bool ran = cl.command != Command_line::Command::None;
  const bool ended = cl.exit_code.has_value();
  if (ran == ended || (ended && *cl.exit_code != 0 && *cl.exit_code != 2) ||
      (ended && *cl.exit_code == 2 && err.str().empty())) {
    std::fprintf(stderr, "fuzz: parse ended with command %d, exit code %d, error '%s'\n",
                 static_cast<int>(cl.command), ended ? *cl.exit_code : -1, err.str().c_str());
    std::abort();
  }
  return 0;
}
