#include "mtc/qos/presets.hpp"

#include <fstream>
#include <stdexcept>

namespace mtc::qos {

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
      .deadline(timing.lease())
      .liveliness_manual_by_topic(timing.lease())
      .reliable_heartbeat(timing.reliable_heartbeat)
      .shared_ownership()
      .max_instances(1024);
}

EndpointQos device_description_topic(const Timing& timing) {
  validate(timing);
  return EndpointQos()
      .reliable()
      .transient_local()
      .keep_last(1)
      .liveliness_manual_by_topic(timing.lease())
      .reliable_heartbeat(timing.reliable_heartbeat)
      .shared_ownership()
      .max_instances(1024);
}

EndpointQos preset(std::string_view name, const Timing& timing) {
  if (name.empty() || name == kStateProfile) {
    return state_topic(timing);
  }
  if (name == kDeviceDescriptionProfile) {
    return device_description_topic(timing);
  }
  std::string known;
  for (const auto& n : preset_names()) {
    known += (known.empty() ? "" : ", ") + n;
  }
  throw std::invalid_argument("unknown QoS preset '" + std::string(name) + "' (known: " +
                              known + ")");
}

std::vector<std::string> preset_names() {
  return {std::string(kStateProfile), std::string(kDeviceDescriptionProfile)};
}

std::string profiles_file_path() {
  // Prefer the installed copy; a build tree that was never installed uses
  // the source copy, which is the same file.
  const std::string installed = MTC_QOS_PROFILES_INSTALLED;
  if (std::ifstream(installed).good()) {
    return installed;
  }
  return MTC_QOS_PROFILES_SOURCE;
}

}  // namespace mtc::qos
