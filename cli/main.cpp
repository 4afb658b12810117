// The `extremal` command: batch distance reports, one-shot distances, file information.
// Contract: ../shared/CLI.md.
#include <iostream>

#include <CLI/CLI.hpp>

#include "cli/Commands.h"

int main(int argc, char** argv) {
  CLI::App app{"Extremal: exact distances between moving NURBS bodies"};
  app.require_subcommand(1);

  extremal::cli::Info_options info;
  CLI::App* info_cmd = app.add_subcommand("info", "What a file or shape spec holds");
  info_cmd->add_option("FILE", info.target, "CAD/mesh file or shape spec (e.g. sphere:1)")
      ->required();
  info_cmd->add_flag("--json", info.json, "JSON output");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI11 maps --help to success and real usage errors to non-zero; ours is 2.
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  if (info_cmd->parsed()) return extremal::cli::run_info(info);
  return 2;
}
