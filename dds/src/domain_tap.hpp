// Internal: the readers that both DomainObserver and Equipment use to see a
// domain. Listener callbacks (middleware threads) convert each DDS sample or
// status into a plain TapEvent and hand it to a sink, which must only
// enqueue; all interpretation happens on the owner's single thread.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "mtc/dds/detail/entities.hpp"
#include "mtc/dds/domain_observer.hpp"
#include "mtc/idl/mtconnect_interfaces.h"
#include "mtc/qos/timing.hpp"

namespace mtc::dds::detail {

// A DDS InstanceHandle_t (writer GUID or instance key hash) as a value.
using Handle = std::array<std::uint8_t, 16>;

// The state topics come first: their index is also the index of their
// change number in a heartbeat (StateChanges).
enum class TopicKind : std::uint8_t {
  Request,
  Response,
  InterfaceState,
  DoorState,
  ChuckState,
  DeviceDescription,
  Heartbeat
};
inline constexpr std::size_t kTopicKindCount = 7;
inline constexpr std::size_t kStateTopicCount = 5;
constexpr bool is_state_topic(TopicKind kind) noexcept {
  return static_cast<std::size_t>(kind) < kStateTopicCount;
}

// Newest change number per state topic (indexed by TopicKind).
using StateChanges = std::array<std::uint64_t, kStateTopicCount>;

// The participant part (GUID prefix) of a writer's handle: which process
// incarnation wrote a sample. A restarted device has a new one.
using ParticipantKey = std::array<std::uint8_t, 12>;

struct ValueEvent {
  TopicKind topic{};
  Handle writer{};
  Handle instance{};
  ObservedValue value;
};
struct HeartbeatEvent {
  Handle writer{};
  Handle instance{};
  ObservedHeartbeat heartbeat;
};
struct DeviceEvent {
  Handle writer{};
  Handle instance{};
  ObservedDevice device;
};
// An instance was disposed or lost all its writers.
struct InstanceGoneEvent {
  TopicKind topic{};
  Handle instance{};
  bool disposed = false;  // by its writer (a graceful leave), not for want of writers
};
// A writer stopped asserting liveliness (or went away) / came back.
struct WriterLivelinessEvent {
  TopicKind topic{};
  Handle writer{};
  bool alive = false;
  bool unmatched = false;  // the writer went away (deleted, participant gone)
};
struct DeadlineMissedEvent {
  TopicKind topic;
  Handle instance;
};
struct IncompatibleQosEvent {
  TopicKind topic;
  std::string policy;
};

using TapEvent = std::variant<ValueEvent, HeartbeatEvent, DeviceEvent, InstanceGoneEvent,
                              WriterLivelinessEvent, DeadlineMissedEvent, IncompatibleQosEvent>;
using TapSink = std::function<void(TapEvent&&)>;

struct TapConfig {
  std::vector<std::string> partitions;
  qos::Timing timing;
  // Reader QoS of the heartbeat topic: an equipment's readers use the
  // heartbeat preset (its DEADLINE is the heartbeat contract); an observer's
  // use the heartbeat_observer preset (no DEADLINE: devices of any heartbeat
  // match). State topics and announcements are read with the state and
  // device_description presets either way.
  bool observer = false;
  // Which topics to read (indexed by TopicKind).
  std::array<bool, kTopicKindCount> topics{true, true, true, true, true, true, true};
};

// The topics of one participant, created on first use (a participant may
// create each topic name only once; writers and readers share them).
class TopicSet {
 public:
  TopicSet(Participant& participant, const qos::Timing& timing)
      : participant_(participant), timing_(timing) {}
  Topic& get(TopicKind kind);

 private:
  Participant& participant_;
  qos::Timing timing_;
  std::array<std::unique_ptr<Topic>, kTopicKindCount> topics_;
};

// Samples the readers of a tap have taken (valid data only), for the
// benchmarks' samples/s; relaxed counters, any thread.
struct TapCounts {
  std::uint64_t values = 0;      // state samples
  std::uint64_t heartbeats = 0;  // heartbeat samples
};

class DomainTap {
 public:
  // Creates one subscriber and the readers; `topics` must outlive the tap.
  DomainTap(Participant& participant, TopicSet& topics, const TapConfig& config, TapSink sink);
  ~DomainTap();
  DomainTap(const DomainTap&) = delete;
  DomainTap& operator=(const DomainTap&) = delete;
  TapCounts counts() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

const char* topic_name(TopicKind kind) noexcept;

// The one rule that turns silence into a loss: a counterpart is lost once
// nothing was heard from it (last_heard_ns, CLOCK_REALTIME; 0 = never) for a
// lease minus half a heartbeat. Every loss cue (a heartbeat's DEADLINE miss,
// its writer's liveliness expiry) is checked against it, because a cue is
// not a verdict: Fast DDS 2.9 keeps one deadline timer per reader and names
// whichever instance owns it, re-fires it for instances that went silent for
// good, and occasionally reports a lease expiry right after a writer's first
// samples. The half heartbeat absorbs the gap between a timer and the last
// reception of the instance that armed it.
constexpr std::chrono::nanoseconds loss_silence(std::chrono::nanoseconds lease,
                                                std::chrono::nanoseconds heartbeat) noexcept {
  return lease - heartbeat / 2;
}
constexpr bool silent_for_a_lease(std::int64_t last_heard_ns, std::int64_t now_ns,
                                  std::chrono::nanoseconds lease,
                                  std::chrono::nanoseconds heartbeat) noexcept {
  return last_heard_ns == 0 ||
         std::chrono::nanoseconds(now_ns - last_heard_ns) >= loss_silence(lease, heartbeat);
}
constexpr bool silent_for_a_lease(std::int64_t last_heard_ns, std::int64_t now_ns,
                                  const qos::Timing& timing) noexcept {
  return silent_for_a_lease(last_heard_ns, now_ns, timing.lease(), timing.heartbeat);
}

ParticipantKey participant_of(const Handle& writer) noexcept;

// Turns Fast DDS intra-process delivery off, process-wide, before the
// runtime creates a participant. With it on, Fast DDS 2.9.1 can leave a
// reliable TRANSIENT_LOCAL reader that matches a writer of the same process
// late stuck behind a sample it never receives (measured: 4 of 8 runs of
// MultiDevice.LossOfOneCounterpartLeavesTheOtherInterfaceAlone hung, 0 of 10
// without it). State topics carry changes only, so no later sample would
// unblock it; over the transports the reliable protocol repairs every hole.
void deliver_through_transports();

// Sample -> plain value conversions (states as core enums).
ObservedDevice to_observed(const idl::DeviceDescription& d);
Handle to_handle(const eprosima::fastrtps::rtps::InstanceHandle_t& h) noexcept;

}  // namespace mtc::dds::detail
