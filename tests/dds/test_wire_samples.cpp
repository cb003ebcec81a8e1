// The Fast DDS backend's two halves of the sample conversion: a core value
// written (mw/fastdds_samples.hpp, to_idl) and read back (decode_sample, what
// every reader applies) is the value again, field by field, for every topic
// type. The Cyclone backend passes the same round trip with its own types
// (test_wire_samples_cyclone.cpp).
#include <gtest/gtest.h>

#include "mtc/dds/detail/sample_decoding.hpp"
#include "mw/fastdds_samples.hpp"
#include "wire_values.hpp"

namespace mtc::dds {
namespace {

using mw::fastdds::to_idl;
using wire_test::expect_same;
using wire_test::value;

template <typename Sample>
ObservedValue round_trip(const ObservedValue& v, const detail::ParticipantKey& paired = {}) {
  Sample s;
  to_idl(v, paired, s);
  return detail::decode_sample(s);
}

TEST(WireSamples, InteractionValueAndItsPairedParticipantRoundTrip) {
  const auto v = value(core::ItemKind::Interaction);
  const detail::ParticipantKey paired{1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 0xff};
  idl::InteractionSample s;
  to_idl(v, paired, s);
  expect_same(detail::decode_sample(s), v);
  for (std::size_t i = 0; i < paired.size(); ++i) {
    EXPECT_EQ(s.paired_participant()[i], paired[i]) << "byte " << i;
  }
}

TEST(WireSamples, StateValuesRoundTrip) {
  const auto itf = value(core::ItemKind::InterfaceState);
  expect_same(round_trip<idl::InterfaceStateSample>(itf), itf);
  const auto door = value(core::ItemKind::DoorState);
  expect_same(round_trip<idl::DoorStateSample>(door), door);
  const auto chuck = value(core::ItemKind::ChuckState);
  expect_same(round_trip<idl::ChuckStateSample>(chuck), chuck);
}

// A test peer may write a number outside the vocabulary; it arrives as that
// number, still outside.
TEST(WireSamples, StateOutsideTheVocabularyTravelsAsItsNumber) {
  auto v = value(core::ItemKind::DoorState);
  v.state = core::ObservedState::outside_vocabulary(core::ItemKind::DoorState, 42);
  const auto back = round_trip<idl::DoorStateSample>(v);
  EXPECT_FALSE(back.state.in_vocabulary());
  EXPECT_EQ(back.state.raw(), 42);
  EXPECT_EQ(back.state.kind(), core::ItemKind::DoorState);
}

TEST(WireSamples, HeartbeatRoundTripsWithEveryChangeNumber) {
  auto h = wire_test::heartbeat();
  idl::Heartbeat s;
  to_idl(h, s);
  expect_same(detail::decode_sample(s), h);
  // A reused sample (the writer's) holds only the newest beat's entries.
  h.interaction_changes.pop_back();
  to_idl(h, s);
  EXPECT_EQ(detail::decode_sample(s).interaction_changes.size(), 1U);
}

TEST(WireSamples, DeviceAnnouncementRoundTripsWithSequenceAndTime) {
  const auto d = wire_test::device();
  idl::DeviceDescription s;
  to_idl(d, 9, 123'456, s);
  EXPECT_EQ(s.sequence_number(), 9U);
  EXPECT_EQ(s.source_time_ns(), 123'456);
  expect_same(detail::decode_sample(s), d);
}

}  // namespace
}  // namespace mtc::dds
