#include "peer_groups.hpp"

#include <algorithm>

namespace mtc::dds::detail {

namespace {

StateChanges announced_by(const ObservedHeartbeat& h) {
  StateChanges out{};
  out[static_cast<std::size_t>(TopicKind::Request)] = h.request_changes;
  out[static_cast<std::size_t>(TopicKind::Response)] = h.response_changes;
  out[static_cast<std::size_t>(TopicKind::InterfaceState)] = h.interface_state_changes;
  out[static_cast<std::size_t>(TopicKind::DoorState)] = h.door_state_changes;
  out[static_cast<std::size_t>(TopicKind::ChuckState)] = h.chuck_state_changes;
  return out;
}

InteractionChanges interactions_announced_by(const ObservedHeartbeat& h) {
  InteractionChanges out{};
  for (const auto& c : h.interaction_changes) {
    out[interaction_index(c.sub_type, c.service)] = c.changes;
  }
  return out;
}

// The interaction totals (Request, Response) are followed per topic instead.
bool counted_per_topic(std::size_t state_topic) {
  return state_topic == static_cast<std::size_t>(TopicKind::Request) ||
         state_topic == static_cast<std::size_t>(TopicKind::Response);
}

}  // namespace

bool PeerGroup::in_step(const InteractionTopics& read) const noexcept {
  for (std::size_t i = 0; i < kStateTopicCount; ++i) {
    if (!counted_per_topic(i) && received[i] < announced[i]) return false;
  }
  for (std::size_t i = 0; i < kInteractionTopicCount; ++i) {
    if (read[i] && received_interactions[i] < announced_interactions[i]) return false;
  }
  return true;
}

void PeerGroups::on_value(const Handle& writer, TopicKind topic, const ObservedValue& value) {
  if (is_state_topic(topic)) {
    const PeerGroupKeyView view{value.device_uuid, value.heartbeat_group, participant_of(writer)};
    auto& group = find_or_add(
        groups_, view, [&] { return key_of(writer, value.device_uuid, value.heartbeat_group); });
    auto& newest = group.received[static_cast<std::size_t>(topic)];
    newest = std::max(newest, value.sequence_number);
    if ((topic == TopicKind::Request || topic == TopicKind::Response) && value.service) {
      auto& per_topic = group.received_interactions[interaction_index(topic, *value.service)];
      per_topic = std::max(per_topic, value.sequence_number);
    }
  }
}

PeerGroup& PeerGroups::on_heartbeat(const Handle& writer, const ObservedHeartbeat& heartbeat,
                                    std::int64_t heard_steady_ns) {
  const auto key = key_of(writer, heartbeat.device_uuid, heartbeat.group);
  heartbeat_writers_[writer] = key;
  auto& g = groups_[key];
  g.last_heartbeat_steady_ns = heard_steady_ns;
  g.newest = heartbeat;
  g.announced = announced_by(heartbeat);
  g.announced_interactions = interactions_announced_by(heartbeat);
  return g;
}

std::optional<std::string> PeerGroups::behind_report(const PeerGroupKey& key, std::int64_t now_ns,
                                                     std::int64_t repair_ns) {
  const auto it = groups_.find(key);
  if (it == groups_.end()) return std::nullopt;
  auto& g = it->second;
  if (g.in_step(read_)) {
    g.behind_since_ns = 0;
    g.behind_reported = false;
    return std::nullopt;
  }
  if (g.behind_since_ns == 0) g.behind_since_ns = now_ns;
  if (g.behind_reported || now_ns - g.behind_since_ns <= repair_ns) return std::nullopt;
  g.behind_reported = true;
  std::string missing;
  const auto note = [&missing](const std::string& topic, std::uint64_t announced,
                               std::uint64_t received) {
    missing += std::string(missing.empty() ? "" : ", ") + topic + " change " +
               std::to_string(announced) + " (received up to " + std::to_string(received) + ")";
  };
  for (std::size_t i = 0; i < kStateTopicCount; ++i) {
    if (counted_per_topic(i) || g.received[i] >= g.announced[i]) continue;
    note(topic_name(static_cast<TopicKind>(i)), g.announced[i], g.received[i]);
  }
  for (std::size_t i = 0; i < kInteractionTopicCount; ++i) {
    if (!read_[i] || g.received_interactions[i] >= g.announced_interactions[i]) continue;
    note(interaction_topic_name(i), g.announced_interactions[i], g.received_interactions[i]);
  }
  return "device " + key.device + " heartbeat group " + std::to_string(key.group) +
         " announced changes not received for " +
         std::to_string((now_ns - g.behind_since_ns) / 1000000) + " ms: " + missing;
}

const PeerGroup* PeerGroups::find(const PeerGroupKey& key) const {
  const auto it = groups_.find(key);
  return it == groups_.end() ? nullptr : &it->second;
}

const PeerGroupKey* PeerGroups::heartbeat_writer(const Handle& writer) const {
  const auto it = heartbeat_writers_.find(writer);
  return it == heartbeat_writers_.end() ? nullptr : &it->second;
}

void PeerGroups::forget_writer(const Handle& writer) {
  const auto it = heartbeat_writers_.find(writer);
  if (it == heartbeat_writers_.end()) return;
  groups_.erase(it->second);
  heartbeat_writers_.erase(it);
}

}  // namespace mtc::dds::detail
