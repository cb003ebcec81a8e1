#include "mtc/qos/presets.hpp"

#include <fstream>
#include <stdexcept>

namespace mtc::qos {

namespace {

// Every data item is an instance: a writer holds its device's items, a
// reader may see every device's (the Fast DDS default of 10 would silently
// refuse larger devices and cells).
constexpr std::int32_t kWriterMaxInstances = 1024;
constexpr std::int32_t kReaderMaxInstances = 16384;

}  // namespace

void validate(const Timing& timing) {
  using std::chrono::milliseconds;
  if (timing.heartbeat <= milliseconds::zero()) {
    throw std::invalid_argument("qos timing: heartbeat period must be positive");
  }
  if (timing.missed_heartbeats < 2) {
    throw std::invalid_argument(
        "qos timing: missed_heartbeats must be at least 2, otherwise scheduling jitter "
        "alone declares a healthy peer lost");
  }
  if (timing.reliable_heartbeat <= milliseconds::zero()) {
    throw std::invalid_argument("qos timing: reliable_heartbeat must be positive");
  }
  if (timing.reliable_heartbeat >= timing.lease()) {
    throw std::invalid_argument(
        "qos timing: reliable_heartbeat must be shorter than the lease, otherwise a single "
        "lost packet is repaired only after the peer has been declared lost");
  }
  if (timing.participant_announcement <= milliseconds::zero() ||
      timing.participant_lease <= timing.participant_announcement) {
    throw std::invalid_argument(
        "qos timing: participant_lease must be longer than participant_announcement (> 0)");
  }
}

EndpointQos state_topic(const Timing& timing) {
  validate(timing);
  return EndpointQos()
      .reliable()
      .transient_local()
      .keep_last(1)
      .reader_depth(8)
      .reliable_heartbeat(timing.reliable_heartbeat)
      .shared_ownership()
      .max_instances(kWriterMaxInstances)
      .reader_max_instances(kReaderMaxInstances);
}

EndpointQos state_observer_topic(const Timing& timing) {
  validate(timing);
  return EndpointQos()
      .reliable()
      .transient_local()
      .keep_last(1)
      .reader_depth(8)
      .shared_ownership()
      .max_instances(kReaderMaxInstances);
}

EndpointQos heartbeat_topic(const Timing& timing) {
  validate(timing);
  return EndpointQos()
      .reliable()
      .transient_local()
      .keep_last(1)
      .deadline(timing.lease())
      .liveliness_manual_by_topic(timing.lease())
      .reliable_heartbeat(timing.reliable_heartbeat)
      .shared_ownership()
      .max_instances(kWriterMaxInstances)
      .reader_max_instances(kReaderMaxInstances);
}

EndpointQos heartbeat_observer_topic(const Timing& timing) {
  validate(timing);
  return EndpointQos()
      .reliable()
      .transient_local()
      .keep_last(1)
      .liveliness_manual_by_topic(timing.lease())
      .shared_ownership()
      .max_instances(kReaderMaxInstances);
}

EndpointQos device_description_topic(const Timing& timing) {
  validate(timing);
  return EndpointQos()
      .reliable()
      .transient_local()
      .keep_last(1)
      .reliable_heartbeat(timing.reliable_heartbeat)
      .shared_ownership()
      .max_instances(kWriterMaxInstances)
      .reader_max_instances(kReaderMaxInstances);
}

EndpointQos preset(std::string_view name, const Timing& timing) {
  if (name.empty() || name == kStateProfile) {
    return state_topic(timing);
  }
  if (name == kDeviceDescriptionProfile) {
    return device_description_topic(timing);
  }
  if (name == kStateObserverProfile) {
    return state_observer_topic(timing);
  }
  if (name == kHeartbeatProfile) {
    return heartbeat_topic(timing);
  }
  if (name == kHeartbeatObserverProfile) {
    return heartbeat_observer_topic(timing);
  }
  std::string known;
  for (const auto& n : preset_names()) {
    known += (known.empty() ? "" : ", ") + n;
  }
  throw std::invalid_argument("unknown QoS preset '" + std::string(name) + "' (known: " + known +
                              ")");
}

std::vector<std::string> preset_names() {
  return {std::string(kStateProfile), std::string(kDeviceDescriptionProfile),
          std::string(kStateObserverProfile), std::string(kHeartbeatProfile),
          std::string(kHeartbeatObserverProfile)};
}

std::string profiles_file_path() {
  // Prefer the installed copy; a build tree that was never installed uses
  // the source copy, which is the same file.
  std::string installed = MTC_QOS_PROFILES_INSTALLED;
  if (std::ifstream(installed).good()) {
    return installed;
  }
  return MTC_QOS_PROFILES_SOURCE;
}

}  // namespace mtc::qos
