// The Fast DDS backend's two halves of the sample conversion: a core value
// written (mw/fastdds_samples.hpp, to_idl) and read back (decode_sample, what
// every reader applies) is the value again, field by field, for every topic
// type. A second backend must pass the same round trip with its own types.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>

#include "mtc/dds/detail/sample_decoding.hpp"
#include "mw/fastdds_samples.hpp"

namespace mtc::dds {
namespace {

using mw::fastdds::to_idl;

ObservedValue value(core::ItemKind kind) {
  ObservedValue v;
  v.device_uuid = "machine-with-a-uuid-longer-than-sso-1";
  v.data_item_id = "mh_material_load_response";
  v.interface_id = "mh";
  v.sequence_number = std::numeric_limits<std::uint64_t>::max() - 3;
  v.heartbeat_group = 7;
  v.source_time_ns = -1'234'567'890'123;
  switch (kind) {
    case core::ItemKind::Interaction:
      v.service = core::Service::MaterialLoad;
      v.sub_type = core::SubType::Response;
      v.state = core::InteractionState::Complete;
      v.paired_device_uuid = "robot-1";
      v.paired_interface_id = "mh";
      break;
    case core::ItemKind::InterfaceState:
      v.state = core::InterfaceState::Disabled;
      break;
    case core::ItemKind::DoorState:
      v.state = core::DoorState::Unlatched;
      break;
    case core::ItemKind::ChuckState:
      v.state = core::ChuckState::Closed;
      break;
  }
  return v;
}

// What travels; the reception time and `redelivered` are the reader's own.
void expect_same(const ObservedValue& a, const ObservedValue& b) {
  EXPECT_EQ(a.device_uuid, b.device_uuid);
  EXPECT_EQ(a.data_item_id, b.data_item_id);
  EXPECT_EQ(a.interface_id, b.interface_id);
  EXPECT_EQ(a.service, b.service);
  EXPECT_EQ(a.sub_type, b.sub_type);
  EXPECT_EQ(a.state, b.state);
  EXPECT_EQ(a.sequence_number, b.sequence_number);
  EXPECT_EQ(a.heartbeat_group, b.heartbeat_group);
  EXPECT_EQ(a.source_time_ns, b.source_time_ns);
  EXPECT_EQ(a.paired_device_uuid, b.paired_device_uuid);
  EXPECT_EQ(a.paired_interface_id, b.paired_interface_id);
}

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
  ObservedHeartbeat h;
  h.device_uuid = "machine-1";
  h.group = 2;
  h.period_ms = 0;  // leaving
  h.lease_ms = 350;
  h.beat = 1'000'000'007;
  h.request_changes = 11;
  h.response_changes = 12;
  h.interface_state_changes = 13;
  h.door_state_changes = 14;
  h.chuck_state_changes = std::numeric_limits<std::uint64_t>::max();
  h.interaction_changes = {{core::Service::OpenDoor, core::SubType::Request, 5},
                           {core::Service::MaterialUnload, core::SubType::Response, 6}};
  h.source_time_ns = 1'795'525'998'481'669'580;
  idl::Heartbeat s;
  to_idl(h, s);
  const auto back = detail::decode_sample(s);
  EXPECT_EQ(back.device_uuid, h.device_uuid);
  EXPECT_EQ(back.group, h.group);
  EXPECT_EQ(back.period_ms, h.period_ms);
  EXPECT_EQ(back.lease_ms, h.lease_ms);
  EXPECT_EQ(back.beat, h.beat);
  EXPECT_EQ(back.request_changes, h.request_changes);
  EXPECT_EQ(back.response_changes, h.response_changes);
  EXPECT_EQ(back.interface_state_changes, h.interface_state_changes);
  EXPECT_EQ(back.door_state_changes, h.door_state_changes);
  EXPECT_EQ(back.chuck_state_changes, h.chuck_state_changes);
  ASSERT_EQ(back.interaction_changes.size(), 2U);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(back.interaction_changes[i].service, h.interaction_changes[i].service);
    EXPECT_EQ(back.interaction_changes[i].sub_type, h.interaction_changes[i].sub_type);
    EXPECT_EQ(back.interaction_changes[i].changes, h.interaction_changes[i].changes);
  }
  EXPECT_EQ(back.source_time_ns, h.source_time_ns);

  // A reused sample (the writer's) holds only the newest beat's entries.
  h.interaction_changes.pop_back();
  to_idl(h, s);
  EXPECT_EQ(detail::decode_sample(s).interaction_changes.size(), 1U);
}

TEST(WireSamples, DeviceAnnouncementRoundTripsWithSequenceAndTime) {
  ObservedDevice d;
  d.device_uuid = "cell-machine";
  d.name = "Machine tool";
  ObservedInterface mh;
  mh.id = "mh";
  mh.name = "material handler";
  mh.type = core::InterfaceType::MaterialHandler;
  mh.data_items = {{"mh_interface_state", "mh_interface_state", "INTERFACE_STATE", "", "EVENT"},
                   {"mh_material_load_response", "mh_material_load_response", "MATERIAL_LOAD",
                    "RESPONSE", "EVENT"}};
  ObservedInterface door;
  door.id = "door";
  door.name = "door";
  door.type = core::InterfaceType::Door;
  door.data_items = {{"door_door_state", "door_door_state", "DOOR_STATE", "", "EVENT"}};
  d.interfaces = {mh, door};
  idl::DeviceDescription s;
  to_idl(d, 9, 123'456, s);
  EXPECT_EQ(s.sequence_number(), 9U);
  EXPECT_EQ(s.source_time_ns(), 123'456);
  const auto back = detail::decode_sample(s);
  EXPECT_EQ(back.device_uuid, d.device_uuid);
  EXPECT_EQ(back.name, d.name);
  ASSERT_EQ(back.interfaces.size(), 2U);
  for (std::size_t i = 0; i < 2; ++i) {
    const auto& a = back.interfaces[i];
    const auto& b = d.interfaces[i];
    EXPECT_EQ(a.id, b.id);
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.type, b.type);
    ASSERT_EQ(a.data_items.size(), b.data_items.size());
    for (std::size_t k = 0; k < a.data_items.size(); ++k) {
      EXPECT_EQ(a.data_items[k].id, b.data_items[k].id);
      EXPECT_EQ(a.data_items[k].name, b.data_items[k].name);
      EXPECT_EQ(a.data_items[k].type, b.data_items[k].type);
      EXPECT_EQ(a.data_items[k].sub_type, b.data_items[k].sub_type);
      EXPECT_EQ(a.data_items[k].category, b.data_items[k].category);
    }
  }
}

}  // namespace
}  // namespace mtc::dds
