#include "mtc/qos/endpoint_qos.hpp"

#include <algorithm>

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

EndpointQos& EndpointQos::reliable() noexcept {
  reliability_ = Reliability::Reliable;
  return *this;
}
EndpointQos& EndpointQos::best_effort() noexcept {
  reliability_ = Reliability::BestEffort;
  return *this;
}
EndpointQos& EndpointQos::transient_local() noexcept {
  durability_ = Durability::TransientLocal;
  return *this;
}
EndpointQos& EndpointQos::durability_volatile() noexcept {
  durability_ = Durability::Volatile;
  return *this;
}
EndpointQos& EndpointQos::keep_last(std::int32_t depth) noexcept {
  keep_all_ = false;
  depth_ = depth > 0 ? depth : 1;
  return *this;
}
EndpointQos& EndpointQos::keep_all() noexcept {
  keep_all_ = true;
  return *this;
}
EndpointQos& EndpointQos::deadline(std::chrono::nanoseconds period) noexcept {
  deadline_ = period;
  return *this;
}
EndpointQos& EndpointQos::liveliness_manual_by_topic(std::chrono::nanoseconds lease) noexcept {
  return liveliness(Liveliness::ManualByTopic, lease);
}
EndpointQos& EndpointQos::liveliness(Liveliness kind, std::chrono::nanoseconds lease) noexcept {
  liveliness_ = kind;
  lease_ = lease;
  return *this;
}
EndpointQos& EndpointQos::exclusive_ownership(std::int32_t strength) noexcept {
  ownership_ = Ownership::Exclusive;
  strength_ = strength;
  return *this;
}
EndpointQos& EndpointQos::shared_ownership() noexcept {
  ownership_ = Ownership::Shared;
  strength_ = 0;
  return *this;
}
EndpointQos& EndpointQos::reliable_heartbeat(std::chrono::nanoseconds period) noexcept {
  rtps_heartbeat_ = period;
  return *this;
}
EndpointQos& EndpointQos::reader_depth(std::int32_t depth) noexcept {
  reader_depth_ = depth > 0 ? depth : 1;
  return *this;
}
EndpointQos& EndpointQos::max_instances(std::int32_t count) noexcept {
  max_instances_ = count > 0 ? count : 1;
  return *this;
}
EndpointQos& EndpointQos::reader_max_instances(std::int32_t count) noexcept {
  reader_max_instances_ = count > 0 ? count : 1;
  return *this;
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

fdds::DataWriterQos EndpointQos::writer_qos() const {
  fdds::DataWriterQos q = fdds::DATAWRITER_QOS_DEFAULT;
  apply_common(*this, q);
  q.ownership_strength().value = static_cast<std::uint32_t>(strength_);
  if (rtps_heartbeat_) {
    q.reliable_writer_qos().times.heartbeatPeriod = to_duration(*rtps_heartbeat_);
  }
  // Keyed types cannot use data-sharing in 2.9; say so instead of AUTO.
  q.data_sharing().off();
  return q;
}

fdds::DataReaderQos EndpointQos::reader_qos() const {
  fdds::DataReaderQos q = fdds::DATAREADER_QOS_DEFAULT;
  auto reader = *this;
  if (!keep_all_) reader.keep_last(reader_depth());
  reader.max_instances(reader_max_instances());
  apply_common(reader, q);
  q.data_sharing().off();
  return q;
}

fdds::TopicQos EndpointQos::topic_qos() const {
  fdds::TopicQos q = fdds::TOPIC_QOS_DEFAULT;
  apply_common(*this, q);
  return q;
}

}  // namespace mtc::qos
