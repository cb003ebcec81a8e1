#include "console.hpp"

#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdarg>
#include <cstdio>
#include <ctime>

namespace mtc::cell {

void print_line(std::string_view station, std::string_view text) {
  const auto now = std::chrono::system_clock::now();
  const auto ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count();
  const auto secs = static_cast<std::time_t>(ms / 1000);
  std::tm tm{};
  gmtime_r(&secs, &tm);
  char head[48];
  std::snprintf(head, sizeof head, "%02d:%02d:%02d.%03d  %-8.*s| ", tm.tm_hour, tm.tm_min,
                tm.tm_sec, static_cast<int>(ms % 1000), static_cast<int>(station.size()),
                station.data());
  std::string line(head);
  line.append(text);
  line.push_back('\n');
  // One write per line; a short write to a terminal or pipe is not worth a
  // retry loop for a log line, but EINTR is.
  ssize_t rc = 0;
  do {
    rc = ::write(STDOUT_FILENO, line.data(), line.size());
  } while (rc < 0 && errno == EINTR);
}

// printf-style on purpose: the header's format attribute lets the compiler
// check every call's arguments against its format string.
std::string format(const char* fmt, ...) {  // NOLINT(cert-dcl50-cpp)
  char buf[512];
  va_list args;
  va_start(args, fmt);
  const int n = std::vsnprintf(buf, sizeof buf, fmt, args);
  va_end(args);
  if (n < 0) {
    return {};
  }
  return std::string(
      buf, static_cast<std::size_t>(n) < sizeof buf ? static_cast<std::size_t>(n) : sizeof buf - 1);
}

}  // namespace mtc::cell
