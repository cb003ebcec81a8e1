// One InteractionSample as plain values, convertible to and from the Fast DDS
// (fastddsgen) and the Cyclone DDS (idlc) types of the same IDL, so the
// interop tests compare what was written with what arrived field by field.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <ostream>
#include <string>
#include <tuple>

#include "cyclone_entities.hpp"
#include "mtc/idl/mtconnect_interfaces.h"
#include "mtc/idl_cyclone/mtconnect_interfaces.h"

namespace mtc::test::interop {

struct Item {
  std::string device_uuid;
  std::string data_item_id;
  std::string interface_id;
  int service = 0;
  int sub_type = 0;
  int state = 0;
  std::uint64_t sequence_number = 0;
  std::uint32_t heartbeat_group = 0;
  std::int64_t source_time_ns = 0;
  std::string paired_device_uuid;
  std::string paired_interface_id;
  std::array<std::uint8_t, 12> paired_participant{};

  auto tie() const {
    return std::tie(device_uuid, data_item_id, interface_id, service, sub_type, state,
                    sequence_number, heartbeat_group, source_time_ns, paired_device_uuid,
                    paired_interface_id, paired_participant);
  }
  bool operator==(const Item& other) const { return tie() == other.tie(); }
};

inline std::ostream& operator<<(std::ostream& os, const Item& i) {
  os << "{" << i.device_uuid << ", " << i.data_item_id << ", " << i.interface_id << ", service "
     << i.service << ", sub_type " << i.sub_type << ", state " << i.state << ", seq "
     << i.sequence_number << ", group " << i.heartbeat_group << ", t " << i.source_time_ns
     << ", paired " << i.paired_device_uuid << "/" << i.paired_interface_id << ", participant";
  for (auto b : i.paired_participant) os << ' ' << static_cast<int>(b);
  return os << "}";
}

inline idl::InteractionSample to_fast(const Item& i) {
  idl::InteractionSample s;
  s.device_uuid(i.device_uuid);
  s.data_item_id(i.data_item_id);
  s.interface_id(i.interface_id);
  s.service(static_cast<idl::services::Service>(i.service));
  s.sub_type(static_cast<idl::sub_types::SubType>(i.sub_type));
  s.state(static_cast<idl::interaction_state::Value>(i.state));
  s.sequence_number(i.sequence_number);
  s.heartbeat_group(i.heartbeat_group);
  s.source_time_ns(i.source_time_ns);
  s.paired_device_uuid(i.paired_device_uuid);
  s.paired_interface_id(i.paired_interface_id);
  std::copy(i.paired_participant.begin(), i.paired_participant.end(),
            s.paired_participant().begin());
  return s;
}

inline Item from_fast(const idl::InteractionSample& s) {
  Item i{s.device_uuid().to_string(),
         s.data_item_id().to_string(),
         s.interface_id().to_string(),
         static_cast<int>(s.service()),
         static_cast<int>(s.sub_type()),
         static_cast<int>(s.state()),
         s.sequence_number(),
         s.heartbeat_group(),
         s.source_time_ns(),
         s.paired_device_uuid().to_string(),
         s.paired_interface_id().to_string(),
         {}};
  std::copy(s.paired_participant().begin(), s.paired_participant().end(),
            i.paired_participant.begin());
  return i;
}

inline mtc_idl_InteractionSample to_cyclone(const Item& i) {
  mtc_idl_InteractionSample s{};
  cyclone::copy_bounded(s.device_uuid, i.device_uuid);
  cyclone::copy_bounded(s.data_item_id, i.data_item_id);
  cyclone::copy_bounded(s.interface_id, i.interface_id);
  s.service = static_cast<mtc_idl_services_Service>(i.service);
  s.sub_type = static_cast<mtc_idl_sub_types_SubType>(i.sub_type);
  s.state = static_cast<mtc_idl_interaction_state_Value>(i.state);
  s.sequence_number = i.sequence_number;
  s.heartbeat_group = i.heartbeat_group;
  s.source_time_ns = i.source_time_ns;
  cyclone::copy_bounded(s.paired_device_uuid, i.paired_device_uuid);
  cyclone::copy_bounded(s.paired_interface_id, i.paired_interface_id);
  std::copy(i.paired_participant.begin(), i.paired_participant.end(), s.paired_participant);
  return s;
}

inline Item from_cyclone(const mtc_idl_InteractionSample& s) {
  Item i{s.device_uuid,
         s.data_item_id,
         s.interface_id,
         static_cast<int>(s.service),
         static_cast<int>(s.sub_type),
         static_cast<int>(s.state),
         s.sequence_number,
         s.heartbeat_group,
         s.source_time_ns,
         s.paired_device_uuid,
         s.paired_interface_id,
         {}};
  std::copy(std::begin(s.paired_participant), std::end(s.paired_participant),
            i.paired_participant.begin());
  return i;
}

// Two data items (instances) of one device. The values catch encoding
// faults: 8-byte members right after 4-byte ones (XCDR1 aligns them to 8,
// XCDR2 to 4), a uint64 above 2^63, a negative int64, strings at their
// 64-character bound and empty, a non-zero enum in every enum member and
// participant bytes that differ from end to end.
inline std::array<Item, 2> test_items() {
  Item a{"robot-1",        "mh1_material_load_response", "mh1", 4, 1, 3, (1ULL << 63) + 5, 7,
         -1234567890123LL, std::string(64, 'm'),         "mh1", {}};
  for (std::size_t b = 0; b < a.paired_participant.size(); ++b) {
    a.paired_participant[b] = static_cast<std::uint8_t>(0xA0 + b);
  }
  Item b = a;
  b.data_item_id = std::string(64, 'd');  // a key at its bound
  b.state = 5;
  b.sequence_number = 2;
  b.paired_device_uuid.clear();
  b.paired_interface_id.clear();
  b.paired_participant.fill(0);
  return {a, b};
}

}  // namespace mtc::test::interop
