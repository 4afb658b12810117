// Seeded randomness for tests: the seed is printed, and EXTREMAL_SEED sets it to reproduce.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <random>

namespace extremal::test {

inline std::uint64_t test_seed(std::uint64_t fallback = 20261123) {
  const char* env = std::getenv("EXTREMAL_SEED");
  const std::uint64_t seed = env ? std::strtoull(env, nullptr, 10) : fallback;
  std::cout << "[ seed     ] EXTREMAL_SEED=" << seed << "\n";
  return seed;
}

inline std::mt19937_64 seeded_rng(std::uint64_t fallback = 20261123) {
  return std::mt19937_64(test_seed(fallback));
}

}  // namespace extremal::test
