// Internal: the seam between the runtime (Equipment, DomainObserver) and a
// DDS implementation (docs/design/middleware-layer.md, sections 2 and 5,
// step 3). The runtime writes and reads core values only; a backend owns
// the vendor's entities, converts those values to and from its generated
// types and turns every callback into a TapEvent. Nothing here names a
// vendor: Fast DDS is the backend today (fastdds_backend.cpp), Cyclone DDS
// the next.
//
// Lifetimes: writers, publishers and taps must be destroyed before the
// participant that made them. Threads: a writer is used by one thread at a
// time (the executor, or the heartbeat thread for heartbeat writers); the
// taps' sinks are called on middleware threads and must only enqueue.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "mtc/dds/domain_observer.hpp"
#include "mtc/dds/error.hpp"
#include "mtc/dds/middleware.hpp"
#include "mtc/qos/endpoint_qos.hpp"
#include "mtc/qos/participant.hpp"
#include "tap_events.hpp"
#include "wire.hpp"

namespace mtc::dds::mw {

using detail::ParticipantKey;
using detail::TapConfig;
using detail::TapCounts;
using detail::TapSink;
using detail::TopicKind;

// A writer of one of the four state-sample topics (an interaction topic of
// one service and side, INTERFACE_STATE, DOOR_STATE or CHUCK_STATE). What is
// sent of a value: device, item, interface, service and side (interaction
// items), state, sequence number, heartbeat group, source time, the pairing
// (interaction items, with the paired participant); not the reception time
// or `redelivered`, which are the reader's.
class ValueWriter {
 public:
  virtual ~ValueWriter() = default;
  virtual void write(const ObservedValue& value, const ParticipantKey& paired) = 0;
  // The item's instance is disposed (a graceful leave).
  virtual void dispose(const std::string& device_uuid, const std::string& data_item_id) = 0;
};

// The writer of a device's heartbeats (one instance per timing group).
class HeartbeatWriter {
 public:
  virtual ~HeartbeatWriter() = default;
  // Everything but the reception time is sent.
  virtual void write(const ObservedHeartbeat& heartbeat) = 0;
  virtual void dispose(const std::string& device_uuid, std::uint32_t group) = 0;
};

// The writer of a device's announcement.
class DeviceWriter {
 public:
  virtual ~DeviceWriter() = default;
  virtual void write(const ObservedDevice& device, std::uint64_t sequence_number,
                     std::int64_t source_time_ns) = 0;
  virtual void dispose(const std::string& device_uuid) = 0;
};

// One partition set's writers.
class Publisher {
 public:
  virtual ~Publisher() = default;
  // `kind` is one of the four state-sample kinds; for Request and Response,
  // `interaction` is the detail::interaction_index of the topic.
  virtual std::unique_ptr<ValueWriter> value_writer(TopicKind kind, std::size_t interaction,
                                                    const qos::EndpointQos& qos) = 0;
  virtual std::unique_ptr<HeartbeatWriter> heartbeat_writer(const qos::EndpointQos& qos) = 0;
  virtual std::unique_ptr<DeviceWriter> device_writer(const qos::EndpointQos& qos) = 0;
  // Announces every writer again (a repair a middleware may need after a
  // one-sided participant drop: docs/multihost.md, "Cable pull"); how many.
  virtual std::size_t reannounce() = 0;
  // Waits until every matched reader acknowledged every sample, at most
  // `bound`: false when some did not.
  virtual bool wait_for_acknowledgments(std::chrono::nanoseconds bound) = 0;
};

// The readers of one partition set: every sample and status arrives at the
// sink as a TapEvent.
class Tap {
 public:
  virtual ~Tap() = default;
  virtual TapCounts counts() const noexcept = 0;
  // Publisher::reannounce for the readers; how many.
  virtual std::size_t reannounce() = 0;
};

// One participant in one domain: an Equipment's or a DomainObserver's.
class Participant {
 public:
  virtual ~Participant() = default;
  // The RTPS GUID prefix: what a writer handle's participant_of() returns
  // for this participant's writers, and what a paired value names.
  virtual ParticipantKey key() const = 0;
  // The implementation this participant really runs on: what the tools
  // print, so that a test can tell a choice that was ignored.
  virtual Middleware middleware() const noexcept = 0;
  virtual std::unique_ptr<Publisher> publisher(const std::vector<std::string>& partitions) = 0;
  virtual std::unique_ptr<Tap> tap(const TapConfig& config, TapSink sink) = 0;
};

// A Fast DDS participant: the configuration checked (a bad one is a
// ConfigError), intra-process delivery off (domain_tap.hpp,
// deliver_through_transports), topics made on first use with
// `config.timing`'s QoS.
std::unique_ptr<Participant> make_fastdds_participant(int domain_id,
                                                      const qos::ParticipantConfig& config);

// The participant of `middleware` (select.cpp): a ConfigError when this
// build lacks it.
std::unique_ptr<Participant> make_participant(Middleware middleware, int domain_id,
                                              const qos::ParticipantConfig& config);

}  // namespace mtc::dds::mw
