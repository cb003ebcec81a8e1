// A hand-driven counterpart: publishes one interaction data item the way a
// (possibly misbehaving) device of another vendor would (changes only, plus
// a heartbeat every 100 ms announcing its newest change), so tests can
// produce states the Equipment API never would (scenarios 4 and 5, protocol
// violations).
#pragma once

#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "mtc/dds/detail/entities.hpp"
#include "mtc/dds/detail/heartbeat_writer.hpp"
#include "mtc/dds/detail/return_code.hpp"
#include "mtc/dds/detail/topics.hpp"
#include "mtc/idl/mtconnect_interfacesPubSubTypes.h"
#include "mtc/idl/type_support.hpp"
#include "mtc/qos/fastdds_qos.hpp"
#include "mtc/qos/participant_qos.hpp"
#include "mtc/qos/presets.hpp"
#include "transport.hpp"

namespace mtc::dds::testing {

// Raw peers build their entities from the runtime's internals.
namespace fdds = detail::fdds;
namespace topics = detail::topics;
using detail::HeartbeatWriter;
using detail::Participant;
using detail::Publisher;
using detail::Topic;
using detail::Writer;

class RawPeer {
 public:
  // `paired_with`: the device whose interface mh1 it names as its pairing
  // (a requester goes ACTIVE only toward a response that names it).
  RawPeer(int domain, const std::string& uuid, core::SubType side, core::Service service,
          const std::string& paired_with = "")
      : participant_(domain, qos::participant_qos(mtc::test::loopback<qos::ParticipantConfig>())),
        publisher_(participant_, {topics::device_partition(uuid)}),
        heartbeat_(participant_, publisher_, uuid),
        side_(side),
        service_(service) {
    participant_.register_type(idl::type_support<idl::InteractionSamplePubSubType>());
    topic_ = std::make_unique<Topic>(participant_, topics::interaction_topic(side, service),
                                     "mtc::idl::InteractionSample",
                                     qos::fastdds_topic_qos(qos::state_topic()));
    writer_ = std::make_unique<Writer<idl::InteractionSample>>(
        publisher_, *topic_, qos::fastdds_writer_qos(qos::state_topic()), listener_);
    sample_.device_uuid(uuid);
    sample_.interface_id("mh1");
    sample_.paired_device_uuid(paired_with);
    sample_.paired_interface_id(paired_with.empty() ? "" : "mh1");
    sample_.data_item_id(topics::interaction_item_id("mh1", service, side));
    sample_.service(topics::to_idl(service));
    sample_.sub_type(topics::to_idl(side));
    thread_ = std::thread([this] { heartbeat(); });
  }
  RawPeer(const RawPeer&) = delete;
  RawPeer& operator=(const RawPeer&) = delete;
  ~RawPeer() { stop_beating(); }
  // The leave said in data without the disposals that follow it, as a
  // reader of another vendor gets a Fast DDS device's graceful end: the
  // heartbeats stop with a last one of period 0; the participant and its
  // writers live on.
  void leave_without_disposal() {
    stop_beating();
    std::lock_guard<std::mutex> lock(mutex_);
    heartbeat_.leave();
  }
  // Every matched reader has acknowledged every value (Fast DDS calls a
  // reader's listener before its acknowledgment goes out, so the value has
  // also been handed to the reading Equipment's executor).
  bool acknowledged(std::chrono::seconds bound) {
    return writer_->get().wait_for_acknowledgments(eprosima::fastrtps::Duration_t(
               static_cast<std::int32_t>(bound.count()), 0)) == detail::ReturnCode::RETCODE_OK;
  }
  // A change of value: new change number.
  void set(core::InteractionState state) {
    std::lock_guard<std::mutex> lock(mutex_);
    sample_.state(topics::to_idl(state));
    sample_.sequence_number(sample_.sequence_number() + 1);
    sample_.source_time_ns(topics::realtime_ns());
    writer_->write(sample_);
  }

 private:
  void stop_beating() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    cv_.notify_all();
    if (thread_.joinable()) thread_.join();
  }
  // The heartbeat every real device writes (a timer, not a synchronisation
  // sleep), announcing the newest change.
  void heartbeat() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!cv_.wait_for(lock, std::chrono::milliseconds(100), [this] { return stop_; })) {
      if (sample_.sequence_number() == 0) continue;
      heartbeat_.announce_interaction(service_, side_, sample_.sequence_number());
      heartbeat_.beat();
    }
  }

  struct QuietListener : fdds::DataWriterListener {};
  Participant participant_;
  Publisher publisher_;
  HeartbeatWriter heartbeat_;
  core::SubType side_;
  core::Service service_;
  QuietListener listener_;
  std::unique_ptr<Topic> topic_;
  std::unique_ptr<Writer<idl::InteractionSample>> writer_;
  idl::InteractionSample sample_;
  std::mutex mutex_;
  std::condition_variable cv_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace mtc::dds::testing
