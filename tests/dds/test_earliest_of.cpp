// EarliestOf: the next wake of an equipment, kept as one interface's time
// limits move at a time. Checked against the plain minimum over every id.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <random>
#include <vector>

#include "earliest_of.hpp"

namespace {

using mtc::dds::detail::EarliestOf;
using TimePoint = EarliestOf::TimePoint;

TimePoint at_ms(int ms) {
  return TimePoint{} + std::chrono::milliseconds(ms);
}

TEST(EarliestOf, EmptyHasNoInstant) {
  const EarliestOf none;
  EXPECT_EQ(none.earliest(), TimePoint::max());
  EXPECT_EQ(none.at(3), TimePoint::max());
}

TEST(EarliestOf, AnInstantMovedLaterGivesWayToTheNext) {
  EarliestOf wakes;
  wakes.set(0, at_ms(30));
  wakes.set(1, at_ms(10));
  wakes.set(2, at_ms(20));
  EXPECT_EQ(wakes.earliest(), at_ms(10));
  wakes.set(1, TimePoint::max());  // its limit is gone: no longer the earliest
  EXPECT_EQ(wakes.earliest(), at_ms(20));
  wakes.set(0, at_ms(5));
  EXPECT_EQ(wakes.earliest(), at_ms(5));
  EXPECT_EQ(wakes.at(2), at_ms(20));
}

TEST(EarliestOf, IdsMayJoinOutOfOrder) {
  EarliestOf wakes;
  wakes.set(7, at_ms(70));
  EXPECT_EQ(wakes.earliest(), at_ms(70));
  EXPECT_EQ(wakes.at(3), TimePoint::max());  // not set yet
  wakes.set(3, at_ms(30));
  EXPECT_EQ(wakes.earliest(), at_ms(30));
}

TEST(EarliestOf, MatchesTheMinimumOverEveryIdUnderRandomChanges) {
  constexpr std::size_t kIds = 100;
  std::mt19937 random(20261207);
  std::uniform_int_distribution<std::size_t> pick_id(0, kIds - 1);
  std::uniform_int_distribution<int> pick_ms(0, 1000);
  EarliestOf wakes;
  std::vector<TimePoint> plain(kIds, TimePoint::max());
  for (std::size_t id = 0; id < kIds; ++id) wakes.set(id, TimePoint::max());
  for (int change = 0; change < 20000; ++change) {
    const auto id = pick_id(random);
    // One change in ten removes the limit, as a machine back to READY does.
    const auto at = change % 10 == 0 ? TimePoint::max() : at_ms(pick_ms(random));
    wakes.set(id, at);
    plain[id] = at;
    ASSERT_EQ(wakes.earliest(), *std::min_element(plain.begin(), plain.end()))
        << "after change " << change;
  }
}

}  // namespace
