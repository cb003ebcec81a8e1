#include "mtc/core/vocabulary.hpp"

#include <cstddef>

namespace mtc::core {
namespace {

// One row per enumerator, in declaration order, so the enum value indexes it.
template <typename Enum, std::size_t N>
struct Spelling {
  std::array<std::string_view, N> names;

  constexpr std::string_view name(Enum e) const noexcept {
    const auto index = static_cast<std::size_t>(e);
    return index < N ? names[index] : std::string_view{"UNAVAILABLE"};
  }

  constexpr std::optional<Enum> parse(std::string_view text) const noexcept {
    for (std::size_t i = 0; i < N; ++i) {
      if (names[i] == text) return static_cast<Enum>(i);
    }
    return std::nullopt;
  }
};

constexpr Spelling<InteractionState, 6> kInteraction{
    {"UNAVAILABLE", "NOT_READY", "READY", "ACTIVE", "COMPLETE", "FAIL"}};
constexpr Spelling<SubType, 2> kSubType{{"REQUEST", "RESPONSE"}};
constexpr Spelling<InterfaceState, 3> kInterfaceState{{"UNAVAILABLE", "ENABLED", "DISABLED"}};
constexpr Spelling<DoorState, 4> kDoor{{"UNAVAILABLE", "OPEN", "UNLATCHED", "CLOSED"}};
constexpr Spelling<ChuckState, 4> kChuck{{"UNAVAILABLE", "OPEN", "UNLATCHED", "CLOSED"}};
constexpr Spelling<Service, 10> kService{{"MATERIAL_FEED", "MATERIAL_CHANGE", "MATERIAL_RETRACT",
                                          "PART_CHANGE", "MATERIAL_LOAD", "MATERIAL_UNLOAD",
                                          "OPEN_DOOR", "CLOSE_DOOR", "OPEN_CHUCK", "CLOSE_CHUCK"}};
constexpr Spelling<Service, 10> kServiceElement{
    {"MaterialFeed", "MaterialChange", "MaterialRetract", "PartChange", "MaterialLoad",
     "MaterialUnload", "OpenDoor", "CloseDoor", "OpenChuck", "CloseChuck"}};
constexpr Spelling<InterfaceType, 4> kInterfaceType{
    {"BAR_FEEDER", "MATERIAL_HANDLER", "DOOR", "CHUCK"}};
constexpr Spelling<InterfaceType, 4> kInterfaceElement{
    {"BarFeederInterface", "MaterialHandlerInterface", "DoorInterface", "ChuckInterface"}};
constexpr Spelling<Role, 2> kRole{{"REQUESTER", "RESPONDER"}};

}  // namespace

std::string_view to_string(InteractionState s) noexcept {
  return kInteraction.name(s);
}
std::string_view to_string(SubType s) noexcept {
  return kSubType.name(s);
}
std::string_view to_string(InterfaceState s) noexcept {
  return kInterfaceState.name(s);
}
std::string_view to_string(DoorState s) noexcept {
  return kDoor.name(s);
}
std::string_view to_string(ChuckState s) noexcept {
  return kChuck.name(s);
}
std::string_view to_string(Service s) noexcept {
  return kService.name(s);
}
std::string_view to_string(InterfaceType t) noexcept {
  return kInterfaceType.name(t);
}
std::string_view to_string(Role r) noexcept {
  return kRole.name(r);
}

std::optional<InteractionState> parse_interaction_state(std::string_view text) noexcept {
  return kInteraction.parse(text);
}
std::optional<SubType> parse_sub_type(std::string_view text) noexcept {
  return kSubType.parse(text);
}
std::optional<InterfaceState> parse_interface_state(std::string_view text) noexcept {
  return kInterfaceState.parse(text);
}
std::optional<DoorState> parse_door_state(std::string_view text) noexcept {
  return kDoor.parse(text);
}
std::optional<ChuckState> parse_chuck_state(std::string_view text) noexcept {
  return kChuck.parse(text);
}
std::optional<Service> parse_service(std::string_view text) noexcept {
  return kService.parse(text);
}
std::optional<InterfaceType> parse_interface_type(std::string_view text) noexcept {
  // Accept both the enumerator spelling and the Devices element name.
  if (auto t = kInterfaceType.parse(text)) return t;
  return kInterfaceElement.parse(text);
}

std::string_view state_item_type(InterfaceType t) noexcept {
  switch (t) {
    case InterfaceType::Door:
      return "DOOR_STATE";
    case InterfaceType::Chuck:
      return "CHUCK_STATE";
    case InterfaceType::BarFeeder:
    case InterfaceType::MaterialHandler:
      break;
  }
  return {};
}

std::string_view element_name(Service s) noexcept {
  return kServiceElement.name(s);
}
std::string_view element_name(InterfaceType t) noexcept {
  return kInterfaceElement.name(t);
}

}  // namespace mtc::core
