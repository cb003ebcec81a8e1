// Internal: DOOR_STATE and CHUCK_STATE differ only in their types and names.
// DoorChuck<State> holds those differences, so that the runtime publishes,
// heartbeats and announces both through one code path.
#pragma once

#include <string>
#include <string_view>

#include "mtc/core/preconditions.hpp"
#include "mtc/core/vocabulary.hpp"
#include "mtc/dds/detail/topic_names.hpp"
#include "mtc/dds/equipment.hpp"
#include "mw/wire.hpp"

namespace mtc::dds::detail {

template <typename State>
struct DoorChuck;

template <>
struct DoorChuck<core::DoorState> {
  static constexpr TopicKind kTopic = TopicKind::DoorState;
  static constexpr std::string_view kItemType = "DOOR_STATE";
  static std::string item_id(std::string_view interface_id) {
    return topics::door_state_item_id(interface_id);
  }
  static bool published(const InterfaceConfig& c) { return c.publishes_door_state; }
  static core::DoorState initial(const InterfaceConfig& c) { return c.initial_door_state; }
  static void apply(core::DoorChuckPreconditions& hook, core::DoorState s) {
    hook.set_door_state(s);
  }
};

template <>
struct DoorChuck<core::ChuckState> {
  static constexpr TopicKind kTopic = TopicKind::ChuckState;
  static constexpr std::string_view kItemType = "CHUCK_STATE";
  static std::string item_id(std::string_view interface_id) {
    return topics::chuck_state_item_id(interface_id);
  }
  static bool published(const InterfaceConfig& c) { return c.publishes_chuck_state; }
  static core::ChuckState initial(const InterfaceConfig& c) { return c.initial_chuck_state; }
  static void apply(core::DoorChuckPreconditions& hook, core::ChuckState s) {
    hook.set_chuck_state(s);
  }
};

// A type as a value, to hand both states to one generic lambda (C++17 has
// no template lambdas): fn(StateTag<core::DoorState>{}).
template <typename State>
struct StateTag {
  using type = State;
};

// Calls fn once for DOOR_STATE, then once for CHUCK_STATE (the order in
// which they are announced).
template <typename Fn>
void for_door_and_chuck(Fn&& fn) {
  fn(StateTag<core::DoorState>{});
  fn(StateTag<core::ChuckState>{});
}

}  // namespace mtc::dds::detail
