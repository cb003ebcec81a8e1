// Internal, vendor-neutral: names and reports of the tap events
// (mw/tap_events.hpp), the same whichever middleware read them.
#include "tap_events.hpp"

#include "mtc/dds/detail/topic_names.hpp"

namespace mtc::dds::detail {

const char* topic_name(TopicKind kind) noexcept {
  switch (kind) {
    case TopicKind::Request:
      return "mtc/InteractionRequest/*";
    case TopicKind::Response:
      return "mtc/InteractionResponse/*";
    case TopicKind::InterfaceState:
      return topics::kInterfaceState;
    case TopicKind::DoorState:
      return topics::kDoorState;
    case TopicKind::ChuckState:
      return topics::kChuckState;
    case TopicKind::DeviceDescription:
      return topics::kDeviceDescription;
    case TopicKind::Heartbeat:
      return topics::kHeartbeat;
  }
  return "";
}

std::string interaction_topic_name(std::size_t index) {
  return topics::interaction_topic(interaction_side(index) == TopicKind::Request
                                       ? core::SubType::Request
                                       : core::SubType::Response,
                                   interaction_service(index));
}

std::string protocol_violation(const ProtocolViolationEvent& e) {
  const auto& v = e.value;
  const std::string service = v.service ? std::string(core::to_string(*v.service)) : "?";
  const std::string side = v.sub_type ? std::string(core::to_string(*v.sub_type)) : "?";
  return "protocol violation: device " + v.device_uuid + " wrote " + v.data_item_id + " (" +
         service + " " + side + ") on topic " + interaction_topic_name(e.topic) +
         ", which carries only that topic's service and side; sample ignored";
}

bool on_its_interaction_topic(const ObservedValue& value, std::size_t topic) {
  return !value.service || !value.sub_type ||
         interaction_index(*value.sub_type, *value.service) == topic;
}

}  // namespace mtc::dds::detail
