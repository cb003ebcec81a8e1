// Internal: topic and partition design (see README "DDS runtime") and item
// ids, vendor-neutral (the IDL <-> core enum conversions are topics.hpp's).
// Used by the runtime's sources, tests and raw peers (never by a public
// header).
//
// Interaction topics are split by side AND service, so that DDS-Security
// permissions, which grant by topic name and partition (never by instance
// key or field value), can express "the robot may publish MATERIAL_LOAD
// RESPONSE items, and no other RESPONSE":
//
//   topic                                 type                  written by
//   mtc/InteractionRequest/<SERVICE>      InteractionSample     requester of <SERVICE>
//   mtc/InteractionResponse/<SERVICE>     InteractionSample     responder of <SERVICE>
//   mtc/InterfaceState                    InterfaceStateSample  every device, per interface
//   mtc/DoorState                         DoorStateSample       device controlling the door
//   mtc/ChuckState                        ChuckStateSample      device controlling the chuck
//   mtc/DeviceDescription                 DeviceDescription     every device (announcement)
//   mtc/Heartbeat                         Heartbeat             every device, per timing group
//
// <SERVICE> is the MTConnect type (core::to_string(Service)): MATERIAL_LOAD,
// OPEN_DOOR, ... (10 services, so 20 interaction topics). Names use only
// letters, digits, '_' and '/', not starting with a digit: Fast DDS takes
// any string, and Cyclone DDS 0.10 (dds_create_topic) accepts exactly
// [A-Za-z0-9_/] ('-', '.' and ':' are refused), so the names stay valid for a
// second backend. An equipment creates the writers and readers of the
// services its interfaces use only; the DomainObserver reads all 20. A
// sample whose service or sub_type disagrees with its topic is a protocol
// violation: reported, never fed to a state machine.
//
// State topics carry changes only; the heartbeat (one sample per device and
// timing group per period, keyed by device uuid and group) is what tells a
// quiet device from a gone one, and announces the newest change of each of
// the group's writers (one per interaction topic).
//
// Each device publishes through one Publisher whose partition is
// "mtc/dev/<device uuid>"; readers subscribe to "mtc/dev/*" or to their
// counterparts' partitions. A permissions file can then allow the robot to
// publish mtc/InteractionResponse/MATERIAL_LOAD only in partition
// mtc/dev/<robot uuid>.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "mtc/core/vocabulary.hpp"

namespace mtc::dds::detail::topics {

// Interaction topic names: prefix + service (interaction_topic below).
inline constexpr const char* kInteractionRequestPrefix = "mtc/InteractionRequest/";
inline constexpr const char* kInteractionResponsePrefix = "mtc/InteractionResponse/";
inline constexpr const char* kInterfaceState = "mtc/InterfaceState";
inline constexpr const char* kDoorState = "mtc/DoorState";
inline constexpr const char* kChuckState = "mtc/ChuckState";
inline constexpr const char* kDeviceDescription = "mtc/DeviceDescription";
inline constexpr const char* kHeartbeat = "mtc/Heartbeat";

inline constexpr const char* kPartitionPrefix = "mtc/dev/";
inline constexpr const char* kAllDevicesPartition = "mtc/dev/*";

// "mtc/dev/<uuid>".
std::string device_partition(std::string_view device_uuid);

// "mtc/InteractionRequest/MATERIAL_LOAD", "mtc/InteractionResponse/OPEN_DOOR", ...
std::string interaction_topic(core::SubType side, core::Service service);

// Device uuids and interface ids end up in partition names, data item ids
// and 64-character IDL strings: 1-64 characters of [A-Za-z0-9_.:-], not
// starting with a digit for ids. Returns the problem in words, or nullopt.
std::optional<std::string> check_device_uuid(std::string_view uuid);
std::optional<std::string> check_interface_id(std::string_view id);

// Data item ids published by this runtime (unique within a device):
//   <interface>_<service>_request / _response, e.g. "mh1_material_load_request"
//   <interface>_interface_state, <interface>_door_state, <interface>_chuck_state
std::string interaction_item_id(std::string_view interface_id, core::Service service,
                                core::SubType sub_type);
std::string interface_state_item_id(std::string_view interface_id);
std::string door_state_item_id(std::string_view interface_id);
std::string chuck_state_item_id(std::string_view interface_id);

// CLOCK_REALTIME in ns since the epoch (the source_time_ns of samples).
std::int64_t realtime_ns() noexcept;

}  // namespace mtc::dds::detail::topics
