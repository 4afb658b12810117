// Numerical-stability stress suite (ctest label `stress`): the short run of every case in
// bench/experiments/Stress_cases (bench/stress_suite runs them 100 times longer). Each case
// asserts its maximum error against its reference, no NaN and no lost track.
#include <gtest/gtest.h>

#include <cstdio>

#include "experiments/Stress_cases.h"
#include "support/Random.h"

namespace extremal {
namespace {

class Stress : public ::testing::TestWithParam<std::string> {};

TEST_P(Stress, ExactNoNanNoLostTrack) {
  const auto seed = test::test_seed();
  const experiments::Stress_result r =
      experiments::run_stress_case(GetParam(), experiments::Stress_length::Short, seed);
  std::printf("[ case     ] %-48s %7ld steps  max error %.2e (tolerance %.1e)  NaN %d  lost %d  "
              "(%s)\n",
              r.name.c_str(), r.steps, r.max_error, r.tolerance, r.nan_count, r.lost_count,
              r.reference.c_str());
  if (!r.known_issue.empty() && !r.passed())
    GTEST_SKIP() << "known issue: " << r.known_issue;
  EXPECT_GT(r.steps, 0);
  EXPECT_EQ(r.nan_count, 0);
  EXPECT_EQ(r.lost_count, 0);
  EXPECT_LE(r.max_error, r.tolerance);
}

INSTANTIATE_TEST_SUITE_P(Cases, Stress, ::testing::ValuesIn(experiments::stress_case_names()),
                         [](const auto& info) {
                           std::string n = info.param;
                           for (char& c : n)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return n;
                         });

}  // namespace
}  // namespace extremal
