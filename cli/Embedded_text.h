// Text files the build embeds in the command (cli/CMakeLists.txt, cli/embed_text.cpp): Debian's
// libjs-three scripts that `extremal report -o OUT.html` inlines, so neither the command nor
// the page it writes needs anything else at run time.
#pragma once

#include <string>
#include <vector>

namespace extremal::cli {

struct Embedded_text {
  std::string name;  // the file's name, e.g. "three.min.js"
  std::string text;  // its bytes
};

// The files in the order the build listed them.
const std::vector<Embedded_text>& embedded_texts();

}  // namespace extremal::cli
