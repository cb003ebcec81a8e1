// Values for the sample-conversion round trips of both backends
// (test_wire_samples.cpp for Fast DDS, test_wire_samples_cyclone.cpp for
// Cyclone DDS): one of each topic type, with awkward field values, and the
// field-by-field comparisons of what travels.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>

#include "mtc/dds/domain_observer.hpp"

namespace mtc::dds::wire_test {

inline ObservedValue value(core::ItemKind kind) {
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
inline void expect_same(const ObservedValue& a, const ObservedValue& b) {
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

inline ObservedHeartbeat heartbeat() {
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
  return h;
}

inline void expect_same(const ObservedHeartbeat& a, const ObservedHeartbeat& b) {
  EXPECT_EQ(a.device_uuid, b.device_uuid);
  EXPECT_EQ(a.group, b.group);
  EXPECT_EQ(a.period_ms, b.period_ms);
  EXPECT_EQ(a.lease_ms, b.lease_ms);
  EXPECT_EQ(a.beat, b.beat);
  EXPECT_EQ(a.request_changes, b.request_changes);
  EXPECT_EQ(a.response_changes, b.response_changes);
  EXPECT_EQ(a.interface_state_changes, b.interface_state_changes);
  EXPECT_EQ(a.door_state_changes, b.door_state_changes);
  EXPECT_EQ(a.chuck_state_changes, b.chuck_state_changes);
  ASSERT_EQ(a.interaction_changes.size(), b.interaction_changes.size());
  for (std::size_t i = 0; i < a.interaction_changes.size(); ++i) {
    EXPECT_EQ(a.interaction_changes[i].service, b.interaction_changes[i].service);
    EXPECT_EQ(a.interaction_changes[i].sub_type, b.interaction_changes[i].sub_type);
    EXPECT_EQ(a.interaction_changes[i].changes, b.interaction_changes[i].changes);
  }
  EXPECT_EQ(a.source_time_ns, b.source_time_ns);
}

inline ObservedDevice device() {
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
  return d;
}

inline void expect_same(const ObservedDevice& a, const ObservedDevice& b) {
  EXPECT_EQ(a.device_uuid, b.device_uuid);
  EXPECT_EQ(a.name, b.name);
  ASSERT_EQ(a.interfaces.size(), b.interfaces.size());
  for (std::size_t i = 0; i < a.interfaces.size(); ++i) {
    const auto& x = a.interfaces[i];
    const auto& y = b.interfaces[i];
    EXPECT_EQ(x.id, y.id);
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.type, y.type);
    ASSERT_EQ(x.data_items.size(), y.data_items.size());
    for (std::size_t k = 0; k < x.data_items.size(); ++k) {
      EXPECT_EQ(x.data_items[k].id, y.data_items[k].id);
      EXPECT_EQ(x.data_items[k].name, y.data_items[k].name);
      EXPECT_EQ(x.data_items[k].type, y.data_items[k].type);
      EXPECT_EQ(x.data_items[k].sub_type, y.data_items[k].sub_type);
      EXPECT_EQ(x.data_items[k].category, y.data_items[k].category);
    }
  }
}

}  // namespace mtc::dds::wire_test
