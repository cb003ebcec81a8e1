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

#include "mtc/core/vocabulary.hpp"
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

// Newest change number per state topic (indexed by TopicKind; the Request
// and Response entries are not used: see InteractionChanges).
using StateChanges = std::array<std::uint64_t, kStateTopicCount>;

// Interaction items have one topic per side (TopicKind::Request or
// Response) and service (topics::interaction_topic), indexed thus.
inline constexpr std::size_t kServiceCount = core::kAllServices.size();
inline constexpr std::size_t kInteractionTopicCount = 2 * kServiceCount;
constexpr std::size_t interaction_index(TopicKind side, core::Service service) noexcept {
  return (side == TopicKind::Request ? 0 : kServiceCount) + static_cast<std::size_t>(service);
}
constexpr std::size_t interaction_index(core::SubType side, core::Service service) noexcept {
  return interaction_index(
      side == core::SubType::Request ? TopicKind::Request : TopicKind::Response, service);
}
constexpr TopicKind interaction_side(std::size_t index) noexcept {
  return index < kServiceCount ? TopicKind::Request : TopicKind::Response;
}
constexpr core::Service interaction_service(std::size_t index) noexcept {
  return core::kAllServices[index % kServiceCount];
}
// A set of interaction topics (which are read), and the newest change
// number per interaction topic.
using InteractionTopics = std::array<bool, kInteractionTopicCount>;
using InteractionChanges = std::array<std::uint64_t, kInteractionTopicCount>;
constexpr InteractionTopics all_interaction_topics() noexcept {
  InteractionTopics all{};
  for (auto& t : all) t = true;
  return all;
}

// The participant part (GUID prefix) of a writer's handle: which process
// incarnation wrote a sample. A restarted device has a new one.
using ParticipantKey = std::array<std::uint8_t, 12>;

struct ValueEvent {
  TopicKind topic{};
  Handle writer{};
  Handle instance{};
  ObservedValue value;
  // Interaction values: the counterpart participant the writer was paired
  // with when it wrote the value (all zero: none, or another kind of item).
  ParticipantKey paired{};
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
// An interaction sample whose service or sub_type disagrees with the topic
// it came on (a protocol violation: never handed on as a value).
struct ProtocolViolationEvent {
  std::size_t topic = 0;  // interaction_index of the topic
  Handle writer{};
  ObservedValue value;
};

using TapEvent =
    std::variant<ValueEvent, HeartbeatEvent, DeviceEvent, InstanceGoneEvent, WriterLivelinessEvent,
                 DeadlineMissedEvent, IncompatibleQosEvent, ProtocolViolationEvent>;
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
  // Which topics to read (indexed by TopicKind); of the interaction topics
  // (Request, Response), those in `interactions` only.
  std::array<bool, kTopicKindCount> topics{true, true, true, true, true, true, true};
  InteractionTopics interactions = all_interaction_topics();
};

// The topics of one participant, created on first use (a participant may
// create each topic name only once; writers and readers share them).
class TopicSet {
 public:
  TopicSet(Participant& participant, const qos::Timing& timing)
      : participant_(participant), timing_(timing) {}
  // A topic other than the interaction ones (ConfigError for Request or
  // Response: those are per service).
  Topic& get(TopicKind kind);
  // The interaction topic of interaction_index `index`.
  Topic& interaction(std::size_t index);

 private:
  Participant& participant_;
  qos::Timing timing_;
  std::array<std::unique_ptr<Topic>, kTopicKindCount> topics_;
  std::array<std::unique_ptr<Topic>, kInteractionTopicCount> interactions_;
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
  // Subscriber::reannounce of the tap's readers (executor thread); how many.
  std::size_t reannounce();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The topic's name; for Request and Response, the pattern of the service
// topics ("mtc/InteractionRequest/*").
const char* topic_name(TopicKind kind) noexcept;
// topics::interaction_topic of an interaction_index.
std::string interaction_topic_name(std::size_t index);
// "device D wrote <item> (<SERVICE> <SIDE>) on <topic>: ...", for the owner's report.
std::string protocol_violation(const ProtocolViolationEvent& e);

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
