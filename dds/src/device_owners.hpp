// Internal: which participant speaks for a device, for a domain without
// DDS-Security (with it, the signed permissions decide who may write where).
//
// The participant whose announcement (mtc/DeviceDescription) was accepted
// owns the device's uuid. While the owner is alive, another participant's
// announcement, value or heartbeat for that uuid is an ownership conflict:
// reported once per device, participant and kind (announcement, value,
// heartbeat) and ignored. Once the owner is lost (its heartbeats stopped for
// a lease) or gone (its announcement went away), the newest announcer takes
// over: that is how a device restarted under the same uuid becomes its
// newest incarnation. A writer's handle is
// its GUID: the first 12 bytes name its participant.
//
// Values of a device nobody announced yet are accepted (peers of other
// vendors, and raw test peers, may publish without announcing). Refused
// announcements and values are held (the latest of each), since both are
// written once: a restarted process whose new participant announced before
// the old one was lost gets them replayed when it takes over.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "mw/tap_events.hpp"

namespace mtc::dds::detail {

// What a participant said about a device.
enum class Said { Announcement, Value, Heartbeat };

constexpr const char* said_text(Said said) noexcept {
  switch (said) {
    case Said::Announcement:
      return "an announcement";
    case Said::Value:
      return "a value";
    case Said::Heartbeat:
      return "a heartbeat";
  }
  return "a sample";
}

class DeviceOwners {
 public:
  // A refused value and the timing group whose readers delivered it.
  struct HeldValue {
    std::size_t group = 0;
    ValueEvent event;
  };

  // An announcement of `device` by `writer`: false on a conflict (the owner
  // is another participant and not lost).
  bool announce(const std::string& device, const Handle& writer) {
    const auto participant = participant_of(writer);
    const auto it = owners_.find(device);
    if (it != owners_.end() && !it->second.lost && it->second.participant != participant) {
      return false;
    }
    owners_[device] = Owner{participant, writer, false};
    return true;
  }

  // A value or heartbeat of `device` written by `writer`: false on a
  // conflict. The owner's own say it is alive again (a resumed process).
  bool accepts(const std::string& device, const Handle& writer) {
    const auto it = owners_.find(device);
    if (it == owners_.end()) return true;
    if (it->second.participant != participant_of(writer)) return false;
    it->second.lost = false;
    return true;
  }

  // True the first time a conflict of this participant on this device is
  // seen, per kind, so that a rogue writing every heartbeat is reported once
  // and none of its kinds hides another (its heartbeat, often first, used to
  // hide its values).
  bool first_conflict(const std::string& device, const Handle& writer, Said said) {
    return reported_.emplace(device, participant_of(writer), said).second;
  }

  // Keeps the latest refused announcement of a device and the latest
  // refused value of each item (bounded: a rogue may invent items).
  void hold(const DeviceEvent& refused) { held_[refused.device.device_uuid] = refused; }
  void hold(std::size_t group, const ValueEvent& refused) {
    auto& values = held_values_[refused.value.device_uuid];
    const ValueKey key{participant_of(refused.writer), refused.topic, refused.value.data_item_id,
                       group};
    if (values.size() >= kMaxHeldValues && values.count(key) == 0) return;
    values[key] = HeldValue{group, refused};
  }

  // One sample: an announcement claims `device`, a value or heartbeat must
  // come from its owner.
  bool check(const std::string& device, const Handle& writer, Said said) {
    return said == Said::Announcement ? announce(device, writer) : accepts(device, writer);
  }

  // The values `writer`'s participant wrote for `device` before it owned it
  // (call after an accepted announcement; the caller replays them).
  std::vector<HeldValue> take_values(const std::string& device, const Handle& writer) {
    std::vector<HeldValue> taken;
    const auto it = held_values_.find(device);
    if (it == held_values_.end()) return taken;
    const auto participant = participant_of(writer);
    for (auto v = it->second.begin(); v != it->second.end();) {
      if (std::get<0>(v->first) != participant) {
        ++v;
        continue;
      }
      taken.push_back(std::move(v->second));
      v = it->second.erase(v);
    }
    return taken;
  }

  // The owner `participant` of `device` lost its heartbeats: anyone may
  // take over. Returns the held announcement to replay, if any.
  std::optional<DeviceEvent> owner_lost(const std::string& device,
                                        const ParticipantKey& participant) {
    const auto it = owners_.find(device);
    if (it == owners_.end() || it->second.participant != participant) return std::nullopt;
    it->second.lost = true;
    return take_held(device);
  }

  // The owner's announcement went away (its writer unmatched, or its
  // instance disposed or left without writers): the uuid is free again.
  // Returns the held announcement to replay, if any.
  std::optional<DeviceEvent> release_writer(const Handle& writer) {
    for (const auto& [device, owner] : owners_) {
      // A copy of the key: release_device erases the entry that holds it.
      if (owner.writer == writer) return release_device(std::string(device));
    }
    return std::nullopt;
  }
  std::optional<DeviceEvent> release_device(const std::string& device) {
    owners_.erase(device);
    return take_held(device);
  }

  // "0f1e...": a participant in words, for the conflict report.
  static std::string to_text(const ParticipantKey& p) {
    static constexpr char kHex[] = "0123456789abcdef";
    std::string out;
    for (auto byte : p) {
      out += kHex[byte >> 4];
      out += kHex[byte & 0xF];
    }
    return out;
  }
  std::string owner_text(const std::string& device) const {
    const auto it = owners_.find(device);
    return it == owners_.end() ? std::string("none") : to_text(it->second.participant);
  }

 private:
  static constexpr std::size_t kMaxHeldValues = 256;  // per device
  using ValueKey = std::tuple<ParticipantKey, TopicKind, std::string, std::size_t>;

  std::optional<DeviceEvent> take_held(const std::string& device) {
    const auto it = held_.find(device);
    if (it == held_.end()) return std::nullopt;
    DeviceEvent held = std::move(it->second);
    held_.erase(it);
    return held;
  }

  struct Owner {
    ParticipantKey participant{};
    Handle writer{};
    bool lost = false;  // its heartbeats stopped; the next announcer takes over
  };
  std::map<std::string, Owner> owners_;
  std::map<std::string, DeviceEvent> held_;
  std::map<std::string, std::map<ValueKey, HeldValue>> held_values_;
  std::set<std::tuple<std::string, ParticipantKey, Said>> reported_;
};

// The words of an ownership conflict report.
inline std::string ownership_conflict(const DeviceOwners& owners, const std::string& device,
                                      const Handle& writer, Said said) {
  return "ownership conflict: " + std::string(said_text(said)) + " for device " + device +
         " from participant " + DeviceOwners::to_text(participant_of(writer)) +
         ", which did not announce it (announced by " + owners.owner_text(device) + "); ignored";
}

}  // namespace mtc::dds::detail
