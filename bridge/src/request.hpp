// Strict integer parsing for query parameters. Internal to mtc_bridge.
#pragma once

#include <cstdint>
#include <string_view>

#include "mtc/bridge/request.hpp"

namespace mtc::bridge::detail {

enum class IntegerError { None, NotInteger, Overflow };

// Decimal integer, optional leading '-', nothing else (no spaces, no '+',
// no hex, no fraction).
IntegerError parse_integer(std::string_view text, std::int64_t& out) noexcept;

}  // namespace mtc::bridge::detail
