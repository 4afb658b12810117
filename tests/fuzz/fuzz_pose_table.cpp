// libFuzzer target: the pose-table reader (io/Scene.h parse_pose_table) must never crash or trip
// a sanitizer, and what it accepts must be a usable motion; bad tables are Invalid_input.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

#include "io/Scene.h"
#include "kernel/Error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    const auto frames = extremal::io::parse_pose_table(in, "fuzz.csv");
    const extremal::Motion m =
        extremal::Motion::keyframes(frames, extremal::Motion::Type::Table);
    const double t = 0.5 * (frames.front().t + frames.back().t);
    const extremal::Rigid_pose_3 X = m.pose_at(t);
    if (!X.translation().allFinite() || !X.rotation().allFinite()) std::abort();
    (void)m.twist_at(t);
  } catch (const extremal::Invalid_input&) {
  }
  return 0;
}
