// What an observer of a domain sees, as plain values: each device's
// announcement (its interfaces and data items) and each sample of each data
// item. The DDS runtime produces them (mtc::dds::DomainObserver, Equipment's
// counterpart values); the bridge's agent and the CLI consume them without
// knowing DDS.
//
// States are core enums, not text: the MTConnect spelling is produced by
// to_string() where a value is printed, and nothing parses it back.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "mtc/core/vocabulary.hpp"

namespace mtc::core {

// Which kind of Part 5 data item a value belongs to.
enum class ItemKind : std::uint8_t { Interaction, InterfaceState, DoorState, ChuckState };

// The state one sample carries, in the vocabulary of its item kind. A peer
// (another implementation, a newer version) may send a number outside that
// vocabulary: such a state stays representable and distinguishable
// (in_vocabulary() false, raw() the number as sent), so that the runtime
// can treat it as a protocol violation instead of guessing.
class ObservedState {
 public:
  // An interaction item's UNAVAILABLE.
  constexpr ObservedState() noexcept = default;
  // Implicit on purpose: `value.state = core::DoorState::Open` says it all.
  // NOLINTNEXTLINE(google-explicit-constructor)
  constexpr ObservedState(InteractionState s) noexcept : code_(static_cast<std::int32_t>(s)) {}
  // NOLINTNEXTLINE(google-explicit-constructor)
  constexpr ObservedState(InterfaceState s) noexcept
      : kind_(ItemKind::InterfaceState), code_(static_cast<std::int32_t>(s)) {}
  // NOLINTNEXTLINE(google-explicit-constructor)
  constexpr ObservedState(DoorState s) noexcept
      : kind_(ItemKind::DoorState), code_(static_cast<std::int32_t>(s)) {}
  // NOLINTNEXTLINE(google-explicit-constructor)
  constexpr ObservedState(ChuckState s) noexcept
      : kind_(ItemKind::ChuckState), code_(static_cast<std::int32_t>(s)) {}

  // A value of `kind`'s item that lies outside its vocabulary, as received.
  static constexpr ObservedState outside_vocabulary(ItemKind kind, std::int32_t raw) noexcept {
    ObservedState s;
    s.kind_ = kind;
    s.in_vocabulary_ = false;
    s.code_ = raw;
    return s;
  }

  constexpr ItemKind kind() const noexcept { return kind_; }
  constexpr bool in_vocabulary() const noexcept { return in_vocabulary_; }
  // The number a peer sent for a state outside the vocabulary.
  constexpr std::int32_t raw() const noexcept { return code_; }

  // The state, when this is an item of that kind carrying a known value.
  constexpr std::optional<InteractionState> interaction() const noexcept {
    return as<InteractionState>(ItemKind::Interaction);
  }
  constexpr std::optional<InterfaceState> interface_state() const noexcept {
    return as<InterfaceState>(ItemKind::InterfaceState);
  }
  constexpr std::optional<DoorState> door() const noexcept {
    return as<DoorState>(ItemKind::DoorState);
  }
  constexpr std::optional<ChuckState> chuck() const noexcept {
    return as<ChuckState>(ItemKind::ChuckState);
  }

  // UNAVAILABLE of any kind (every vocabulary starts with it).
  constexpr bool unavailable() const noexcept { return in_vocabulary_ && code_ == 0; }

  friend constexpr bool operator==(const ObservedState& a, const ObservedState& b) noexcept {
    return a.kind_ == b.kind_ && a.in_vocabulary_ == b.in_vocabulary_ && a.code_ == b.code_;
  }
  friend constexpr bool operator!=(const ObservedState& a, const ObservedState& b) noexcept {
    return !(a == b);
  }

 private:
  template <typename State>
  constexpr std::optional<State> as(ItemKind kind) const noexcept {
    if (kind_ != kind || !in_vocabulary_) return std::nullopt;
    return static_cast<State>(code_);
  }

  ItemKind kind_ = ItemKind::Interaction;
  bool in_vocabulary_ = true;
  std::int32_t code_ = 0;  // the core enumerator, or the raw number outside the vocabulary
};

// MTConnect spelling of the state ("READY", "ENABLED", "CLOSED"); a state
// outside the vocabulary reads "INVALID(<number>)".
std::string to_string(const ObservedState& state);

// One value of one data item: a change as it arrived, or the last known
// value handed over again once its device's heartbeats came back after a
// loss (`redelivered`; devices write changes only, so nothing else would
// restore it).
struct ObservedValue {
  std::string device_uuid;
  std::string data_item_id;
  std::string interface_id;
  std::optional<Service> service;      // set for Interaction items
  std::optional<SubType> sub_type;     // set for Interaction items
  ObservedState state;                 // its kind() is the item's kind
  std::uint64_t sequence_number = 0;   // writer's change counter
  std::uint32_t heartbeat_group = 0;   // the device's heartbeat that vouches for it
  bool redelivered = false;            // true: last known value again, not a new sample
  std::int64_t source_time_ns = 0;     // writer clock, ns since the epoch
  std::int64_t reception_time_ns = 0;  // local clock at reception
  // Interaction items: the counterpart (device uuid, interface id) the
  // writing interface was paired with; empty: not paired yet.
  std::string paired_device_uuid;
  std::string paired_interface_id;

  ItemKind kind() const noexcept { return state.kind(); }
};

// The newest change number of one of a group's interaction writers (one
// writer per service and side).
struct InteractionChange {
  Service service = Service::MaterialLoad;
  SubType sub_type = SubType::Request;
  std::uint64_t changes = 0;
};

// One heartbeat of one timing group of a device: it is alive, and these are
// the newest change numbers (sequence_number) of the group's writers per item
// kind; 0 = no change written yet. request_changes and response_changes sum
// the group's interaction writers of that side; interaction_changes has each.
struct ObservedHeartbeat {
  std::string device_uuid;
  std::uint32_t group = 0;  // 0: the device's own timing
  std::uint32_t period_ms = 0;
  std::uint32_t lease_ms = 0;
  std::uint64_t beat = 0;  // heartbeats the group has written, from 1
  std::uint64_t request_changes = 0;
  std::uint64_t response_changes = 0;
  std::uint64_t interface_state_changes = 0;
  std::uint64_t door_state_changes = 0;
  std::uint64_t chuck_state_changes = 0;
  std::vector<InteractionChange> interaction_changes;
  std::int64_t source_time_ns = 0;
  std::int64_t reception_time_ns = 0;
};

// A data item as a device announces it (MTConnect attributes, as text: they
// are copied into Devices documents).
struct ObservedDataItem {
  std::string id;
  std::string name;
  std::string type;      // e.g. MATERIAL_LOAD, INTERFACE_STATE, DOOR_STATE
  std::string sub_type;  // REQUEST, RESPONSE or empty
  std::string category;  // EVENT
};

struct ObservedInterface {
  std::string id;
  std::string name;
  InterfaceType type = InterfaceType::MaterialHandler;
  std::vector<ObservedDataItem> data_items;
};

// A device's announcement.
struct ObservedDevice {
  std::string device_uuid;
  std::string name;
  std::vector<ObservedInterface> interfaces;
};

}  // namespace mtc::core
