// The Fast DDS backend of mw::Participant: the RAII entities of
// mtc/dds/detail/entities.hpp, the fastddsgen types (fastdds_samples.hpp)
// and the readers of domain_tap.hpp behind the vendor-neutral interface.
#include <fastdds/rtps/common/Time_t.h>

#include <memory>
#include <string>
#include <vector>

#include "../domain_tap.hpp"
#include "fastdds_samples.hpp"
#include "middleware.hpp"
#include "mtc/dds/detail/entities.hpp"
#include "mtc/dds/detail/return_code.hpp"
#include "mtc/qos/fastdds_qos.hpp"

namespace mtc::dds::mw {

namespace {

namespace fdds = eprosima::fastdds::dds;

// Every writer gets a listener of its own (entities.hpp: Fast DDS 2.9.1
// crashes when an offered-deadline miss reaches a publisher without one).
struct QuietWriterListener : fdds::DataWriterListener {};

// A value writer of one IDL state-sample type. The sample is built on the
// stack: its strings are fixed-size, so a write allocates nothing.
template <typename Sample>
class FastValueWriter final : public ValueWriter {
 public:
  FastValueWriter(detail::Publisher& publisher, detail::Topic& topic, const qos::EndpointQos& q)
      : writer_(publisher, topic, qos::fastdds_writer_qos(q), listener_) {}

  void write(const ObservedValue& value, const ParticipantKey& paired) override {
    Sample s;
    fastdds::to_idl(value, paired, s);
    writer_.write(s);
  }
  void dispose(const std::string& device_uuid, const std::string& data_item_id) override {
    Sample s;
    s.device_uuid(device_uuid);
    s.data_item_id(data_item_id);
    writer_.dispose(s);
  }

 private:
  QuietWriterListener listener_;  // before the writer that uses it
  detail::Writer<Sample> writer_;
};

class FastHeartbeatWriter final : public HeartbeatWriter {
 public:
  FastHeartbeatWriter(detail::Publisher& publisher, detail::Topic& topic, const qos::EndpointQos& q)
      : writer_(publisher, topic, qos::fastdds_writer_qos(q), listener_) {}

  void write(const ObservedHeartbeat& heartbeat) override {
    idl::Heartbeat h;
    fastdds::to_idl(heartbeat, h);
    writer_.write(h);
  }
  void dispose(const std::string& device_uuid, std::uint32_t group) override {
    idl::Heartbeat h;
    h.device_uuid(device_uuid);
    h.group(group);
    writer_.dispose(h);
  }

 private:
  QuietWriterListener listener_;
  detail::Writer<idl::Heartbeat> writer_;
};

class FastDeviceWriter final : public DeviceWriter {
 public:
  FastDeviceWriter(detail::Publisher& publisher, detail::Topic& topic, const qos::EndpointQos& q)
      : writer_(publisher, topic, announcement_qos(q), listener_) {}

  void write(const ObservedDevice& device, std::uint64_t sequence_number,
             std::int64_t source_time_ns) override {
    idl::DeviceDescription d;
    fastdds::to_idl(device, sequence_number, source_time_ns, d);
    writer_.write(d);
  }
  void dispose(const std::string& device_uuid) override {
    idl::DeviceDescription d;
    d.device_uuid(device_uuid);
    writer_.dispose(d);
  }

 private:
  static eprosima::fastdds::dds::DataWriterQos announcement_qos(const qos::EndpointQos& q) {
    auto fast = qos::fastdds_writer_qos(q);
    qos::announcement_memory(fast);
    return fast;
  }

  QuietWriterListener listener_;
  detail::Writer<idl::DeviceDescription> writer_;
};

class FastPublisher final : public Publisher {
 public:
  FastPublisher(detail::Participant& participant, detail::TopicSet& topics,
                const std::vector<std::string>& partitions)
      : topics_(topics), publisher_(participant, partitions) {}

  std::unique_ptr<ValueWriter> value_writer(TopicKind kind, std::size_t interaction,
                                            const qos::EndpointQos& q) override {
    switch (kind) {
      case TopicKind::Request:
      case TopicKind::Response:
        return std::make_unique<FastValueWriter<idl::InteractionSample>>(
            publisher_, topics_.interaction(interaction), q);
      case TopicKind::InterfaceState:
        return std::make_unique<FastValueWriter<idl::InterfaceStateSample>>(publisher_,
                                                                            topics_.get(kind), q);
      case TopicKind::DoorState:
        return std::make_unique<FastValueWriter<idl::DoorStateSample>>(publisher_,
                                                                       topics_.get(kind), q);
      case TopicKind::ChuckState:
        return std::make_unique<FastValueWriter<idl::ChuckStateSample>>(publisher_,
                                                                        topics_.get(kind), q);
      case TopicKind::DeviceDescription:
      case TopicKind::Heartbeat:
        break;
    }
    throw ConfigError(std::string("mw::Publisher: ") + detail::topic_name(kind) +
                      " carries no state samples");
  }
  std::unique_ptr<HeartbeatWriter> heartbeat_writer(const qos::EndpointQos& q) override {
    return std::make_unique<FastHeartbeatWriter>(publisher_, topics_.get(TopicKind::Heartbeat), q);
  }
  std::unique_ptr<DeviceWriter> device_writer(const qos::EndpointQos& q) override {
    return std::make_unique<FastDeviceWriter>(publisher_, topics_.get(TopicKind::DeviceDescription),
                                              q);
  }
  std::size_t reannounce() override { return publisher_.reannounce(); }
  // Fast DDS 2.9.1 answers ERROR, not TIMEOUT, when the bound runs out.
  bool wait_for_acknowledgments(std::chrono::nanoseconds bound) override {
    const eprosima::fastrtps::Duration_t d(std::chrono::duration<double>(bound).count());
    return publisher_.get().wait_for_acknowledgments(d) == detail::ReturnCode::RETCODE_OK;
  }

 private:
  detail::TopicSet& topics_;
  detail::Publisher publisher_;
};

class FastTap final : public Tap {
 public:
  FastTap(detail::Participant& participant, detail::TopicSet& topics, const TapConfig& config,
          TapSink sink)
      : tap_(participant, topics, config, std::move(sink)) {}
  TapCounts counts() const noexcept override { return tap_.counts(); }
  std::size_t reannounce() override { return tap_.reannounce(); }

 private:
  detail::DomainTap tap_;
};

class FastParticipant final : public Participant {
 public:
  FastParticipant(int domain_id, const qos::ParticipantConfig& config)
      : participant_(domain_id, detail::checked_qos(config)),
        topics_(participant_, config.timing) {}

  ParticipantKey key() const override {
    ParticipantKey out{};
    const auto& prefix = participant_.get().guid().guidPrefix.value;
    std::copy(std::begin(prefix), std::end(prefix), out.begin());
    return out;
  }
  Middleware middleware() const noexcept override { return Middleware::FastDds; }
  std::unique_ptr<Publisher> publisher(const std::vector<std::string>& partitions) override {
    return std::make_unique<FastPublisher>(participant_, topics_, partitions);
  }
  std::unique_ptr<Tap> tap(const TapConfig& config, TapSink sink) override {
    return std::make_unique<FastTap>(participant_, topics_, config, std::move(sink));
  }

 private:
  detail::Participant participant_;
  detail::TopicSet topics_;  // after the participant: topics go first
};

}  // namespace

std::unique_ptr<Participant> make_fastdds_participant(int domain_id,
                                                      const qos::ParticipantConfig& config) {
  detail::deliver_through_transports();
  return std::make_unique<FastParticipant>(domain_id, config);
}

}  // namespace mtc::dds::mw
