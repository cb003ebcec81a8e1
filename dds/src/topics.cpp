#include "mtc/dds/detail/topics.hpp"

#include <cctype>
#include <chrono>

namespace mtc::dds::detail::topics {

std::string device_partition(std::string_view device_uuid) {
  return std::string(kPartitionPrefix) + std::string(device_uuid);
}

namespace {

std::optional<std::string> check_token(std::string_view what, std::string_view text,
                                       bool id_rules) {
  if (text.empty() || text.size() > 64) {
    return std::string(what) + " must have 1 to 64 characters, got " +
           std::to_string(text.size());
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
std::optional<Out> checked_cast(In v, int count) noexcept {
  const int i = static_cast<int>(v);
  if (i < 0 || i >= count) {
    return std::nullopt;
  }
  return static_cast<Out>(i);
}

}  // namespace

std::optional<std::string> check_device_uuid(std::string_view uuid) {
  return check_token("device uuid", uuid, false);
}

std::optional<std::string> check_interface_id(std::string_view id) {
  return check_token("interface id", id, true);
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
  return checked_cast<core::InteractionState>(v, 6);
}
std::optional<core::InterfaceState> from_idl(idl::interface_state::Value v) noexcept {
  return checked_cast<core::InterfaceState>(v, 3);
}
std::optional<core::DoorState> from_idl(idl::door_state::Value v) noexcept {
  return checked_cast<core::DoorState>(v, 4);
}
std::optional<core::ChuckState> from_idl(idl::chuck_state::Value v) noexcept {
  return checked_cast<core::ChuckState>(v, 4);
}
std::optional<core::Service> from_idl(idl::services::Service v) noexcept {
  return checked_cast<core::Service>(v, 10);
}
std::optional<core::SubType> from_idl(idl::sub_types::SubType v) noexcept {
  return checked_cast<core::SubType>(v, 2);
}
std::optional<core::InterfaceType> from_idl(idl::interface_types::InterfaceType v) noexcept {
  return checked_cast<core::InterfaceType>(v, 4);
}

std::int64_t realtime_ns() noexcept {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace mtc::dds::detail::topics
