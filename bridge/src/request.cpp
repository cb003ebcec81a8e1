#include "request.hpp"

#include <limits>

namespace mtc::bridge::detail {

IntegerError parse_integer(std::string_view text, std::int64_t& out) noexcept {
  bool negative = false;
  if (!text.empty() && text.front() == '-') {
    negative = true;
    text.remove_prefix(1);
  }
  if (text.empty()) return IntegerError::NotInteger;
  for (char c : text) {
    if (c < '0' || c > '9') return IntegerError::NotInteger;
  }
  constexpr auto kMax = static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max());
  std::uint64_t value = 0;
  for (char c : text) {
    const auto digit = static_cast<std::uint64_t>(c - '0');
    if (value > (kMax - digit) / 10) return IntegerError::Overflow;
    value = value * 10 + digit;
  }
  out = negative ? -static_cast<std::int64_t>(value) : static_cast<std::int64_t>(value);
  return IntegerError::None;
}

}  // namespace mtc::bridge::detail
