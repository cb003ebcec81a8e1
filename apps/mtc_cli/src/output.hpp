// Line output of the `mtc` tool. Every line is flushed at once so that a
// script (or the cross-process tests) reading a pipe sees events as they
// happen. JsonLine builds one JSON object per line with fields in insertion
// order; Output serialises lines written from several threads.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <mutex>
#include <string>
#include <string_view>

namespace mtc::cli {

class JsonLine {
 public:
  JsonLine& field(std::string_view key, std::string_view value);
  JsonLine& field(std::string_view key, const char* value) {
    return field(key, std::string_view(value));
  }
  JsonLine& field(std::string_view key, const std::string& value) {
    return field(key, std::string_view(value));
  }
  JsonLine& field(std::string_view key, std::int64_t value);
  JsonLine& field(std::string_view key, std::uint64_t value);
  JsonLine& field(std::string_view key, int value) {
    return field(key, static_cast<std::int64_t>(value));
  }
  JsonLine& field(std::string_view key, double value);
  JsonLine& field(std::string_view key, bool value);
  JsonLine& null_field(std::string_view key);
  // Inserts already-serialised JSON (an array or object built elsewhere).
  JsonLine& raw_field(std::string_view key, std::string_view json);
  std::string str() const { return "{" + body_ + "}"; }

 private:
  void key(std::string_view k);
  std::string body_;
};

// JSON string literal of text (quotes included), control characters escaped.
std::string json_quote(std::string_view text);

class Output {
 public:
  explicit Output(std::ostream& out) : out_(out) {}
  void line(const std::string& text);
  // False once a write failed (e.g. the reader of our pipe went away).
  bool good() const;

 private:
  std::ostream& out_;
  mutable std::mutex mutex_;
};

// Wall clock (CLOCK_REALTIME) in ns since the epoch, the clock source_time_ns uses.
std::int64_t now_ns() noexcept;
// "2026-11-21T06:01:02.123456Z" for a time in ns since the epoch.
std::string format_utc(std::int64_t ns);
// "1.234 ms" for a duration in ns.
std::string format_ms(std::int64_t ns);

}  // namespace mtc::cli
