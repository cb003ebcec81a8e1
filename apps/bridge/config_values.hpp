// The value syntax of the bridge's settings, in a file or on the command
// line: integers and milliseconds in a range, lists, printable text. Each
// refusal names where the value came from ("agent.cfg:12: Port ...").
#pragma once

#include <algorithm>
#include <charconv>
#include <chrono>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "bridge_config.hpp"

namespace mtc::bridge::config_values {

[[noreturn]] inline void fail(const std::string& origin, const std::string& message) {
  throw ConfigError(origin + ": " + message);
}

template <typename Int>
Int parse_int(std::string_view value, Int min, Int max, const std::string& origin,
              std::string_view what) {
  Int result{};
  const auto* end = value.data() + value.size();
  const auto parsed = std::from_chars(value.data(), end, result);
  if (value.empty() || parsed.ec != std::errc() || parsed.ptr != end || result < min ||
      result > max) {
    fail(origin, std::string(what) + " must be an integer from " + std::to_string(min) + " to " +
                     std::to_string(max) + ", not '" + std::string(value) + "'");
  }
  return result;
}

inline std::chrono::milliseconds parse_ms(std::string_view value, long min, long max,
                                          const std::string& origin, std::string_view what) {
  return std::chrono::milliseconds(parse_int<long>(value, min, max, origin, what));
}

// Comma- and/or space-separated items, none empty.
inline std::vector<std::string_view> split_list(std::string_view value) {
  std::vector<std::string_view> items;
  std::size_t start = 0;
  while (start <= value.size()) {
    const auto end = value.find_first_of(", \t", start);
    const auto item = value.substr(start, end == std::string_view::npos ? end : end - start);
    if (!item.empty()) {
      items.push_back(item);
    }
    if (end == std::string_view::npos) {
      break;
    }
    start = end + 1;
  }
  return items;
}

inline bool is_printable(std::string_view value) {
  return std::all_of(value.begin(), value.end(),
                     [](char c) { return static_cast<unsigned char>(c) >= 0x20 && c != 0x7f; });
}

}  // namespace mtc::bridge::config_values
