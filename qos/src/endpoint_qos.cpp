#include "mtc/qos/endpoint_qos.hpp"

namespace mtc::qos {

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

}  // namespace mtc::qos
