// Internal: topic and partition design (see README "DDS runtime"), item ids
// and the IDL <-> core enum conversions. Used by the runtime's sources,
// tests and raw peers (never by a public header).
//
// Topics are split by role so that DDS-Security permissions, which grant by
// topic name and partition (not by instance key), can express "only the
// robot may publish its RESPONSE items":
//
//   topic                    type                     written by
//   mtc/InteractionRequest   InteractionSample        requester of a service
//   mtc/InteractionResponse  InteractionSample        responder of a service
//   mtc/InterfaceState       InterfaceStateSample     every device, per interface
//   mtc/DoorState            DoorStateSample          device controlling the door
//   mtc/ChuckState           ChuckStateSample         device controlling the chuck
//   mtc/DeviceDescription    DeviceDescription        every device (announcement)
//   mtc/Heartbeat            Heartbeat                every device, per timing group
//
// State topics carry changes only; the heartbeat (one sample per device and
// timing group per period, keyed by device uuid and group) is what tells a
// quiet device from a gone one.
//
// Each device publishes through one Publisher whose partition is
// "mtc/dev/<device uuid>"; readers subscribe to "mtc/dev/*" or to their
// counterparts' partitions. A permissions file can then allow the robot to
// publish mtc/InteractionResponse only in partition mtc/dev/<robot uuid>.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "mtc/core/vocabulary.hpp"
#include "mtc/idl/mtconnect_interfaces.h"

namespace mtc::dds::detail::topics {

inline constexpr const char* kInteractionRequest = "mtc/InteractionRequest";
inline constexpr const char* kInteractionResponse = "mtc/InteractionResponse";
inline constexpr const char* kInterfaceState = "mtc/InterfaceState";
inline constexpr const char* kDoorState = "mtc/DoorState";
inline constexpr const char* kChuckState = "mtc/ChuckState";
inline constexpr const char* kDeviceDescription = "mtc/DeviceDescription";
inline constexpr const char* kHeartbeat = "mtc/Heartbeat";

inline constexpr const char* kPartitionPrefix = "mtc/dev/";
inline constexpr const char* kAllDevicesPartition = "mtc/dev/*";

// "mtc/dev/<uuid>".
std::string device_partition(std::string_view device_uuid);

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

// Conversions between the IDL enums and the core vocabulary, by position:
// topics.cpp pairs every enumerator and fails the build if the two sides
// fall out of order. from_idl returns nullopt for a value outside the enum,
// which a peer of another vendor could send.
idl::interaction_state::Value to_idl(core::InteractionState s) noexcept;
idl::interface_state::Value to_idl(core::InterfaceState s) noexcept;
idl::door_state::Value to_idl(core::DoorState s) noexcept;
idl::chuck_state::Value to_idl(core::ChuckState s) noexcept;
idl::services::Service to_idl(core::Service s) noexcept;
idl::sub_types::SubType to_idl(core::SubType s) noexcept;
idl::interface_types::InterfaceType to_idl(core::InterfaceType t) noexcept;

std::optional<core::InteractionState> from_idl(idl::interaction_state::Value v) noexcept;
std::optional<core::InterfaceState> from_idl(idl::interface_state::Value v) noexcept;
std::optional<core::DoorState> from_idl(idl::door_state::Value v) noexcept;
std::optional<core::ChuckState> from_idl(idl::chuck_state::Value v) noexcept;
std::optional<core::Service> from_idl(idl::services::Service v) noexcept;
std::optional<core::SubType> from_idl(idl::sub_types::SubType v) noexcept;
std::optional<core::InterfaceType> from_idl(idl::interface_types::InterfaceType v) noexcept;

// CLOCK_REALTIME in ns since the epoch (the source_time_ns of samples).
std::int64_t realtime_ns() noexcept;

}  // namespace mtc::dds::detail::topics
