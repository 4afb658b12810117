// The clearance class of a pair from its rows' bounds (io/Clearance_class.h, docs/cli.md
// "Clearance classes"): known rows and the class, range and undecided spans they must give.
#include <gtest/gtest.h>

#include <limits>

#include "io/Clearance_class.h"

namespace extremal {
namespace {

using io::Clearance_class;
using io::Clearance_state;

const io::Clearance_thresholds k_with_clearance{1e-9, 2.0};
const io::Clearance_thresholds k_without_clearance{1e-9, std::nullopt};

TEST(ClearanceClass, ThresholdsOfADistance) {
  const auto& t = k_with_clearance;
  EXPECT_EQ(io::class_of_distance(-0.5, t), Clearance_class::Clash);
  EXPECT_EQ(io::class_of_distance(-1e-9, t), Clearance_class::Contact);  // |x| <= contact
  EXPECT_EQ(io::class_of_distance(1e-9, t), Clearance_class::Contact);
  EXPECT_EQ(io::class_of_distance(1.5, t), Clearance_class::Clearance);
  EXPECT_EQ(io::class_of_distance(2.0, t), Clearance_class::Clear);  // not closer than D
  EXPECT_EQ(io::class_of_distance(1.5, k_without_clearance), Clearance_class::Clear);
}

TEST(ClearanceClass, RowsProveTheUpperEndAndLeaveTheLowerEndOpen) {
  const auto& t = k_with_clearance;
  // Apart: the distance (a real pair) proves, the lower bound leaves open.
  io::Class_range r = io::row_class(Clearance_state::Apart, 3.0, 2.5, t);
  EXPECT_EQ(r.proven, Clearance_class::Clear);
  EXPECT_EQ(r.possible, Clearance_class::Clear);
  r = io::row_class(Clearance_state::Apart, 2.0 + 1e-10, 2.0 - 1e-10, t);
  EXPECT_EQ(r.proven, Clearance_class::Clear);
  EXPECT_EQ(r.possible, Clearance_class::Clearance);
  // An uncertified row's lower bound may be far below its distance.
  r = io::row_class(Clearance_state::Uncertified, 1.0, -0.1, t);
  EXPECT_EQ(r.proven, Clearance_class::Clearance);
  EXPECT_EQ(r.possible, Clearance_class::Clash);
  // No bound, or a NaN one, leaves every class open; a NaN distance proves nothing.
  r = io::row_class(Clearance_state::Apart, 5.0, std::nullopt, t);
  EXPECT_EQ(r.possible, Clearance_class::Clash);
  r = io::row_class(Clearance_state::Apart, 5.0, std::numeric_limits<double>::quiet_NaN(), t);
  EXPECT_EQ(r.possible, Clearance_class::Clash);
  r = io::row_class(Clearance_state::Apart, std::numeric_limits<double>::quiet_NaN(), 1.0, t);
  EXPECT_EQ(r.proven, Clearance_class::Clear);
  EXPECT_EQ(r.possible, Clearance_class::Clash);
  // Farther: the boxes' bound below, nothing above.
  r = io::row_class(Clearance_state::Farther, 7.0, 7.0, t);
  EXPECT_EQ(r.proven, Clearance_class::Clear);
  EXPECT_EQ(r.possible, Clearance_class::Clear);
  r = io::row_class(Clearance_state::Farther, 1.0, 1.0, t);
  EXPECT_EQ(r.possible, Clearance_class::Clearance);
  // Contact and penetrating rows: their status.
  r = io::row_class(Clearance_state::Contact, 0.0, std::nullopt, t);
  EXPECT_EQ(r.proven, Clearance_class::Contact);
  EXPECT_EQ(r.possible, Clearance_class::Contact);
  r = io::row_class(Clearance_state::Penetrating, -0.2, std::nullopt, t);
  EXPECT_EQ(r.proven, Clearance_class::Clash);
}

TEST(ClearanceClass, MostSevereProvenClassWhenEveryBoundAgrees) {
  io::Clearance_class_builder b(k_with_clearance);
  b.add(0.0, Clearance_state::Farther, 9.0, 9.0);
  b.add(0.1, Clearance_state::Apart, 3.0, 3.0 - 1e-9);
  b.add(0.2, Clearance_state::Apart, 1.0, 1.0 - 1e-9);  // clearance
  b.add(0.3, Clearance_state::Contact, 0.0, std::nullopt);
  b.add(0.4, Clearance_state::Apart, 0.5, 0.5 - 1e-9);
  const io::Clearance_verdict v = b.verdict();
  EXPECT_EQ(v.verdict, Clearance_class::Contact);
  EXPECT_TRUE(v.undecided.empty());
  EXPECT_FALSE(io::fails(v, Clearance_class::Clash));
  EXPECT_TRUE(io::fails(v, Clearance_class::Contact));
  EXPECT_TRUE(io::fails(v, Clearance_class::Clearance));
}

TEST(ClearanceClass, ClearOnlyWhenEveryLowerBoundIsPastTheClearance) {
  io::Clearance_class_builder clear(k_with_clearance);
  clear.add(0.0, Clearance_state::Apart, 2.5, 2.0);  // the bound at D: not closer than D
  clear.add(0.1, Clearance_state::Farther, 4.0, 4.0);
  EXPECT_EQ(clear.verdict().verdict, Clearance_class::Clear);
  EXPECT_FALSE(io::fails(clear.verdict(), Clearance_class::Clearance));

  io::Clearance_class_builder open(k_with_clearance);
  open.add(0.0, Clearance_state::Apart, 2.5, 2.4);
  open.add(0.1, Clearance_state::Apart, 2.1, 1.9);  // distance past D, its bound below it
  open.add(0.2, Clearance_state::Apart, 2.2, 1.95);
  open.add(0.3, Clearance_state::Apart, 2.5, 2.4);
  const io::Clearance_verdict v = open.verdict();
  EXPECT_EQ(v.verdict, Clearance_class::Undecided);
  EXPECT_EQ(v.range.proven, Clearance_class::Clear);
  EXPECT_EQ(v.range.possible, Clearance_class::Clearance);
  ASSERT_EQ(v.undecided.size(), 1u);
  EXPECT_EQ(v.undecided[0].start, 0.1);
  EXPECT_EQ(v.undecided[0].end, 0.2);
  // A gate fails what it has not proved, and passes what it has.
  EXPECT_TRUE(io::fails(v, Clearance_class::Clearance));
  EXPECT_FALSE(io::fails(v, Clearance_class::Contact));
}

TEST(ClearanceClass, UndecidedSpansAreThoseAboveTheProvenClassJoinedAcrossLevels) {
  io::Clearance_class_builder b(k_with_clearance);
  b.add(0.0, Clearance_state::Apart, 1.0, 0.9);          // clearance, proven
  b.add(0.1, Clearance_state::Apart, 2.1, 1.9);          // open to clearance: not above it
  b.add(0.2, Clearance_state::Uncertified, 1.5, 0.0);    // open to contact
  b.add(0.3, Clearance_state::Uncertified, 1.5, -0.1);   // open to clash
  b.add(0.4, Clearance_state::Apart, 1.5, 1.4);
  b.add(0.5, Clearance_state::Apart, 1.5, std::nullopt);  // no bound: open to clash
  const io::Clearance_verdict v = b.verdict();
  EXPECT_EQ(v.verdict, Clearance_class::Undecided);
  EXPECT_EQ(v.range.proven, Clearance_class::Clearance);
  EXPECT_EQ(v.range.possible, Clearance_class::Clash);
  ASSERT_EQ(v.undecided.size(), 2u);
  EXPECT_EQ(v.undecided[0].start, 0.2);  // two levels, consecutive rows: one span
  EXPECT_EQ(v.undecided[0].end, 0.3);
  EXPECT_EQ(v.undecided[1].start, 0.5);
  EXPECT_EQ(v.undecided[1].end, 0.5);
  EXPECT_TRUE(io::fails(v, Clearance_class::Clash));
}

TEST(ClearanceClass, AClashDecidesWhateverTheBoundsLeaveOpen) {
  io::Clearance_class_builder b(k_without_clearance);
  b.add(0.0, Clearance_state::Apart, 1.0, std::nullopt);
  b.add(0.1, Clearance_state::Penetrating, -0.3, std::nullopt);
  const io::Clearance_verdict v = b.verdict();
  EXPECT_EQ(v.verdict, Clearance_class::Clash);
  EXPECT_TRUE(v.undecided.empty());
}

TEST(ClearanceClass, LevelsByName) {
  EXPECT_EQ(io::clearance_class_named("clash"), Clearance_class::Clash);
  EXPECT_EQ(io::clearance_class_named("clearance"), Clearance_class::Clearance);
  EXPECT_FALSE(io::clearance_class_named("undecided"));
  EXPECT_FALSE(io::clearance_class_named("Clash"));
  EXPECT_STREQ(io::to_string(Clearance_class::Undecided), "undecided");
}

}  // namespace
}  // namespace extremal
