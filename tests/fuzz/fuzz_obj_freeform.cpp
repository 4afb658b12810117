// libFuzzer target: the OBJ free-form reader must never crash, hang or trip a sanitizer on any
// input; unreadable input is an Invalid_input, anything else a model whose faces, trims and
// boxes are usable. A Precondition_violation escaping here is a bug (it aborts the run).
#include <cstddef>
#include <cstdint>
#include <string>

#include "io/Model_reader.h"
#include "kernel/Error.h"
#include "Use_model.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  extremal::io::Read_options options;
  options.format = extremal::io::Model_format::Obj_freeform;
  try {
    const extremal::io::Model m = extremal::io::read_model_from_memory("fuzz.obj", text, options);
    extremal::fuzz::use_model(m);
  } catch (const extremal::Invalid_input&) {
  }
  return 0;
}
