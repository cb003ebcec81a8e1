#include "mtc/dds/detail/topics.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cstddef>

namespace mtc::dds::detail::topics {

std::string device_partition(std::string_view device_uuid) {
  return std::string(kPartitionPrefix) + std::string(device_uuid);
}

std::string interaction_topic(core::SubType side, core::Service service) {
  return std::string(side == core::SubType::Request ? kInteractionRequestPrefix
                                                    : kInteractionResponsePrefix) +
         std::string(core::to_string(service));
}

namespace {

std::optional<std::string> check_token(std::string_view what, std::string_view text,
                                       bool id_rules) {
  if (text.empty() || text.size() > 64) {
    return std::string(what) + " must have 1 to 64 characters, got " + std::to_string(text.size());
  }
  for (char c : text) {
    const bool ok = std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '-' ||
                    c == '.' || c == ':';
    if (!ok) {
      return std::string(what) + " \"" + std::string(text) +
             "\" may only contain letters, digits and _ - . :";
    }
  }
  if (id_rules && std::isdigit(static_cast<unsigned char>(text.front())) != 0) {
    return std::string(what) + " \"" + std::string(text) + "\" must not start with a digit";
  }
  return std::nullopt;
}

std::string lower(std::string_view text) {
  std::string out(text);
  for (auto& c : out) {
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  return out;
}

template <typename Out, typename In>
std::optional<Out> checked_cast(In v, std::size_t count) noexcept {
  const auto i = static_cast<std::size_t>(v);
  if (i >= count) {
    return std::nullopt;
  }
  return static_cast<Out>(i);
}

// The IDL enums beside the core enums, enumerator by enumerator (paired by
// name). to_idl / from_idl convert by position, so every row must hold the
// same position on both sides: the static_asserts below fail the build as
// soon as either side is reordered. A row count below the core enum's
// (where core says how many there are) fails too.
template <typename Core, typename Idl>
struct Pair {
  Core core;
  Idl idl;
};

// Index of the first row whose two enumerators are not both at that
// position; N when every row is aligned.
template <typename Core, typename Idl, std::size_t N>
constexpr std::size_t first_misaligned(const std::array<Pair<Core, Idl>, N>& rows) {
  for (std::size_t i = 0; i < N; ++i) {
    if (static_cast<std::size_t>(rows[i].core) != i || static_cast<std::size_t>(rows[i].idl) != i) {
      return i;
    }
  }
  return N;
}

namespace is = idl::interaction_state;
constexpr std::array<Pair<core::InteractionState, is::Value>, 6> kInteractionStates{{
    {core::InteractionState::Unavailable, is::UNAVAILABLE},
    {core::InteractionState::NotReady, is::NOT_READY},
    {core::InteractionState::Ready, is::READY},
    {core::InteractionState::Active, is::ACTIVE},
    {core::InteractionState::Complete, is::COMPLETE},
    {core::InteractionState::Fail, is::FAIL},
}};
static_assert(first_misaligned(kInteractionStates) == kInteractionStates.size(),
              "core::InteractionState and idl::interaction_state differ at that row");
static_assert(kInteractionStates.size() == core::kAllInteractionStates.size(),
              "an InteractionState has no IDL counterpart");

namespace its = idl::interface_state;
constexpr std::array<Pair<core::InterfaceState, its::Value>, 3> kInterfaceStates{{
    {core::InterfaceState::Unavailable, its::UNAVAILABLE},
    {core::InterfaceState::Enabled, its::ENABLED},
    {core::InterfaceState::Disabled, its::DISABLED},
}};
static_assert(first_misaligned(kInterfaceStates) == kInterfaceStates.size(),
              "core::InterfaceState and idl::interface_state differ at that row");

namespace ds = idl::door_state;
constexpr std::array<Pair<core::DoorState, ds::Value>, 4> kDoorStates{{
    {core::DoorState::Unavailable, ds::UNAVAILABLE},
    {core::DoorState::Open, ds::OPEN},
    {core::DoorState::Unlatched, ds::UNLATCHED},
    {core::DoorState::Closed, ds::CLOSED},
}};
static_assert(first_misaligned(kDoorStates) == kDoorStates.size(),
              "core::DoorState and idl::door_state differ at that row");

namespace cs = idl::chuck_state;
constexpr std::array<Pair<core::ChuckState, cs::Value>, 4> kChuckStates{{
    {core::ChuckState::Unavailable, cs::UNAVAILABLE},
    {core::ChuckState::Open, cs::OPEN},
    {core::ChuckState::Unlatched, cs::UNLATCHED},
    {core::ChuckState::Closed, cs::CLOSED},
}};
static_assert(first_misaligned(kChuckStates) == kChuckStates.size(),
              "core::ChuckState and idl::chuck_state differ at that row");

namespace sv = idl::services;
constexpr std::array<Pair<core::Service, sv::Service>, 10> kServices{{
    {core::Service::MaterialFeed, sv::MATERIAL_FEED},
    {core::Service::MaterialChange, sv::MATERIAL_CHANGE},
    {core::Service::MaterialRetract, sv::MATERIAL_RETRACT},
    {core::Service::PartChange, sv::PART_CHANGE},
    {core::Service::MaterialLoad, sv::MATERIAL_LOAD},
    {core::Service::MaterialUnload, sv::MATERIAL_UNLOAD},
    {core::Service::OpenDoor, sv::OPEN_DOOR},
    {core::Service::CloseDoor, sv::CLOSE_DOOR},
    {core::Service::OpenChuck, sv::OPEN_CHUCK},
    {core::Service::CloseChuck, sv::CLOSE_CHUCK},
}};
static_assert(first_misaligned(kServices) == kServices.size(),
              "core::Service and idl::services differ at that row");
static_assert(kServices.size() == core::kAllServices.size(), "a Service has no IDL counterpart");

namespace st = idl::sub_types;
constexpr std::array<Pair<core::SubType, st::SubType>, 2> kSubTypes{{
    {core::SubType::Request, st::REQUEST},
    {core::SubType::Response, st::RESPONSE},
}};
static_assert(first_misaligned(kSubTypes) == kSubTypes.size(),
              "core::SubType and idl::sub_types differ at that row");

namespace it = idl::interface_types;
constexpr std::array<Pair<core::InterfaceType, it::InterfaceType>, 4> kInterfaceTypes{{
    {core::InterfaceType::BarFeeder, it::BAR_FEEDER},
    {core::InterfaceType::MaterialHandler, it::MATERIAL_HANDLER},
    {core::InterfaceType::Door, it::DOOR},
    {core::InterfaceType::Chuck, it::CHUCK},
}};
static_assert(first_misaligned(kInterfaceTypes) == kInterfaceTypes.size(),
              "core::InterfaceType and idl::interface_types differ at that row");
static_assert(kInterfaceTypes.size() == core::kAllInterfaceTypes.size(),
              "an InterfaceType has no IDL counterpart");

}  // namespace

std::optional<std::string> check_device_uuid(std::string_view uuid) {
  return check_token("device uuid", uuid, false);
}

// An interface id is the prefix of its data item ids, which travel in the
// same 64-character IDL strings: the id may only be as long as leaves room
// for the longest suffix (Fast DDS would cut a longer item id short without
// a word, and two interfaces with a long common prefix would then share
// items).
namespace {
std::size_t longest_item_suffix() {
  std::size_t longest = std::string_view("_interface_state").size();
  for (const auto service : core::kAllServices) {
    longest = std::max(longest, interaction_item_id("", service, core::SubType::Response).size());
  }
  return longest;
}
}  // namespace

std::optional<std::string> check_interface_id(std::string_view id) {
  if (auto problem = check_token("interface id", id, true)) return problem;
  static const std::size_t limit = 64 - longest_item_suffix();
  if (id.size() > limit) {
    return "interface id \"" + std::string(id) + "\" has " + std::to_string(id.size()) +
           " characters; at most " + std::to_string(limit) +
           " leave room for its data item ids (e.g. <id>_material_retract_response) in the 64 "
           "characters the wire contract allows";
  }
  return std::nullopt;
}

std::string interaction_item_id(std::string_view interface_id, core::Service service,
                                core::SubType sub_type) {
  return std::string(interface_id) + "_" + lower(core::to_string(service)) +
         (sub_type == core::SubType::Request ? "_request" : "_response");
}

std::string interface_state_item_id(std::string_view interface_id) {
  return std::string(interface_id) + "_interface_state";
}
std::string door_state_item_id(std::string_view interface_id) {
  return std::string(interface_id) + "_door_state";
}
std::string chuck_state_item_id(std::string_view interface_id) {
  return std::string(interface_id) + "_chuck_state";
}

idl::interaction_state::Value to_idl(core::InteractionState s) noexcept {
  return static_cast<idl::interaction_state::Value>(s);
}
idl::interface_state::Value to_idl(core::InterfaceState s) noexcept {
  return static_cast<idl::interface_state::Value>(s);
}
idl::door_state::Value to_idl(core::DoorState s) noexcept {
  return static_cast<idl::door_state::Value>(s);
}
idl::chuck_state::Value to_idl(core::ChuckState s) noexcept {
  return static_cast<idl::chuck_state::Value>(s);
}
idl::services::Service to_idl(core::Service s) noexcept {
  return static_cast<idl::services::Service>(s);
}
idl::sub_types::SubType to_idl(core::SubType s) noexcept {
  return static_cast<idl::sub_types::SubType>(s);
}
idl::interface_types::InterfaceType to_idl(core::InterfaceType t) noexcept {
  return static_cast<idl::interface_types::InterfaceType>(t);
}

std::optional<core::InteractionState> from_idl(idl::interaction_state::Value v) noexcept {
  return checked_cast<core::InteractionState>(v, kInteractionStates.size());
}
std::optional<core::InterfaceState> from_idl(idl::interface_state::Value v) noexcept {
  return checked_cast<core::InterfaceState>(v, kInterfaceStates.size());
}
std::optional<core::DoorState> from_idl(idl::door_state::Value v) noexcept {
  return checked_cast<core::DoorState>(v, kDoorStates.size());
}
std::optional<core::ChuckState> from_idl(idl::chuck_state::Value v) noexcept {
  return checked_cast<core::ChuckState>(v, kChuckStates.size());
}
std::optional<core::Service> from_idl(idl::services::Service v) noexcept {
  return checked_cast<core::Service>(v, kServices.size());
}
std::optional<core::SubType> from_idl(idl::sub_types::SubType v) noexcept {
  return checked_cast<core::SubType>(v, kSubTypes.size());
}
std::optional<core::InterfaceType> from_idl(idl::interface_types::InterfaceType v) noexcept {
  return checked_cast<core::InterfaceType>(v, kInterfaceTypes.size());
}

std::int64_t realtime_ns() noexcept {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace mtc::dds::detail::topics
