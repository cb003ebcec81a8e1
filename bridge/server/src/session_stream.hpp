// What a Session keeps while it streams: shared by session.cpp (closing,
// shutdown) and session_stream.cpp (the parts).
#pragma once

#include <array>
#include <atomic>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstdint>
#include <string>

#include "session.hpp"

namespace mtc::bridge::detail {

// Final boundary of a stream at shutdown: a client that does not take it
// quickly is simply closed.
inline constexpr std::chrono::milliseconds kStreamEndTimeout{1000};

struct Session::Stream {
  explicit Stream(const asio::any_io_executor& executor) : timer(executor) {}
  StreamPlan plan;
  std::string boundary;
  asio::steady_timer timer;
  std::chrono::steady_clock::time_point armed_for = std::chrono::steady_clock::time_point::max();
  std::chrono::steady_clock::time_point last_part{};
  std::uint64_t subscription = 0;
  bool subscribed = false;
  bool writing = false;
  bool ending = false;            // shutdown asked for the final boundary
  bool ended = false;             // the final boundary is on its way
  bool stop_after_write = false;  // the agent answered an error part
  std::atomic<bool> wake_pending{false};
  std::array<char, 256> sink{};  // client bytes while streaming, discarded
};

}  // namespace mtc::bridge::detail
