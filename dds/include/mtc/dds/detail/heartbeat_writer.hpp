// Internal: a device's heartbeat written by hand, for raw peers (tests,
// benchmarks) that play a device without the Equipment runtime. Same topic,
// type support, partition (the publisher's) and QoS as the runtime's own
// heartbeat (qos::heartbeat_topic); the caller decides when to beat and
// which change numbers to announce.
#pragma once

#include <algorithm>
#include <cstdint>
#include <iterator>
#include <memory>
#include <string>

#include "mtc/dds/detail/entities.hpp"
#include "mtc/dds/detail/topics.hpp"
#include "mtc/idl/mtconnect_interfacesPubSubTypes.h"
#include "mtc/idl/type_support.hpp"
#include "mtc/qos/fastdds_qos.hpp"
#include "mtc/qos/presets.hpp"

namespace mtc::dds::detail {

class HeartbeatWriter {
 public:
  // Creates the participant's mtc/Heartbeat topic: a participant may hold
  // one HeartbeatWriter (or one runtime) at a time.
  HeartbeatWriter(Participant& participant, Publisher& publisher, const std::string& device_uuid,
                  std::uint32_t group = 0, const qos::Timing& timing = {}) {
    auto type = idl::type_support<idl::HeartbeatPubSubType>();
    participant.register_type(type);
    topic_ = std::make_unique<Topic>(participant, topics::kHeartbeat, type.get_type_name(),
                                     qos::fastdds_topic_qos(qos::heartbeat_topic(timing)));
    writer_ = std::make_unique<Writer<idl::Heartbeat>>(
        publisher, *topic_, qos::fastdds_writer_qos(qos::heartbeat_topic(timing)), listener_);
    sample_.device_uuid(device_uuid);
    sample_.group(group);
    sample_.period_ms(static_cast<std::uint32_t>(timing.heartbeat.count()));
    sample_.lease_ms(static_cast<std::uint32_t>(timing.lease().count()));
  }

  // The next heartbeat: set the change numbers to announce here.
  idl::Heartbeat& sample() noexcept { return sample_; }
  // Announces `changes` as the newest change of the peer's one interaction
  // writer of (service, side): its interaction_changes entry and the side's
  // total.
  void announce_interaction(core::Service service, core::SubType side, std::uint64_t changes) {
    const auto idl_service = topics::to_idl(service);
    const auto idl_side = topics::to_idl(side);
    auto& entries = sample_.interaction_changes();
    auto it = std::find_if(entries.begin(), entries.end(), [&](const auto& c) {
      return c.service() == idl_service && c.sub_type() == idl_side;
    });
    if (it == entries.end()) {
      entries.emplace_back();
      it = std::prev(entries.end());
      it->service(idl_service);
      it->sub_type(idl_side);
    }
    it->changes(changes);
    if (side == core::SubType::Request) {
      sample_.request_changes(changes);
    } else {
      sample_.response_changes(changes);
    }
  }
  // Writes one heartbeat (beat counter bumped, source time now).
  void beat() {
    sample_.beat(sample_.beat() + 1);
    sample_.source_time_ns(topics::realtime_ns());
    writer_->write(sample_);
  }
  // The leave said in data: one last heartbeat with period_ms 0, what the
  // runtime writes before it disposes (idl: Heartbeat.period_ms).
  void leave() {
    sample_.period_ms(0);
    beat();
  }
  // Asserts the writer's liveliness without writing a heartbeat.
  void assert_liveliness() { writer_->assert_liveliness(); }
  // Disposes the instance (a graceful leave).
  void dispose() { writer_->dispose(sample_); }

 private:
  struct QuietListener : fdds::DataWriterListener {};
  QuietListener listener_;
  std::unique_ptr<Topic> topic_;
  std::unique_ptr<Writer<idl::Heartbeat>> writer_;
  idl::Heartbeat sample_;
};

}  // namespace mtc::dds::detail
