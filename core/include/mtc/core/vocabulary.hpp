// The vocabulary of MTConnect Part 5 "Interfaces": services, interface types,
// and the value sets of the interaction and state data items.
//
// MTConnect spellings ("NOT_READY", "MATERIAL_LOAD") appear only in the
// to_string / parse functions of this header; everywhere else the project
// uses these enums.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

namespace mtc::core {

// Value of a REQUEST or RESPONSE data item (Tables 5 and 6). A request never
// takes Complete; is_valid_request_state() tells.
enum class InteractionState : std::uint8_t { Unavailable, NotReady, Ready, Active, Complete, Fail };

// Which side of a service a data item belongs to.
enum class Role : std::uint8_t { Requester, Responder };

// subType of an interaction data item.
enum class SubType : std::uint8_t { Request, Response };

// INTERFACE_STATE.
enum class InterfaceState : std::uint8_t { Unavailable, Enabled, Disabled };

// DOOR_STATE and CHUCK_STATE share one value set.
enum class DoorState : std::uint8_t { Unavailable, Open, Unlatched, Closed };
enum class ChuckState : std::uint8_t { Unavailable, Open, Unlatched, Closed };

// The ten services of the interaction model.
enum class Service : std::uint8_t {
  MaterialFeed,
  MaterialChange,
  MaterialRetract,
  PartChange,
  MaterialLoad,
  MaterialUnload,
  OpenDoor,
  CloseDoor,
  OpenChuck,
  CloseChuck,
};

// The four interface types.
enum class InterfaceType : std::uint8_t { BarFeeder, MaterialHandler, Door, Chuck };

inline constexpr std::array<Service, 10> kAllServices = {
    Service::MaterialFeed, Service::MaterialChange, Service::MaterialRetract, Service::PartChange,
    Service::MaterialLoad, Service::MaterialUnload, Service::OpenDoor,        Service::CloseDoor,
    Service::OpenChuck,    Service::CloseChuck};

inline constexpr std::array<InteractionState, 6> kAllInteractionStates = {
    InteractionState::Unavailable, InteractionState::NotReady, InteractionState::Ready,
    InteractionState::Active,      InteractionState::Complete, InteractionState::Fail};

inline constexpr std::array<InterfaceType, 4> kAllInterfaceTypes = {
    InterfaceType::BarFeeder, InterfaceType::MaterialHandler, InterfaceType::Door,
    InterfaceType::Chuck};

// True for the five values Table 5 allows a REQUEST (plus UNAVAILABLE).
constexpr bool is_valid_request_state(InteractionState s) noexcept {
  return s != InteractionState::Complete;
}

// MTConnect spellings. to_string never fails; parse returns nullopt for text
// outside the vocabulary (callers report that as a protocol violation).
std::string_view to_string(InteractionState s) noexcept;
std::string_view to_string(SubType s) noexcept;
std::string_view to_string(InterfaceState s) noexcept;
std::string_view to_string(DoorState s) noexcept;
std::string_view to_string(ChuckState s) noexcept;
std::string_view to_string(Service s) noexcept;
std::string_view to_string(InterfaceType t) noexcept;
std::string_view to_string(Role r) noexcept;

std::optional<InteractionState> parse_interaction_state(std::string_view text) noexcept;
std::optional<SubType> parse_sub_type(std::string_view text) noexcept;
std::optional<InterfaceState> parse_interface_state(std::string_view text) noexcept;
std::optional<DoorState> parse_door_state(std::string_view text) noexcept;
std::optional<ChuckState> parse_chuck_state(std::string_view text) noexcept;
std::optional<Service> parse_service(std::string_view text) noexcept;
std::optional<InterfaceType> parse_interface_type(std::string_view text) noexcept;

// Data item type of the state item an interface type carries besides its
// services: DOOR_STATE for DoorInterface, CHUCK_STATE for ChuckInterface.
// Empty for the others.
std::string_view state_item_type(InterfaceType t) noexcept;

// Element name of a service's data item in MTConnectStreams (Table 4),
// e.g. "MaterialLoad" for MATERIAL_LOAD. Part 5 does not tie services to
// interface types: any interface may carry any service.
std::string_view element_name(Service s) noexcept;

// Element name of an interface type in MTConnectDevices, e.g.
// "MaterialHandlerInterface".
std::string_view element_name(InterfaceType t) noexcept;

}  // namespace mtc::core
