// The two ends of an interop test on one interaction topic: a Fast DDS side
// built from the runtime's own RAII wrappers, type support (the RTPS key
// hash) and QoS presets, and a Cyclone DDS side built from the types idlc
// generates from the same IDL and the same presets mapped by mtc::qos_cyclone.
// Writers publish in the device's partition, readers subscribe to every
// device's ("mtc/dev/*"), as the runtime does. The Cyclone side takes the
// topic descriptor of its type (mtc_idl_InteractionSample_desc, or that of a
// test fixture of another version of the type under the same name).
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "cyclone_entities.hpp"
#include "mtc/dds/detail/entities.hpp"
#include "mtc/dds/detail/topics.hpp"
#include "mtc/idl/mtconnect_interfacesPubSubTypes.h"
#include "mtc/idl/type_support.hpp"
#include "mtc/qos/cyclone_qos.hpp"
#include "mtc/qos/participant_qos.hpp"
#include "mtc/qos/presets.hpp"
#include "transport.hpp"

namespace mtc::test::interop {

namespace detail = mtc::dds::detail;
namespace fdds = detail::fdds;

inline const std::string kTopic = "mtc/InteractionResponse/MATERIAL_LOAD";
inline const std::string kTypeName = "mtc::idl::InteractionSample";
inline const std::string kDevice = "robot-1";

// Polls `done` until it holds or `timeout` passes (the condition is another
// process's or thread's progress; the poll period only bounds the latency).
template <typename Predicate>
bool wait_until(Predicate done, std::chrono::milliseconds timeout = std::chrono::seconds(15)) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (!done()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

class FastSide {
 public:
  explicit FastSide(int domain)
      : participant_(domain, qos::participant_qos(loopback<qos::ParticipantConfig>())) {
    participant_.register_type(idl::type_support<idl::InteractionSamplePubSubType>());
    topic_.emplace(participant_, kTopic, kTypeName, qos::state_topic().topic_qos());
  }

 protected:
  detail::Participant participant_;
  std::optional<detail::Topic> topic_;
};

class FastWriter : public FastSide {
 public:
  explicit FastWriter(int domain)
      : FastSide(domain),
        publisher_(participant_, {detail::topics::device_partition(kDevice)}),
        writer_(publisher_, *topic_, qos::state_topic().writer_qos(), listener_) {}
  detail::Writer<idl::InteractionSample>& writer() { return writer_; }
  int matched() const {
    fdds::PublicationMatchedStatus status;
    if (writer_.get().get_publication_matched_status(status) != ReturnCode::RETCODE_OK) return 0;
    return status.current_count;
  }

 private:
  using ReturnCode = eprosima::fastrtps::types::ReturnCode_t;
  struct QuietListener : fdds::DataWriterListener {};
  detail::Publisher publisher_;
  QuietListener listener_;
  detail::Writer<idl::InteractionSample> writer_;
};

class FastReader : public FastSide {
 public:
  explicit FastReader(int domain)
      : FastSide(domain),
        subscriber_(participant_, {detail::topics::kAllDevicesPartition}),
        reader_(subscriber_, *topic_, qos::state_topic().reader_qos(), nullptr) {}
  fdds::DataReader& reader() { return reader_.get(); }
  int matched() const {
    fdds::SubscriptionMatchedStatus status;
    if (reader_.get().get_subscription_matched_status(status) !=
        eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK) {
      return 0;
    }
    return status.current_count;
  }

 private:
  detail::Subscriber subscriber_;
  detail::Reader reader_;
};

class CycloneSide {
 public:
  CycloneSide(int domain, const dds_topic_descriptor_t& type)
      : participant_(domain, qos::cyclone_loopback_config()),
        topic_(dds_create_topic(participant_.get(), &type, kTopic.c_str(),
                                qos::cyclone_topic_qos(qos::state_topic()).get(), nullptr),
               "dds_create_topic") {}

 protected:
  cyclone::DomainParticipant participant_;
  cyclone::Entity topic_;
};

class CycloneWriter : public CycloneSide {
 public:
  CycloneWriter(int domain, const dds_topic_descriptor_t& type)
      : CycloneSide(domain, type),
        publisher_(
            dds_create_publisher(
                participant_.get(),
                qos::cyclone_partition_qos({detail::topics::device_partition(kDevice)}).get(),
                nullptr),
            "dds_create_publisher"),
        writer_(dds_create_writer(publisher_.get(), topic_.get(),
                                  qos::cyclone_writer_qos(qos::state_topic()).get(), nullptr),
                "dds_create_writer") {}
  dds_entity_t get() const noexcept { return writer_.get(); }
  int matched() const {
    dds_publication_matched_status_t status{};
    cyclone::check(dds_get_publication_matched_status(writer_.get(), &status),
                   "dds_get_publication_matched_status");
    return static_cast<int>(status.current_count);
  }

 private:
  cyclone::Entity publisher_;
  cyclone::Entity writer_;
};

class CycloneReader : public CycloneSide {
 public:
  CycloneReader(int domain, const dds_topic_descriptor_t& type)
      : CycloneSide(domain, type),
        subscriber_(
            dds_create_subscriber(
                participant_.get(),
                qos::cyclone_partition_qos({detail::topics::kAllDevicesPartition}).get(), nullptr),
            "dds_create_subscriber"),
        reader_(dds_create_reader(subscriber_.get(), topic_.get(),
                                  qos::cyclone_reader_qos(qos::state_topic()).get(), nullptr),
                "dds_create_reader") {}
  dds_entity_t get() const noexcept { return reader_.get(); }
  int matched() const {
    dds_subscription_matched_status_t status{};
    cyclone::check(dds_get_subscription_matched_status(reader_.get(), &status),
                   "dds_get_subscription_matched_status");
    return static_cast<int>(status.current_count);
  }

 private:
  cyclone::Entity subscriber_;
  cyclone::Entity reader_;
};

}  // namespace mtc::test::interop
