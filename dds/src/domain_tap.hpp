// Internal, Fast DDS backend: the readers that both DomainObserver and
// Equipment use to see a domain (through mw::Participant::tap), and the
// topics of a participant. The events they produce are mw/tap_events.hpp's.
#pragma once

#include <array>
#include <memory>
#include <string>

#include "mtc/dds/detail/entities.hpp"
#include "mtc/idl/mtconnect_interfaces.h"
#include "mw/tap_events.hpp"

namespace mtc::dds::detail {

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
