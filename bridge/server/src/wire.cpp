#include "wire.hpp"

#include <array>
#include <boost/beast/http/status.hpp>
#include <charconv>
#include <chrono>
#include <cstdint>
#include <ctime>
#include <ostream>  // boost/utility/string_view.hpp needs it first
#include <random>

namespace mtc::bridge::detail {
namespace {

void append_number(std::string& out, std::size_t value, int base = 10) {
  std::array<char, 24> digits{};
  auto result = std::to_chars(digits.data(), digits.data() + digits.size(), value, base);
  out.append(digits.data(), result.ptr);
}

// RFC 7231 IMF-fixdate, recomputed at most once a second per thread.
std::string_view http_date() {
  struct Cache {
    std::time_t second = -1;
    std::array<char, 40> text{};
    std::size_t size = 0;
  };
  thread_local Cache cache;
  const std::time_t now = std::time(nullptr);
  if (now != cache.second) {
    std::tm utc{};
    gmtime_r(&now, &utc);
    // strftime under the "C" locale (the program never calls setlocale).
    cache.size =
        std::strftime(cache.text.data(), cache.text.size(), "%a, %d %b %Y %H:%M:%S GMT", &utc);
    cache.second = now;
  }
  return {cache.text.data(), cache.size};
}

void append_status_line(std::string& out, unsigned version, int status) {
  out.append(version == 10 ? "HTTP/1.0 " : "HTTP/1.1 ");
  append_number(out, static_cast<std::size_t>(status));
  out.push_back(' ');
  out.append(reason_phrase(status));
  out.append("\r\nServer: ");
}

}  // namespace

std::string_view reason_phrase(int status) noexcept {
  auto reason = boost::beast::http::obsolete_reason(
      boost::beast::http::int_to_status(static_cast<unsigned>(status)));
  if (reason.empty() || reason == "<unknown-status>") {
    return "Unknown";
  }
  return {reason.data(), reason.size()};
}

void write_head(std::string& out, const HeadFields& fields) {
  out.clear();
  append_status_line(out, fields.version, fields.status);
  out.append(fields.server_name);
  out.append("\r\nDate: ");
  out.append(http_date());
  out.append("\r\nContent-Type: ");
  out.append(fields.content_type);
  out.append("\r\nContent-Length: ");
  append_number(out, fields.content_length);
  // HTTP/1.1 is persistent unless told; HTTP/1.0 only when asked for.
  if (!fields.keep_alive) {
    out.append("\r\nConnection: close");
  } else if (fields.version == 10) {
    out.append("\r\nConnection: keep-alive");
  }
  out.append("\r\n\r\n");
}

void write_stream_head(std::string& out, std::string_view boundary, std::string_view server_name) {
  out.clear();
  append_status_line(out, 11, 200);
  out.append(server_name);
  out.append("\r\nDate: ");
  out.append(http_date());
  out.append(
      "\r\nCache-Control: no-cache, no-store\r\nContent-Type: multipart/x-mixed-replace;boundary=");
  out.append(boundary);
  out.append("\r\nTransfer-Encoding: chunked\r\n\r\n");
}

void write_part_head(std::string& out, std::string_view boundary, std::string_view content_type,
                     std::size_t body_size) {
  thread_local std::string part;
  part.clear();
  part.append("--");
  part.append(boundary);
  part.append("\r\nContent-type: ");
  part.append(content_type);
  part.append("\r\nContent-length: ");
  append_number(part, body_size);
  part.append("\r\n\r\n");

  append_number(out, part.size() + body_size + 2, 16);  // + the part's CRLF
  out.append("\r\n");
  out.append(part);
}

void write_stream_end(std::string& out, std::string_view boundary) {
  const std::size_t size = 2 + boundary.size() + 4;  // "--" boundary "--\r\n"
  out.clear();
  append_number(out, size, 16);
  out.append("\r\n--");
  out.append(boundary);
  out.append("--\r\n\r\n0\r\n\r\n");
}

std::string make_boundary() {
  std::random_device device;
  std::mt19937_64 engine(
      (static_cast<std::uint64_t>(device()) << 32) ^ device() ^
      static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count()));
  std::string boundary;
  boundary.reserve(32);
  for (int i = 0; i < 2; ++i) {
    const std::uint64_t word = engine();
    std::array<char, 16> hex{};
    auto result = std::to_chars(hex.data(), hex.data() + hex.size(), word, 16);
    boundary.append(16 - static_cast<std::size_t>(result.ptr - hex.data()), '0');
    boundary.append(hex.data(), result.ptr);
  }
  return boundary;
}

}  // namespace mtc::bridge::detail
