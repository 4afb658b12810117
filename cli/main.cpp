// The `extremal` command: batch distance reports, one-shot distances, file information,
// tessellation.
// Contract: docs/cli.md.
#include <iostream>

#include "cli/Command_line.h"
#include "io/Model_reader.h"

int main(int argc, char** argv) {
  using extremal::cli::Command_line;
  const Command_line cl = extremal::cli::parse_command_line(argc, argv, std::cout, std::cerr);
  if (cl.exit_code) return *cl.exit_code;
  extremal::io::set_default_import_limits(cl.limits);
  switch (cl.command) {
    case Command_line::Command::Info: return extremal::cli::run_info(cl.info);
    case Command_line::Command::Distance: return extremal::cli::run_distance(cl.distance);
    case Command_line::Command::Report: return extremal::cli::run_report(cl.report);
    case Command_line::Command::Tessellate: return extremal::cli::run_tessellate(cl.tessellate);
    case Command_line::Command::None: break;
  }
  return 2;
}
