#include "mtc/qos/fastdds_qos.hpp"

#include <algorithm>
#include <cstdint>

namespace mtc::qos {

namespace fdds = eprosima::fastdds::dds;

eprosima::fastrtps::Duration_t to_duration(std::chrono::nanoseconds d) noexcept {
  const auto secs = std::chrono::duration_cast<std::chrono::seconds>(d);
  const auto nanos = d - secs;
  return eprosima::fastrtps::Duration_t(static_cast<std::int32_t>(secs.count()),
                                        static_cast<std::uint32_t>(nanos.count()));
}

std::chrono::nanoseconds to_chrono(const eprosima::fastrtps::Duration_t& d) noexcept {
  if (d == eprosima::fastrtps::c_TimeInfinite) {
    return std::chrono::nanoseconds::max();
  }
  return std::chrono::seconds(d.seconds) + std::chrono::nanoseconds(d.nanosec);
}

namespace {

// Policies shared by the writer, reader and topic QoS classes (they have the
// same accessor names but no common base).
template <typename Qos>
void apply_common(const EndpointQos& e, Qos& q) {
  q.reliability().kind = e.reliability() == Reliability::Reliable
                             ? fdds::RELIABLE_RELIABILITY_QOS
                             : fdds::BEST_EFFORT_RELIABILITY_QOS;
  q.durability().kind = e.durability() == Durability::TransientLocal
                            ? fdds::TRANSIENT_LOCAL_DURABILITY_QOS
                            : fdds::VOLATILE_DURABILITY_QOS;
  if (e.is_keep_all()) {
    q.history().kind = fdds::KEEP_ALL_HISTORY_QOS;
  } else {
    q.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
    q.history().depth = e.depth();
  }
  // Explicit limits: one instance per data item, `depth` samples each.
  const std::int32_t per_instance = e.is_keep_all() ? 64 : e.depth();
  q.resource_limits().max_instances = e.max_instances();
  q.resource_limits().max_samples_per_instance = per_instance;
  q.resource_limits().max_samples = e.max_instances() * per_instance;
  q.resource_limits().allocated_samples = std::min(100, q.resource_limits().max_samples);
  if (e.deadline()) {
    q.deadline().period = to_duration(*e.deadline());
  }
  switch (e.liveliness_kind()) {
    case Liveliness::Automatic:
      q.liveliness().kind = fdds::AUTOMATIC_LIVELINESS_QOS;
      break;
    case Liveliness::ManualByParticipant:
      q.liveliness().kind = fdds::MANUAL_BY_PARTICIPANT_LIVELINESS_QOS;
      break;
    case Liveliness::ManualByTopic:
      q.liveliness().kind = fdds::MANUAL_BY_TOPIC_LIVELINESS_QOS;
      break;
  }
  if (e.liveliness_lease()) {
    q.liveliness().lease_duration = to_duration(*e.liveliness_lease());
    // Only used by AUTOMATIC/MANUAL_BY_PARTICIPANT writers; keep it a safe
    // fraction of the lease so Fast DDS accepts the QoS.
    q.liveliness().announcement_period = to_duration(*e.liveliness_lease() / 3);
  }
  q.ownership().kind = e.ownership() == Ownership::Exclusive ? fdds::EXCLUSIVE_OWNERSHIP_QOS
                                                             : fdds::SHARED_OWNERSHIP_QOS;
}

}  // namespace

std::chrono::nanoseconds nack_suppression(std::chrono::nanoseconds heartbeat_period) noexcept {
  constexpr std::chrono::nanoseconds kFastDdsHeartbeatResponseDelay = std::chrono::milliseconds(5);
  return std::min(heartbeat_period / 4, kFastDdsHeartbeatResponseDelay);
}

fdds::DataWriterQos fastdds_writer_qos(const EndpointQos& endpoint) {
  fdds::DataWriterQos q = fdds::DATAWRITER_QOS_DEFAULT;
  apply_common(endpoint, q);
  q.ownership_strength().value = static_cast<std::uint32_t>(endpoint.ownership_strength());
  if (const auto period = endpoint.reliable_heartbeat()) {
    q.reliable_writer_qos().times.heartbeatPeriod = to_duration(*period);
    q.reliable_writer_qos().times.nackSupressionDuration = to_duration(nack_suppression(*period));
  }
  // Keyed types cannot use data-sharing in 2.9; say so instead of AUTO.
  q.data_sharing().off();
  return q;
}

fdds::DataReaderQos fastdds_reader_qos(const EndpointQos& endpoint) {
  fdds::DataReaderQos q = fdds::DATAREADER_QOS_DEFAULT;
  // The reader's own depth and instance bound stand in for the writer's.
  auto reader = endpoint;
  if (!endpoint.is_keep_all()) reader.keep_last(endpoint.reader_depth());
  reader.max_instances(endpoint.reader_max_instances());
  apply_common(reader, q);
  q.data_sharing().off();
  return q;
}

void announcement_memory(fdds::DataWriterQos& q) noexcept {
  q.endpoint().history_memory_policy = eprosima::fastrtps::rtps::DYNAMIC_REUSABLE_MEMORY_MODE;
}

void announcement_memory(fdds::DataReaderQos& q) noexcept {
  q.resource_limits().allocated_samples = 1;
}

fdds::TopicQos fastdds_topic_qos(const EndpointQos& endpoint) {
  fdds::TopicQos q = fdds::TOPIC_QOS_DEFAULT;
  apply_common(endpoint, q);
  return q;
}

}  // namespace mtc::qos
