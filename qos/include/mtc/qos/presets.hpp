// Named QoS presets of mtconnect-dds. The XML profiles file
// qos/profiles/mtconnect_dds_profiles.xml (installed to
// share/mtconnect-dds/) carries the same presets for the default Timing;
// tests/qos checks that both agree.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "mtc/qos/endpoint_qos.hpp"
#include "mtc/qos/timing.hpp"

namespace mtc::qos {

// Interface state topics (interaction REQUEST/RESPONSE items, INTERFACE_STATE,
// DOOR_STATE, CHUCK_STATE). They carry changes only: a value is written when
// it changes (and reaches late joiners through TRANSIENT_LOCAL), never
// repeated; liveness is the heartbeat topic's (heartbeat_topic below), so the
// idle cost of a device does not grow with its data items. Every policy and
// why:
// - RELIABLE: a handshake step (READY -> ACTIVE) must never be lost; a peer
//   that missed a transition would wait forever.
// - TRANSIENT_LOCAL: a late joiner or a peer reconnecting after an outage gets
//   the current value of every item at once.
// - KEEP_LAST 1 per instance (writer): only the current state matters; a
//   late joiner gets the current state only (a stale ACTIVE must not
//   resurface after recovery). Readers keep up to 8 per instance so that a
//   burst of transitions that arrives before the listener runs is handed
//   over in order instead of being collapsed to the last one.
// - no DEADLINE, LIVELINESS AUTOMATIC with an infinite lease (the defaults):
//   an unchanged item is silent by design.
// - Reliable-writer HEARTBEAT = timing.reliable_heartbeat: a lost packet is
//   repaired within tens of milliseconds, not the 3 s default.
// - SHARED ownership: each instance has exactly one writer (its device).
// - max_instances 1024 per writer, 16384 per reader: every data item is an
//   instance, and a reader may see every device's; the Fast DDS default of
//   10 would silently refuse larger devices.
EndpointQos state_topic(const Timing& timing = {});

// State topics as a passive observer reads them (the bridge, `mtc watch`,
// `mtc list`); reader only, an observer never writes. The same reader as
// state_topic's (RELIABLE, TRANSIENT_LOCAL, KEEP_LAST 8 per instance, no
// DEADLINE, SHARED ownership) with room for every device's items
// (max_instances 16384): an observer tells lost devices by their heartbeats
// (heartbeat_observer_topic).
EndpointQos state_observer_topic(const Timing& timing = {});

// The heartbeat topic: one instance per (device, timing group), written every
// timing.heartbeat by a thread of its own. Every policy and why:
// - RELIABLE, KEEP_LAST 1: a heartbeat lost in transit is repaired within the
//   RTPS heartbeat period (or superseded by the next one), so lost packets
//   do not add up to a false alarm; the repair traffic is one small sample
//   per group and period, not per data item.
// - TRANSIENT_LOCAL: a reader that matches gets the newest heartbeat at once,
//   which starts its DEADLINE timer and tells it the change numbers to expect;
//   a device that dies within its first period after matching is then still
//   lost within a lease (a timer starts only at an instance's first sample).
// - DEADLINE = timing.lease(): the heartbeat contract; a group silent for a
//   lease raises requested_deadline_missed at its readers.
// - LIVELINESS MANUAL_BY_TOPIC, lease = timing.lease(): each heartbeat
//   asserts its writer; a dead, hung or cut-off device is declared not alive
//   within the lease. (AUTOMATIC / MANUAL_BY_PARTICIPANT are unusable for
//   this in Fast DDS 2.9.1, see FASTDDS-NOTES.)
// - Reliable-writer HEARTBEAT = timing.reliable_heartbeat, SHARED ownership,
//   max_instances 1024 per writer (timing groups), 16384 per reader.
EndpointQos heartbeat_topic(const Timing& timing = {});

// The heartbeat topic as a passive observer reads it: heartbeat_topic's
// reader without DEADLINE, so that devices of any heartbeat period match; the
// MANUAL_BY_TOPIC lease = timing.lease() is the longest lease the observer
// accepts (a writer offering a longer one does not match), and the writer's
// own lease is how soon its loss is reported.
EndpointQos heartbeat_observer_topic(const Timing& timing = {});

// DeviceDescription announcements:
// - RELIABLE + TRANSIENT_LOCAL + KEEP_LAST 1: a bridge or peer started later
//   still learns every device's data items at once.
// - no DEADLINE, AUTOMATIC liveliness with an infinite lease: the description
//   only changes at start-up and is not repeated; a device's loss is told by
//   its heartbeats (group 0), its departure by disposal or unmatching.
// - max_instances 1024 per writer, 16384 per reader, as state_topic.
// Observers and equipment read announcements with the same reader QoS.
EndpointQos device_description_topic(const Timing& timing = {});

// Names of the presets, as used in the XML profiles file:
//   <data_writer profile_name="mtc.state.writer">, "mtc.state.reader",
//   "mtc.device_description.writer", "mtc.device_description.reader",
//   "mtc.heartbeat.writer", "mtc.heartbeat.reader",
//   "mtc.state_observer.reader", "mtc.heartbeat_observer.reader" (no writer
//   profiles),
//   participant profiles "mtc.participant.loopback" (UDPv4 on 127.0.0.1 +
//   SHM) and "mtc.participant.loopback_udp" (UDPv4 on 127.0.0.1 only).
inline constexpr std::string_view kStateProfile = "mtc.state";
inline constexpr std::string_view kDeviceDescriptionProfile = "mtc.device_description";
inline constexpr std::string_view kStateObserverProfile = "mtc.state_observer";
inline constexpr std::string_view kHeartbeatProfile = "mtc.heartbeat";
inline constexpr std::string_view kHeartbeatObserverProfile = "mtc.heartbeat_observer";
inline constexpr std::string_view kLoopbackParticipantProfile = "mtc.participant.loopback";
inline constexpr std::string_view kLoopbackUdpParticipantProfile = "mtc.participant.loopback_udp";

// Looks a preset up by name ("mtc.state", "mtc.device_description",
// "mtc.state_observer", "mtc.heartbeat", "mtc.heartbeat_observer"); throws std::invalid_argument
// naming the known presets otherwise. Each topic's role fixes its preset: the runtime takes no
// preset name from its users.
EndpointQos preset(std::string_view name, const Timing& timing = {});
std::vector<std::string> preset_names();

// Path of the installed XML profiles file (share/mtconnect-dds/...), as
// configured at build time; the source-tree copy when not installed.
std::string profiles_file_path();

}  // namespace mtc::qos
