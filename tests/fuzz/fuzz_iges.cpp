// libFuzzer target: IGES files through the import layer (Cad_file_target.h).
#include "Cad_file_target.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return extremal::fuzz::read_cad_file(data, size, extremal::io::Model_format::Iges, "igs");
}
