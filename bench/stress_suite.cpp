// The stress suite's long mode: every case of bench/experiments/Stress_cases run 100 times
// longer than in ctest (the drift case 10^6 steps at 1 kHz). Prints one Markdown row per case
// and exits non-zero if any case fails its tolerance, has a NaN or loses track.
// Usage: stress_suite [--short] [--seed N] [case ...]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "experiments/Stress_cases.h"

using namespace extremal::experiments;

int main(int argc, char** argv) {
  Stress_length length = Stress_length::Long;
  std::uint64_t seed = 20261123;
  if (const char* env = std::getenv("EXTREMAL_SEED")) seed = std::strtoull(env, nullptr, 10);
  std::vector<std::string> names;
  const std::vector<std::string> known = stress_case_names();
  auto usage = [&](FILE* to) {
    std::fprintf(to, "usage: stress_suite [--short] [--seed N] [case ...]\ncases:");
    for (const std::string& k : known) std::fprintf(to, " %s", k.c_str());
    std::fprintf(to, "\n");
  };
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--short")) {
      length = Stress_length::Short;
    } else if (!std::strcmp(argv[i], "--seed") && i + 1 < argc) {
      seed = std::strtoull(argv[++i], nullptr, 10);
    } else if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h")) {
      usage(stdout);
      return 0;
    } else if (std::find(known.begin(), known.end(), argv[i]) != known.end()) {
      names.push_back(argv[i]);
    } else {
      std::fprintf(stderr, "stress_suite: unknown argument or case '%s'\n", argv[i]);
      usage(stderr);
      return 2;
    }
  }
  if (names.empty()) names = known;
  std::printf("stress suite, %s mode, EXTREMAL_SEED=%llu\n\n",
              length == Stress_length::Long ? "long" : "short",
              static_cast<unsigned long long>(seed));
  std::printf("| case | steps | max error | tolerance | NaN | lost | reference | wall time (s) | result |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  int failed = 0;
  std::vector<std::string> issues;
  for (const std::string& n : names) {
    const Stress_result r = run_stress_case(n, length, seed);
    failed += !r.passed();
    if (!r.passed() && !r.known_issue.empty()) issues.push_back(r.name + ": " + r.known_issue);
    std::printf("| %s | %ld | %.2e | %.1e | %d | %d | %s | %.1f | %s |\n", r.name.c_str(), r.steps,
                r.max_error, r.tolerance, r.nan_count, r.lost_count, r.reference.c_str(),
                r.seconds, r.passed() ? "pass" : "FAIL");
    std::fflush(stdout);
  }
  std::printf("\n%d of %zu cases failed\n", failed, names.size());
  for (const std::string& i : issues) std::printf("- known issue, %s\n", i.c_str());
  return failed ? 1 : 0;
}
