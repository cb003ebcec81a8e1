// What the fuzz targets of tests/fuzz share: a reader that turns the
// fuzzer's bytes into typed fields, and the checks whose failure is a
// finding (a crash for libFuzzer, a failed replay for ctest).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <pugixml.hpp>
#include <string>
#include <string_view>

#include "mtc/bridge/xml_text.hpp"

namespace mtc::fuzz {

// Consumes the input front to back; once it is exhausted every value is 0
// or empty, so a target never reads past the end.
class ByteReader {
 public:
  ByteReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  bool empty() const noexcept { return offset_ >= size_; }

  template <typename Int>
  Int integer() noexcept {
    Int value{};
    const std::size_t n = std::min(sizeof(Int), size_ - offset_);
    std::memcpy(&value, data_ + offset_, n);
    offset_ += n;
    return value;
  }

  std::uint8_t byte() noexcept { return integer<std::uint8_t>(); }

  // A length byte, then that many bytes (fewer at the end of the input).
  std::string string(std::size_t max_length = 255) {
    const std::size_t wanted = std::min<std::size_t>(byte(), max_length);
    const std::size_t n = std::min(wanted, size_ - offset_);
    std::string out(reinterpret_cast<const char*>(data_ + offset_), n);
    offset_ += n;
    return out;
  }

  // Everything not consumed yet.
  std::string_view rest() noexcept {
    std::string_view out(reinterpret_cast<const char*>(data_ + offset_), size_ - offset_);
    offset_ = size_;
    return out;
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t offset_ = 0;
};

// A broken invariant: report it and abort, which libFuzzer records as a
// crash with its input and the replay test as a failure.
[[noreturn]] inline void finding(const char* what, std::string_view detail = {}) {
  std::fprintf(stderr, "fuzz finding: %s: %.*s\n", what, static_cast<int>(detail.size()),
               detail.data());
  std::abort();
}

inline void require(bool ok, const char* what, std::string_view detail = {}) {
  if (!ok) finding(what, detail);
}

// Every document the bridge answers must be XML: well-formed, and only
// characters XML allows (pugixml alone does not check those).
inline void require_xml_document(const std::string& body, const char* what) {
  require(bridge::find_unfit_xml_char(body) == std::string::npos, what,
          "a character XML does not allow");
  pugi::xml_document doc;
  const auto parsed = doc.load_buffer(body.data(), body.size());
  require(parsed.status == pugi::status_ok, what, parsed.description());
  require(doc.document_element() != nullptr, what, "no root element");
}

}  // namespace mtc::fuzz
