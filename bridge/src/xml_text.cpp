#include "mtc/bridge/xml_text.hpp"

#include <algorithm>
#include <cstdint>

namespace mtc::bridge {
namespace {

constexpr std::string_view kReplacement = "\xEF\xBF\xBD";  // U+FFFD in UTF-8

bool is_xml_char(std::uint32_t cp) noexcept {
  if (cp < 0x20) return cp == 0x09 || cp == 0x0A || cp == 0x0D;
  if (cp >= 0xD800 && cp <= 0xDFFF) return false;
  return cp != 0xFFFE && cp != 0xFFFF && cp <= 0x10FFFF;
}

// Length of the well-formed UTF-8 sequence at text[i] that encodes an XML
// Char, or 0 when the bytes there are not one (RFC 3629: no overlong forms,
// no surrogates, nothing above U+10FFFF).
std::size_t fit_sequence(std::string_view text, std::size_t i) noexcept {
  const auto lead = static_cast<unsigned char>(text[i]);
  if (lead < 0x80) return is_xml_char(lead) ? 1 : 0;
  std::size_t length = 0;
  std::uint32_t cp = 0;
  std::uint32_t min = 0;
  if ((lead & 0xE0) == 0xC0) {
    length = 2;
    cp = lead & 0x1Fu;
    min = 0x80;
  } else if ((lead & 0xF0) == 0xE0) {
    length = 3;
    cp = lead & 0x0Fu;
    min = 0x800;
  } else if ((lead & 0xF8) == 0xF0) {
    length = 4;
    cp = lead & 0x07u;
    min = 0x10000;
  } else {
    return 0;  // a continuation byte or 0xF8..0xFF where a sequence starts
  }
  if (text.size() - i < length) return 0;
  for (std::size_t k = 1; k < length; ++k) {
    const auto next = static_cast<unsigned char>(text[i + k]);
    if ((next & 0xC0) != 0x80) return 0;
    cp = (cp << 6) | (next & 0x3Fu);
  }
  return cp >= min && is_xml_char(cp) ? length : 0;
}

bool is_upper_word(std::string_view text) noexcept {
  if (text.empty() || text.front() < 'A' || text.front() > 'Z') return false;
  return std::all_of(text.begin(), text.end(), [](char c) {
    return (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
  });
}

bool is_prefix(std::string_view text) noexcept {
  if (text.empty()) return false;
  const char first = text.front();
  if (!((first >= 'a' && first <= 'z') || (first >= 'A' && first <= 'Z') || first == '_')) {
    return false;
  }
  return std::all_of(text.begin(), text.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-' || c == '.';
  });
}

}  // namespace

std::size_t find_unfit_xml_char(std::string_view text) noexcept {
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t length = fit_sequence(text, i);
    if (length == 0) return i;
    i += length;
  }
  return std::string_view::npos;
}

std::string make_xml_safe(std::string_view text) {
  std::size_t bad = find_unfit_xml_char(text);
  if (bad == std::string_view::npos) return std::string(text);
  std::string out;
  out.reserve(text.size() + 8);
  std::size_t i = 0;
  while (bad != std::string_view::npos) {
    out.append(text.substr(i, bad - i));
    out.append(kReplacement);
    i = bad + 1;  // resynchronise on the next byte
    while (i < text.size() && fit_sequence(text, i) == 0) {
      // A run of unfit bytes is one replacement per byte: a reader can still
      // count what was there.
      out.append(kReplacement);
      ++i;
    }
    const std::size_t rest = find_unfit_xml_char(text.substr(i));
    bad = rest == std::string_view::npos ? rest : i + rest;
  }
  out.append(text.substr(i));
  return out;
}

bool is_data_item_type(std::string_view text) noexcept {
  const auto colon = text.find(':');
  if (colon == std::string_view::npos) return is_upper_word(text);
  return is_prefix(text.substr(0, colon)) && is_upper_word(text.substr(colon + 1));
}

}  // namespace mtc::bridge
