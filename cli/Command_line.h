// The `extremal` command line parsed into the subcommands' options, without running anything:
// main() runs the command it names, the fuzz target tests/fuzz/fuzz_cli_options.cpp parses
// arbitrary argument vectors. Contract: docs/cli.md.
#pragma once

#include <optional>
#include <ostream>

#include "cli/Commands.h"
#include "io/Model_reader.h"

namespace extremal::cli {

struct Command_line {
  enum class Command { None, Info, Distance, Report, Tessellate };
  Command command = Command::None;
  Info_options info;
  Distance_options distance;
  Report_options report;
  Tessellate_options tessellate;
  // --max-patch-poles, --max-total-poles, --import-memory-mb, --import-seconds.
  io::Import_limits limits;
  // Set when parsing ends the run: 0 after --help (the help went to `out`), 2 for a usage error
  // (the message went to `err`).
  std::optional<int> exit_code;
};

// Parses argv[1..argc-1] (argv[0] is the program name). Never throws for any argument vector.
Command_line parse_command_line(int argc, const char* const* argv, std::ostream& out,
                                std::ostream& err);

}  // namespace extremal::cli
