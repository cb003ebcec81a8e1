// Request targets: "/mill/sample?from=10&count=5" split into decoded path
// segments and query parameters, plus strict integer parsing. Internal to
// mtc_bridge.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace mtc::bridge::detail {

struct Target {
  std::vector<std::string> segments;                         // decoded, non-empty
  std::vector<std::pair<std::string, std::string>> query;    // decoded, in order
};

// nullopt with `error` set for a target that is not an origin-form path
// ("/..."), has a bad %-escape, a NUL byte, or is absurdly long.
std::optional<Target> parse_target(std::string_view target, std::string& error);

enum class IntegerError { None, NotInteger, Overflow };

// Decimal integer, optional leading '-', nothing else (no spaces, no '+',
// no hex, no fraction).
IntegerError parse_integer(std::string_view text, std::int64_t& out) noexcept;

}  // namespace mtc::bridge::detail
