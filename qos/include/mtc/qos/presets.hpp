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
// DOOR_STATE, CHUCK_STATE). Every policy and why:
// - RELIABLE: a handshake step (READY -> ACTIVE) must never be lost; a peer
//   that missed a transition would wait forever.
// - TRANSIENT_LOCAL: a late joiner or a peer reconnecting after an outage gets
//   the current value of every item at once instead of waiting a heartbeat.
// - KEEP_LAST 1 per instance (writer): only the current state matters; a
//   late joiner gets the current state only (a stale ACTIVE must not
//   resurface after recovery). Readers keep up to 8 per instance so that a
//   burst of transitions that arrives before the listener runs is handed
//   over in order instead of being collapsed to the last one.
// - DEADLINE = timing.lease(): the heartbeat contract; a missing heartbeat of
//   one data item raises requested_deadline_missed for that instance.
// - LIVELINESS MANUAL_BY_TOPIC, lease = timing.lease(): each write asserts the
//   writer's liveliness; a dead, hung or cut-off writer is declared not alive
//   within the lease. (AUTOMATIC / MANUAL_BY_PARTICIPANT are unusable for
//   this in Fast DDS 2.9.1, see FASTDDS-NOTES.)
// - Reliable-writer HEARTBEAT = timing.reliable_heartbeat: a lost packet is
//   repaired within tens of milliseconds, not the 3 s default.
// - SHARED ownership: each instance has exactly one writer (its device).
// - max_instances 1024 per writer, 16384 per reader: every data item is an
//   instance, and a reader may see every device's; the Fast DDS default of
//   10 would silently refuse larger devices.
EndpointQos state_topic(const Timing& timing = {});

// State topics as a passive observer reads them (the bridge, `mtc watch`,
// `mtc list`); reader only, an observer never writes. Every policy and why:
// - RELIABLE, TRANSIENT_LOCAL, KEEP_LAST 8 per instance, SHARED ownership:
//   as state_topic's reader (every step seen, current values at once on
//   joining, bursts handed over in order).
// - no DEADLINE: the observer tells lost devices by liveliness alone. A
//   requested DEADLINE would have to be at least every device's offered one
//   and would arm Fast DDS 2.9's per-reader deadline timer, which re-fires
//   every period for instances that went silent (a departed device's items).
// - LIVELINESS MANUAL_BY_TOPIC, lease = timing.lease(): the longest lease
//   the observer accepts (a writer offering a longer one does not match) and
//   the bound on how soon a lost device's items read UNAVAILABLE.
// - max_instances 16384: the items of every device of the cell.
EndpointQos state_observer_topic(const Timing& timing = {});

// DeviceDescription announcements:
// - RELIABLE + TRANSIENT_LOCAL + KEEP_LAST 1: a bridge or peer started later
//   still learns every device's data items at once.
// - no DEADLINE: the description only changes at start-up, so it is not
//   re-published; instead the writer asserts liveliness every heartbeat:
// - LIVELINESS MANUAL_BY_TOPIC, lease = timing.lease(): a vanished device is
//   reported lost within the same bound as its data items.
// - max_instances 1024 per writer, 16384 per reader, as state_topic.
// Observers and equipment read announcements with the same reader QoS.
EndpointQos device_description_topic(const Timing& timing = {});

// Names of the presets, as used in the XML profiles file:
//   <data_writer profile_name="mtc.state.writer">, "mtc.state.reader",
//   "mtc.device_description.writer", "mtc.device_description.reader",
//   "mtc.state_observer.reader" (no writer profile),
//   participant profiles "mtc.participant.loopback" (UDPv4 on 127.0.0.1 +
//   SHM) and "mtc.participant.loopback_udp" (UDPv4 on 127.0.0.1 only).
inline constexpr std::string_view kStateProfile = "mtc.state";
inline constexpr std::string_view kDeviceDescriptionProfile = "mtc.device_description";
inline constexpr std::string_view kStateObserverProfile = "mtc.state_observer";
inline constexpr std::string_view kLoopbackParticipantProfile = "mtc.participant.loopback";
inline constexpr std::string_view kLoopbackUdpParticipantProfile = "mtc.participant.loopback_udp";

// Looks a preset up by name ("mtc.state", "mtc.device_description",
// "mtc.state_observer"); throws std::invalid_argument naming the known
// presets otherwise. Each topic's role fixes its preset: the runtime takes
// no preset name from its users.
EndpointQos preset(std::string_view name, const Timing& timing = {});
std::vector<std::string> preset_names();

// Path of the installed XML profiles file (share/mtconnect-dds/...), as
// configured at build time; the source-tree copy when not installed.
std::string profiles_file_path();

}  // namespace mtc::qos
