// Seeded randomness for tests: the seed is printed, and EXTREMAL_SEED sets it to reproduce.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <random>

#include <Eigen/Geometry>

#include "kernel/Rigid_pose_3.h"

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

// A uniformly random rotation (a normalised Gaussian quaternion) and a translation with
// coordinates uniform in [-spread, spread].
inline Rigid_pose_3 random_pose(std::mt19937_64& rng, double spread) {
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(-spread, spread);
  const Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
  return Rigid_pose_3::from_quaternion(Vec3(u(rng), u(rng), u(rng)), q.w(), q.x(), q.y(), q.z());
}

}  // namespace extremal::test
