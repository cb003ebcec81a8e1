// Internal, vendor-neutral: how the runtime names topics, instances and
// writers, whatever middleware carries them (docs/design/middleware-layer.md,
// section 2). Handles are RTPS identities (a writer's GUID, an instance's
// key hash), so values compare across vendors and processes.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "mtc/core/vocabulary.hpp"

namespace mtc::dds::detail {

// A writer GUID or an instance key hash (RTPS) as a value.
using Handle = std::array<std::uint8_t, 16>;

// The state topics come first: their index is also the index of their
// change number in a heartbeat (StateChanges).
enum class TopicKind : std::uint8_t {
  Request,
  Response,
  InterfaceState,
  DoorState,
  ChuckState,
  DeviceDescription,
  Heartbeat
};
inline constexpr std::size_t kTopicKindCount = 7;
inline constexpr std::size_t kStateTopicCount = 5;
constexpr bool is_state_topic(TopicKind kind) noexcept {
  return static_cast<std::size_t>(kind) < kStateTopicCount;
}

// Newest change number per state topic (indexed by TopicKind; the Request
// and Response entries are not used: see InteractionChanges).
using StateChanges = std::array<std::uint64_t, kStateTopicCount>;

// Interaction items have one topic per side (TopicKind::Request or
// Response) and service (topics::interaction_topic), indexed thus.
inline constexpr std::size_t kServiceCount = core::kAllServices.size();
inline constexpr std::size_t kInteractionTopicCount = 2 * kServiceCount;
constexpr std::size_t interaction_index(TopicKind side, core::Service service) noexcept {
  return (side == TopicKind::Request ? 0 : kServiceCount) + static_cast<std::size_t>(service);
}
constexpr std::size_t interaction_index(core::SubType side, core::Service service) noexcept {
  return interaction_index(
      side == core::SubType::Request ? TopicKind::Request : TopicKind::Response, service);
}
constexpr TopicKind interaction_side(std::size_t index) noexcept {
  return index < kServiceCount ? TopicKind::Request : TopicKind::Response;
}
constexpr core::Service interaction_service(std::size_t index) noexcept {
  return core::kAllServices[index % kServiceCount];
}
// A set of interaction topics (which are read), and the newest change
// number per interaction topic.
using InteractionTopics = std::array<bool, kInteractionTopicCount>;
using InteractionChanges = std::array<std::uint64_t, kInteractionTopicCount>;
constexpr InteractionTopics all_interaction_topics() noexcept {
  InteractionTopics all{};
  for (auto& t : all) t = true;
  return all;
}

// The participant part (GUID prefix) of a writer's handle: which process
// incarnation wrote a sample. A restarted device has a new one.
using ParticipantKey = std::array<std::uint8_t, 12>;

// A writer handle is its GUID: 12 bytes of participant prefix, then 4 of
// entity id.
inline ParticipantKey participant_of(const Handle& writer) noexcept {
  ParticipantKey out{};
  std::memcpy(out.data(), writer.data(), out.size());
  return out;
}

}  // namespace mtc::dds::detail
