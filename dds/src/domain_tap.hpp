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

enum class TopicKind : std::uint8_t {
  Request,
  Response,
  InterfaceState,
  DoorState,
  ChuckState,
  DeviceDescription
};
inline constexpr std::size_t kTopicKindCount = 6;

struct ValueEvent {
  TopicKind topic;
  Handle writer;
  Handle instance;
  ObservedValue value;
};
struct DeviceEvent {
  Handle writer;
  Handle instance;
  ObservedDevice device;
};
// An instance was disposed or lost all its writers.
struct InstanceGoneEvent {
  TopicKind topic;
  Handle instance;
};
// A writer stopped asserting liveliness (or went away) / came back.
struct WriterLivelinessEvent {
  TopicKind topic;
  Handle writer;
  bool alive;
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

using TapEvent = std::variant<ValueEvent, DeviceEvent, InstanceGoneEvent, WriterLivelinessEvent,
                              DeadlineMissedEvent, IncompatibleQosEvent>;
using TapSink = std::function<void(TapEvent&&)>;

struct TapConfig {
  std::vector<std::string> partitions;
  qos::Timing timing;
  // Reader QoS of the state topics: an equipment's readers use the state
  // preset (its DEADLINE is the heartbeat contract); an observer's use the
  // state_observer preset (no DEADLINE: devices of any heartbeat match).
  // Announcements are read with the device_description preset either way.
  bool observer = false;
  // Which topics to read (indexed by TopicKind).
  std::array<bool, kTopicKindCount> topics{true, true, true, true, true, true};
};

// The six topics of one participant, created on first use (a participant may
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

class DomainTap {
 public:
  // Creates one subscriber and the readers; `topics` must outlive the tap.
  DomainTap(Participant& participant, TopicSet& topics, const TapConfig& config, TapSink sink);
  ~DomainTap();
  DomainTap(const DomainTap&) = delete;
  DomainTap& operator=(const DomainTap&) = delete;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

const char* topic_name(TopicKind kind) noexcept;

// A writer's liveliness lease expiry (WriterLivelinessEvent, not alive, not
// unmatched) is a loss only after about a lease of silence: Fast DDS 2.9
// occasionally reports one right after a writer's first samples. True when
// the writer was heard (last_heard_ns, CLOCK_REALTIME; 0 = never) less than
// half a lease before now_ns: the expiry is to be ignored.
constexpr bool expiry_is_premature(std::int64_t last_heard_ns, std::int64_t now_ns,
                                   const qos::Timing& timing) noexcept {
  return last_heard_ns != 0 &&
         std::chrono::nanoseconds(now_ns - last_heard_ns) < timing.lease() / 2;
}

// Sample -> plain value conversions (states as core enums).
ObservedDevice to_observed(const idl::DeviceDescription& d);
Handle to_handle(const eprosima::fastrtps::rtps::InstanceHandle_t& h) noexcept;

}  // namespace mtc::dds::detail
