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
#include <utility>
#include <vector>

#include "cyclone_entities.hpp"
#include "mtc/dds/detail/entities.hpp"
#include "mtc/dds/detail/topics.hpp"
#include "mtc/idl/mtconnect_interfacesPubSubTypes.h"
#include "mtc/idl/type_support.hpp"
#include "mtc/qos/cyclone_qos.hpp"
#include "mtc/qos/fastdds_qos.hpp"
#include "mtc/qos/participant_qos.hpp"
#include "mtc/qos/presets.hpp"
#include "transport.hpp"

namespace mtc::test::interop {

namespace detail = mtc::dds::detail;
namespace fdds = detail::fdds;

inline const std::string kDevice = "robot-1";

// A topic as both sides create it: name, type name (the same string in the
// fastddsgen and idlc output) and the preset of its role.
struct TopicSpec {
  std::string name;
  std::string type_name;
  qos::EndpointQos qos;
};

// The interaction topic the tests use (a responder's MATERIAL_LOAD items).
inline TopicSpec interaction_spec() {
  return {"mtc/InteractionResponse/MATERIAL_LOAD", "mtc::idl::InteractionSample",
          qos::state_topic()};
}

// The heartbeat topic with the preset of equipment (DEADLINE and
// MANUAL_BY_TOPIC liveliness of `timing.lease()`).
inline TopicSpec heartbeat_spec(const qos::Timing& timing = {}) {
  return {detail::topics::kHeartbeat, "mtc::idl::Heartbeat", qos::heartbeat_topic(timing)};
}

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

// PubSub is the fastddsgen type support of the topic's type.
template <typename PubSub>
class FastSide {
 public:
  FastSide(int domain, TopicSpec spec)
      : spec_(std::move(spec)),
        participant_(domain, qos::participant_qos(loopback<qos::ParticipantConfig>())) {
    participant_.register_type(idl::type_support<PubSub>());
    topic_.emplace(participant_, spec_.name, spec_.type_name,
                   mtc::qos::fastdds_topic_qos(spec_.qos));
  }

 protected:
  using ReturnCode = eprosima::fastrtps::types::ReturnCode_t;
  TopicSpec spec_;
  detail::Participant participant_;
  std::optional<detail::Topic> topic_;
};

template <typename PubSub>
class FastWriter : public FastSide<PubSub> {
 public:
  using Sample = typename PubSub::type;
  FastWriter(int domain, TopicSpec spec)
      : FastSide<PubSub>(domain, std::move(spec)),
        publisher_(this->participant_, {detail::topics::device_partition(kDevice)}),
        writer_(publisher_, *this->topic_, mtc::qos::fastdds_writer_qos(this->spec_.qos),
                listener_) {}
  detail::Writer<Sample>& writer() { return writer_; }
  int matched() const {
    fdds::PublicationMatchedStatus status;
    if (writer_.get().get_publication_matched_status(status) != ReturnCode::RETCODE_OK) return 0;
    return status.current_count;
  }

 private:
  using ReturnCode = typename FastSide<PubSub>::ReturnCode;
  struct QuietListener : fdds::DataWriterListener {};
  detail::Publisher publisher_;
  QuietListener listener_;
  detail::Writer<Sample> writer_;
};

template <typename PubSub>
class FastReader : public FastSide<PubSub> {
 public:
  FastReader(int domain, TopicSpec spec)
      : FastSide<PubSub>(domain, std::move(spec)),
        subscriber_(this->participant_, {detail::topics::kAllDevicesPartition}),
        reader_(subscriber_, *this->topic_, mtc::qos::fastdds_reader_qos(this->spec_.qos),
                nullptr) {}
  fdds::DataReader& reader() { return reader_.get(); }
  int matched() const {
    fdds::SubscriptionMatchedStatus status;
    if (reader_.get().get_subscription_matched_status(status) != ReturnCode::RETCODE_OK) return 0;
    return status.current_count;
  }

 private:
  using ReturnCode = typename FastSide<PubSub>::ReturnCode;
  detail::Subscriber subscriber_;
  detail::Reader reader_;
};

class CycloneSide {
 public:
  CycloneSide(int domain, const dds_topic_descriptor_t& type, TopicSpec spec)
      : spec_(std::move(spec)),
        participant_(domain, qos::cyclone_loopback_config()),
        topic_(dds_create_topic(participant_.get(), &type, spec_.name.c_str(),
                                qos::cyclone_topic_qos(spec_.qos).get(), nullptr),
               "dds_create_topic") {}

 protected:
  TopicSpec spec_;
  cyclone::DomainParticipant participant_;
  cyclone::Entity topic_;
};

class CycloneWriter : public CycloneSide {
 public:
  CycloneWriter(int domain, const dds_topic_descriptor_t& type, TopicSpec spec)
      : CycloneSide(domain, type, std::move(spec)),
        publisher_(
            dds_create_publisher(
                participant_.get(),
                qos::cyclone_partition_qos({detail::topics::device_partition(kDevice)}).get(),
                nullptr),
            "dds_create_publisher"),
        writer_(dds_create_writer(publisher_.get(), topic_.get(),
                                  qos::cyclone_writer_qos(spec_.qos).get(), nullptr),
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
  CycloneReader(int domain, const dds_topic_descriptor_t& type, TopicSpec spec)
      : CycloneSide(domain, type, std::move(spec)),
        subscriber_(
            dds_create_subscriber(
                participant_.get(),
                qos::cyclone_partition_qos({detail::topics::kAllDevicesPartition}).get(), nullptr),
            "dds_create_subscriber"),
        reader_(dds_create_reader(subscriber_.get(), topic_.get(),
                                  qos::cyclone_reader_qos(spec_.qos).get(), nullptr),
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
