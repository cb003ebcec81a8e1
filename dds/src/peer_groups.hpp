// Internal: the timing groups of other devices as their heartbeats and state
// samples describe them. A heartbeat announces, per state topic (per
// interaction topic: service and side), the newest change the group's writer
// of it has written; the values received from those
// writers say how far this reader has got. When they agree the reader is in
// step: the last value it holds of each item is the device's current one,
// which is what lets Equipment and DomainObserver hand last known values over
// again after a loss instead of waiting for a change that may never come.
// Only the interaction topics this side reads count: an equipment reads the
// services of its own interfaces, while a counterpart's group may write
// others too.
//
// Keyed by the writing participant as well: a restarted device (same uuid,
// new process) starts its change numbers afresh, and nothing of its previous
// incarnation may be taken for current.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <tuple>

#include "lookup_keys.hpp"
#include "mw/tap_events.hpp"

namespace mtc::dds::detail {

struct PeerGroupKey {
  std::string device;
  std::uint32_t group = 0;
  ParticipantKey participant{};

  auto parts() const noexcept { return std::tie(device, group, participant); }
  friend bool operator<(const PeerGroupKey& a, const PeerGroupKey& b) {
    return a.parts() < b.parts();
  }
  friend bool operator==(const PeerGroupKey& a, const PeerGroupKey& b) {
    return a.parts() == b.parts();
  }
};

// A PeerGroupKey to look up (ViewLess), its device viewed: a value's group
// is found for every sample, and building the key allocated the uuid.
struct PeerGroupKeyView {
  std::string_view device;
  std::uint32_t group = 0;
  ParticipantKey participant{};

  auto parts() const noexcept { return std::tie(device, group, participant); }
};

// The leave said in data (idl: Heartbeat.period_ms): a device's last
// heartbeat of a group, written before its disposals, carries period 0. A
// reader takes it as the disposal it precedes, which a reader of another
// vendor may never get (Fast DDS 2.9 disposes by the key's MD5 hash alone).
constexpr bool says_leaving(const ObservedHeartbeat& h) noexcept {
  return h.period_ms == 0;
}

struct PeerGroup {
  std::int64_t last_heartbeat_steady_ns = 0;  // when the newest heartbeat came (steady_ns; 0: none)
  ObservedHeartbeat newest;                   // the newest heartbeat itself
  StateChanges announced{};                   // change numbers it announced
  StateChanges received{};                    // newest change number received, per state topic
  InteractionChanges announced_interactions{};  // the same per interaction topic
  InteractionChanges received_interactions{};
  std::int64_t behind_since_ns = 0;  // announced ahead of received since (steady_ns; 0: in step)
  bool behind_reported = false;

  bool heard() const noexcept { return last_heartbeat_steady_ns != 0; }
  // The period its heartbeats announce; `own` until one was heard. Never 0:
  // a heartbeat with period 0 is a leave (says_leaving) and is not kept.
  std::chrono::milliseconds period_or(std::chrono::milliseconds own) const noexcept {
    return heard() ? std::chrono::milliseconds(newest.period_ms) : own;
  }
  // Every change the newest heartbeat announced has been received, on the
  // interaction topics in `read`.
  bool in_step(const InteractionTopics& read) const noexcept;
};

class PeerGroups {
 public:
  // `read`: the interaction topics whose changes this side receives.
  explicit PeerGroups(const InteractionTopics& read = all_interaction_topics()) : read_(read) {}
  void set_read(const InteractionTopics& read) { read_ = read; }
  bool in_step(const PeerGroup& group) const noexcept { return group.in_step(read_); }

  // A state sample from `writer` on state topic `topic`.
  void on_value(const Handle& writer, TopicKind topic, const ObservedValue& value);
  // A heartbeat heard at `heard_steady_ns` (steady_ns); returns its group's
  // record (created on first sight).
  PeerGroup& on_heartbeat(const Handle& writer, const ObservedHeartbeat& heartbeat,
                          std::int64_t heard_steady_ns);
  // A report once a group has stayed behind its heartbeats for longer than
  // `repair_ns` (a change announced but not received: lost, or stuck in
  // repair); nullopt otherwise. Call after on_heartbeat, with steady_ns().
  std::optional<std::string> behind_report(const PeerGroupKey& key, std::int64_t now_ns,
                                           std::int64_t repair_ns);

  const PeerGroup* find(const PeerGroupKey& key) const;
  // The group whose heartbeats `writer` writes, if it is a heartbeat writer.
  const PeerGroupKey* heartbeat_writer(const Handle& writer) const;
  // Drops what is known of a heartbeat writer's group (the writer is gone).
  void forget_writer(const Handle& writer);
  // Calls fn(key, group) for every group known.
  template <typename Fn>
  void for_each(Fn&& fn) const {
    for (const auto& [key, group] : groups_) fn(key, group);
  }

  static PeerGroupKey key_of(const Handle& writer, const std::string& device, std::uint32_t group) {
    return {device, group, participant_of(writer)};
  }

 private:
  InteractionTopics read_;
  std::map<PeerGroupKey, PeerGroup, ViewLess> groups_;
  std::map<Handle, PeerGroupKey> heartbeat_writers_;
};

}  // namespace mtc::dds::detail
