// ObservationBuffer: sequence numbers, wrap-around, latest values that fell
// out of the ring, and state_at() against a brute-force replay.
#include <gtest/gtest.h>

#include <random>

#include "mtc/bridge/observation_buffer.hpp"

namespace mtc::bridge {
namespace {

TEST(ObservationBuffer, SequencesStartAtOneAndIncrease) {
  ObservationBuffer b(4);
  EXPECT_TRUE(b.empty());
  EXPECT_EQ(b.first_sequence(), 1u);
  EXPECT_EQ(b.next_sequence(), 1u);
  EXPECT_EQ(b.append(0, "A", 10), 1u);
  EXPECT_EQ(b.append(1, "B", 20), 2u);
  EXPECT_EQ(b.last_sequence(), 2u);
  ASSERT_NE(b.find(2), nullptr);
  EXPECT_EQ(b.find(2)->value, "B");
  EXPECT_EQ(b.find(3), nullptr);
  EXPECT_EQ(b.find(0), nullptr);
}

TEST(ObservationBuffer, WrapAroundKeepsTheLastCapacityEntries) {
  ObservationBuffer b(3);  // not a power of two
  for (int i = 0; i < 10; ++i) b.append(static_cast<std::uint32_t>(i % 2), std::to_string(i), i);
  EXPECT_EQ(b.first_sequence(), 8u);
  EXPECT_EQ(b.next_sequence(), 11u);
  EXPECT_EQ(b.find(7), nullptr);
  for (std::uint64_t s = 8; s <= 10; ++s) {
    ASSERT_NE(b.find(s), nullptr);
    EXPECT_EQ(b.find(s)->value, std::to_string(s - 1));
  }
}

TEST(ObservationBuffer, LatestSurvivesEviction) {
  ObservationBuffer b(2);
  b.append(5, "ONLY_ONCE", 1);
  for (int i = 0; i < 10; ++i) b.append(0, std::to_string(i), i);
  ASSERT_NE(b.latest(5), nullptr);
  EXPECT_EQ(b.latest(5)->value, "ONLY_ONCE");
  EXPECT_EQ(b.latest(5)->sequence, 1u);
  EXPECT_EQ(b.latest(3), nullptr);
}

TEST(ObservationBuffer, StateAtMatchesBruteForceReplay) {
  constexpr std::size_t kCapacity = 37;
  ObservationBuffer b(kCapacity, 5);
  std::vector<Observation> all;
  std::mt19937 rng(7);
  for (int i = 0; i < 300; ++i) {
    const auto slot = static_cast<std::uint32_t>(rng() % 6);
    const std::string v = "V" + std::to_string(rng() % 4);
    const std::uint64_t seq = b.append(slot, v, i);
    all.push_back(Observation{seq, slot, i, v});
    if (i % 17 != 0) continue;
    for (std::uint64_t at = b.first_sequence(); at <= b.last_sequence(); ++at) {
      std::vector<Observation> expected;
      for (const Observation& o : all) {
        if (o.sequence > at) break;
        if (expected.size() <= o.slot) expected.resize(o.slot + 1);
        expected[o.slot] = o;
      }
      const std::vector<Observation> got = b.state_at(at);
      for (std::size_t s = 0; s < std::max(got.size(), expected.size()); ++s) {
        const std::uint64_t want = s < expected.size() ? expected[s].sequence : 0;
        const std::uint64_t have = s < got.size() ? got[s].sequence : 0;
        ASSERT_EQ(have, want) << "at=" << at << " slot=" << s;
        if (want != 0) {
          ASSERT_EQ(got[s].value, expected[s].value);
        }
      }
    }
  }
}

TEST(ObservationBuffer, StateAtOutsideTheRingThrows) {
  ObservationBuffer b(2);
  EXPECT_THROW(b.state_at(1), std::out_of_range);
  b.append(0, "A", 0);
  b.append(0, "B", 0);
  b.append(0, "C", 0);
  EXPECT_THROW(b.state_at(1), std::out_of_range);
  EXPECT_THROW(b.state_at(4), std::out_of_range);
  EXPECT_EQ(b.state_at(2)[0].value, "B");
}

TEST(ObservationBuffer, RejectsTinyCapacity) {
  EXPECT_THROW(ObservationBuffer(1), std::invalid_argument);
}

}  // namespace
}  // namespace mtc::bridge
