// libFuzzer target: the scene reader (io/Scene.h) must never crash or trip a sanitizer; bad
// scenes are Invalid_input. File entries are not loaded (no loader), so only the JSON is fuzzed.
#include <cstddef>
#include <cstdint>
#include <string>

#include "io/Scene.h"
#include "kernel/Error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const extremal::io::Scene s = extremal::io::parse_scene(text, "fuzz.json");
    if (s.step > 0.0 && s.step_count() < 1000000) (void)s.time_of(s.step_count() - 1);
  } catch (const extremal::Invalid_input&) {
  }
  return 0;
}
