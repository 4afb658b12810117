// Per-pair report summaries: minimum and when, contact, penetration and farther intervals,
// deepest penetration, from a known sequence of rows.
#include <gtest/gtest.h>

#include "io/Pair_summary.h"

namespace extremal {
namespace {

using io::Clearance_state;

TEST(PairSummary, IntervalsMinimumAndDeepestFromKnownRows) {
  struct Row {
    double t, d;
    Clearance_state s;
  };
  const Row rows[] = {
      {0.0, 9.0, Clearance_state::Farther},     {0.1, 8.0, Clearance_state::Farther},
      {0.2, 2.0, Clearance_state::Apart},       {0.3, 0.0, Clearance_state::Contact},
      {0.4, -0.5, Clearance_state::Penetrating}, {0.5, -0.7, Clearance_state::Penetrating},
      {0.6, -0.7, Clearance_state::Penetrating}, {0.7, 0.0, Clearance_state::Contact},
      {0.8, 1.0, Clearance_state::Apart},       {0.9, -0.1, Clearance_state::Penetrating},
      {1.0, 7.0, Clearance_state::Farther}};
  io::Pair_summary_builder b;
  for (const Row& r : rows) b.add(r.t, r.d, r.s);
  const io::Pair_summary& s = b.summary();
  EXPECT_EQ(s.rows, 11);
  EXPECT_EQ(s.tracked_rows, 8);
  ASSERT_TRUE(s.min_distance);
  EXPECT_EQ(*s.min_distance, -0.7);
  EXPECT_EQ(s.min_time, 0.5);  // the first time the minimum occurred
  ASSERT_TRUE(s.deepest_penetration);
  EXPECT_EQ(*s.deepest_penetration, 0.7);
  EXPECT_EQ(s.deepest_time, 0.5);
  ASSERT_EQ(s.contact.size(), 2u);  // touching or inside
  EXPECT_EQ(s.contact[0].start, 0.3);
  EXPECT_EQ(s.contact[0].end, 0.7);
  EXPECT_EQ(s.contact[1].start, 0.9);
  EXPECT_EQ(s.contact[1].end, 0.9);
  ASSERT_EQ(s.penetration.size(), 2u);
  EXPECT_EQ(s.penetration[0].start, 0.4);
  EXPECT_EQ(s.penetration[0].end, 0.6);
  EXPECT_EQ(s.penetration[1].start, 0.9);
  ASSERT_EQ(s.farther.size(), 2u);
  EXPECT_EQ(s.farther[0].start, 0.0);
  EXPECT_EQ(s.farther[0].end, 0.1);
  EXPECT_EQ(s.farther[1].start, 1.0);
}

TEST(PairSummary, AlwaysFartherHasNoMinimumAndNeverTouching) {
  io::Pair_summary_builder b;
  b.add(0.0, 5.0, Clearance_state::Farther);
  b.add(1.0, 4.0, Clearance_state::Farther);
  EXPECT_FALSE(b.summary().min_distance);
  EXPECT_FALSE(b.summary().deepest_penetration);
  EXPECT_TRUE(b.summary().contact.empty());
  ASSERT_EQ(b.summary().farther.size(), 1u);
  EXPECT_EQ(b.summary().farther[0].end, 1.0);
}

TEST(PairSummary, UncertifiedRowsAreApartAndRunInIntervals) {
  io::Pair_summary_builder b;
  b.add(0.0, 2.0, Clearance_state::Apart);
  b.add(0.1, 1.0, Clearance_state::Uncertified);
  b.add(0.2, 1.5, Clearance_state::Uncertified);
  b.add(0.3, 3.0, Clearance_state::Apart);
  b.add(0.4, 3.5, Clearance_state::Uncertified);
  const io::Pair_summary& s = b.summary();
  EXPECT_EQ(s.tracked_rows, 5);
  EXPECT_EQ(*s.min_distance, 1.0);  // an uncertified row's distance is still a reading
  EXPECT_EQ(s.min_time, 0.1);
  ASSERT_EQ(s.uncertified.size(), 2u);
  EXPECT_EQ(s.uncertified[0].start, 0.1);
  EXPECT_EQ(s.uncertified[0].end, 0.2);
  EXPECT_EQ(s.uncertified[1].start, 0.4);
  EXPECT_TRUE(s.contact.empty());
}

}  // namespace
}  // namespace extremal
