// Internal: the IDL <-> core enum conversions of the Fast DDS types (the
// topic names and item ids are topic_names.hpp's). Used by the Fast DDS
// backend, tests and raw peers (never by a public header).
#pragma once

#include <optional>

#include "mtc/core/vocabulary.hpp"
#include "mtc/dds/detail/topic_names.hpp"
#include "mtc/idl/mtconnect_interfaces.h"

namespace mtc::dds::detail::topics {

// Conversions between the IDL enums and the core vocabulary, by position:
// topics.cpp pairs every enumerator and fails the build if the two sides
// fall out of order. from_idl returns nullopt for a value outside the enum,
// which a peer of another vendor could send.
idl::interaction_state::Value to_idl(core::InteractionState s) noexcept;
idl::interface_state::Value to_idl(core::InterfaceState s) noexcept;
idl::door_state::Value to_idl(core::DoorState s) noexcept;
idl::chuck_state::Value to_idl(core::ChuckState s) noexcept;
idl::services::Service to_idl(core::Service s) noexcept;
idl::sub_types::SubType to_idl(core::SubType s) noexcept;
idl::interface_types::InterfaceType to_idl(core::InterfaceType t) noexcept;

std::optional<core::InteractionState> from_idl(idl::interaction_state::Value v) noexcept;
std::optional<core::InterfaceState> from_idl(idl::interface_state::Value v) noexcept;
std::optional<core::DoorState> from_idl(idl::door_state::Value v) noexcept;
std::optional<core::ChuckState> from_idl(idl::chuck_state::Value v) noexcept;
std::optional<core::Service> from_idl(idl::services::Service v) noexcept;
std::optional<core::SubType> from_idl(idl::sub_types::SubType v) noexcept;
std::optional<core::InterfaceType> from_idl(idl::interface_types::InterfaceType v) noexcept;

}  // namespace mtc::dds::detail::topics
