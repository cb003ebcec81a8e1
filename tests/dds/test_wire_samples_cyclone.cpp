// The Cyclone backend's two halves of the sample conversion (MTC_CYCLONE
// builds): a core value written into idlc's C struct (mw/cyclone_samples.hpp,
// to_c) and read back (from_c) is the value again, field by field, for every
// topic type, under the same rules as the Fast DDS backend's
// (test_wire_samples.cpp, the same values). Strings are cut at their IDL
// bound; a peer's unterminated string is read up to the bound.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "mw/cyclone_samples.hpp"
#include "wire_values.hpp"

namespace mtc::dds {
namespace {

using mw::cyclone::from_c;
using mw::cyclone::to_c;
using wire_test::expect_same;
using wire_test::value;

template <typename Sample>
ObservedValue round_trip(const ObservedValue& v) {
  Sample s{};
  to_c(v, {}, s);
  return from_c(s);
}

TEST(WireSamplesCyclone, InteractionValueAndItsPairedParticipantRoundTrip) {
  const auto v = value(core::ItemKind::Interaction);
  const detail::ParticipantKey paired{1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 0xff};
  mtc_idl_InteractionSample s{};
  to_c(v, paired, s);
  detail::ParticipantKey back_paired{};
  expect_same(from_c(s, &back_paired), v);
  EXPECT_EQ(back_paired, paired);
}

TEST(WireSamplesCyclone, StateValuesRoundTrip) {
  const auto itf = value(core::ItemKind::InterfaceState);
  expect_same(round_trip<mtc_idl_InterfaceStateSample>(itf), itf);
  const auto door = value(core::ItemKind::DoorState);
  expect_same(round_trip<mtc_idl_DoorStateSample>(door), door);
  const auto chuck = value(core::ItemKind::ChuckState);
  expect_same(round_trip<mtc_idl_ChuckStateSample>(chuck), chuck);
}

TEST(WireSamplesCyclone, StateServiceAndSideOutsideTheVocabulary) {
  auto v = value(core::ItemKind::DoorState);
  v.state = core::ObservedState::outside_vocabulary(core::ItemKind::DoorState, 42);
  const auto back = round_trip<mtc_idl_DoorStateSample>(v);
  EXPECT_FALSE(back.state.in_vocabulary());
  EXPECT_EQ(back.state.raw(), 42);
  EXPECT_EQ(back.state.kind(), core::ItemKind::DoorState);

  mtc_idl_InteractionSample s{};
  to_c(value(core::ItemKind::Interaction), {}, s);
  s.service = static_cast<mtc_idl_services_Service>(10);
  s.sub_type = static_cast<mtc_idl_sub_types_SubType>(-1);
  const auto odd = from_c(s);
  EXPECT_FALSE(odd.service.has_value());
  EXPECT_FALSE(odd.sub_type.has_value());
}

TEST(WireSamplesCyclone, StringsAreCutAtTheBoundAndReadUpToIt) {
  auto v = value(core::ItemKind::InterfaceState);
  v.device_uuid = std::string(80, 'd');
  mtc_idl_InterfaceStateSample s{};
  to_c(v, {}, s);
  EXPECT_EQ(from_c(s).device_uuid, std::string(64, 'd'));
  std::memset(s.interface_id, 'i', sizeof s.interface_id);  // no terminator at all
  EXPECT_EQ(from_c(s).interface_id, std::string(sizeof s.interface_id, 'i'));
}

TEST(WireSamplesCyclone, HeartbeatRoundTripsAndItsSequenceFollowsTheNewestBeat) {
  auto h = wire_test::heartbeat();
  mw::cyclone::CycloneHeartbeat c;
  to_c(h, c);
  EXPECT_FALSE(c.sample.interaction_changes._release);
  expect_same(from_c(c.sample), h);
  h.interaction_changes.pop_back();
  to_c(h, c);
  EXPECT_EQ(c.sample.interaction_changes._length, 1U);
  expect_same(from_c(c.sample), h);
}

TEST(WireSamplesCyclone, DeviceAnnouncementRoundTripsWithSequenceAndTime) {
  const auto d = wire_test::device();
  mw::cyclone::CycloneDevice c;
  to_c(d, 9, 123'456, c);
  EXPECT_EQ(c.sample.sequence_number, 9U);
  EXPECT_EQ(c.sample.source_time_ns, 123'456);
  expect_same(from_c(c.sample), d);
  // An interface type outside the vocabulary reads MaterialHandler.
  c.interfaces[1].interface_type = static_cast<mtc_idl_interface_types_InterfaceType>(9);
  EXPECT_EQ(from_c(c.sample).interfaces[1].type, core::InterfaceType::MaterialHandler);
}

}  // namespace
}  // namespace mtc::dds
