// MTConnect schema versions the agent can print, and what each one's
// official XSD accepts (see /shared/schemas/README.md for the audit).
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace mtc::bridge {

enum class SchemaVersion : std::uint8_t { V1_3, V1_6, V1_8, V2_0 };

// "1.3", "1.6", "1.8", "2.0" (also accepts "1.6.0" style prefixes).
std::optional<SchemaVersion> parse_schema_version(std::string_view text) noexcept;
std::string_view to_string(SchemaVersion v) noexcept;

// Header version attribute, e.g. "1.6.0.0".
std::string_view header_version(SchemaVersion v) noexcept;

// 1.8 and 2.0 headers carry deviceModelChangeTime (required there, absent
// before).
constexpr bool has_model_change_time(SchemaVersion v) noexcept {
  return v == SchemaVersion::V1_8 || v == SchemaVersion::V2_0;
}

// The 1.8 Devices schema requires an <Agent> as the first device.
constexpr bool requires_agent_device(SchemaVersion v) noexcept {
  return v == SchemaVersion::V1_8;
}

// Whether the version's Devices schema has an element for this component
// (only DoorInterface and ChuckInterface exist in 1.3). Unknown names are
// accepted: the printer does not police user Devices files.
bool devices_schema_has(SchemaVersion v, std::string_view component_element) noexcept;

}  // namespace mtc::bridge
