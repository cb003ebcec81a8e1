// A minimal streaming JSON writer for the agent's JSON documents: objects,
// arrays, strings, unsigned integers, numbers and booleans, with commas and
// (optionally) indentation handled here. Strings must be valid UTF-8 (the
// model and error texts are made XML-safe first, which guarantees it);
// quotes, backslashes and control characters are escaped. Internal to
// mtc_bridge.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace mtc::bridge::detail {

class JsonWriter {
 public:
  JsonWriter(std::string& out, bool pretty) : out_(out), pretty_(pretty) {}

  JsonWriter& begin_object();
  JsonWriter& end_object();
  JsonWriter& begin_array();
  JsonWriter& end_array();
  // The key of the next member of the current object.
  JsonWriter& key(std::string_view name);
  JsonWriter& string(std::string_view text);
  JsonWriter& number(std::uint64_t value);
  // A decimal number as text (already checked to be a JSON number).
  JsonWriter& raw_number(std::string_view text);
  JsonWriter& boolean(bool value);

  // Shorthands for one member.
  JsonWriter& member(std::string_view name, std::string_view text) {
    return key(name).string(text);
  }
  JsonWriter& member(std::string_view name, std::uint64_t value) { return key(name).number(value); }

 private:
  void before_value();
  void newline();

  std::string& out_;
  bool pretty_;
  std::vector<bool> first_;  // per open container: nothing written in it yet
  bool after_key_ = false;
};

// True when `text` is a JSON number as strtod would read a sample value
// ("12.5", "-3", "1e-3"), so it may be printed unquoted.
bool is_json_number(std::string_view text) noexcept;

}  // namespace mtc::bridge::detail
