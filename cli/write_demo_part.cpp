// Writes the demo's generated part (kernel/Bracket.h) as STEP through io/Step_writer.h:
//   build/cli/write_demo_part data/demo/bracket.step
// The build runs it (target demo_part, cli/CMakeLists.txt): the file is generated, not kept in
// git. test_step_writer checks that the file on disk is what the generator writes now.
#include <iostream>

#include "io/Step_writer.h"
#include "kernel/Bracket.h"
#include "kernel/Error.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: write_demo_part OUT.step\n";
    return 2;
  }
  try {
    extremal::io::Step_write_options options;
    options.file_name = "bracket.step";
    extremal::io::write_step(argv[1], {extremal::make_bracket_body()}, options);
  } catch (const extremal::Invalid_input& e) {
    std::cerr << "write_demo_part: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
