#include "mtc/bridge/schema_version.hpp"

namespace mtc::bridge {

namespace {
struct VersionRow {
  SchemaVersion version;
  std::string_view text;
  std::string_view header;
};
constexpr VersionRow kVersions[] = {
    {SchemaVersion::V1_3, "1.3", "1.3.0.0"},
    {SchemaVersion::V1_6, "1.6", "1.6.0.0"},
    {SchemaVersion::V1_8, "1.8", "1.8.0.0"},
    {SchemaVersion::V2_0, "2.0", "2.0.0.0"},
};
}  // namespace

std::optional<SchemaVersion> parse_schema_version(std::string_view text) noexcept {
  for (const auto& row : kVersions) {
    if (text == row.text) return row.version;
    // "1.6.0", "1.6.0.0": a longer dotted form of the same minor version.
    if (text.size() > row.text.size() && text.substr(0, row.text.size()) == row.text &&
        text[row.text.size()] == '.') {
      return row.version;
    }
  }
  return std::nullopt;
}

std::string_view to_string(SchemaVersion v) noexcept {
  for (const auto& row : kVersions) {
    if (row.version == v) return row.text;
  }
  return "1.6";
}

std::string_view header_version(SchemaVersion v) noexcept {
  for (const auto& row : kVersions) {
    if (row.version == v) return row.header;
  }
  return "1.6.0.0";
}

bool devices_schema_has(SchemaVersion v, std::string_view component_element) noexcept {
  if (v != SchemaVersion::V1_3) return true;
  return component_element != "BarFeederInterface" &&
         component_element != "MaterialHandlerInterface";
}

}  // namespace mtc::bridge
