// The bridge as an MTConnect adapter: a TCP listener speaking SHDR, the
// line protocol MTConnect agents (the reference agent, cppagent) read from
// their adapters, so a site's existing agent picks up the Part 5 items.
//
// To each agent that connects: first the latest value of every data item,
// then every change as it happens, one `timestamp|item|value` line each
// (item = the data item's id in the bridge's Devices model, i.e. its
// /probe). `* PING` is answered `* PONG <heartbeat ms>`. A device's comms
// loss reaches the agent as UNAVAILABLE lines (the bridge's agent records
// them as observations). Several agents may connect at once.
//
// Memory per connection is bounded: one batch of lines is in flight at a
// time; a connection that falls so far behind that the bridge's buffer has
// overwritten what it has not read yet is closed (the agent reconnects and
// gets the full state again), never queued without end.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "mtc/bridge/mtconnect_agent.hpp"

namespace mtc::bridge {

struct ShdrOptions {
  std::string bind_address = "127.0.0.1";  // loopback unless told otherwise
  std::uint16_t port = 7878;               // 0 = any free port (tests)
  // Announced in `* PONG <ms>`: the agent pings this often and gives up on
  // the connection after about twice this without a line.
  std::chrono::milliseconds heartbeat{10000};
  std::size_t max_connections = 16;  // more are closed at once
  std::size_t batch = 1000;          // observations per write
};

// Counters, for logs and tests.
struct ShdrStats {
  std::uint64_t connections = 0;  // accepted so far
  std::uint64_t lines = 0;        // observation lines written
  std::uint64_t dropped = 0;      // connections closed for falling behind
  std::uint64_t pongs = 0;
};

class ShdrAdapter {
 public:
  // Binds and listens at once; throws std::system_error when the address
  // cannot be bound, std::invalid_argument without an agent.
  ShdrAdapter(std::shared_ptr<MtconnectAgent> agent, ShdrOptions options);
  ~ShdrAdapter();  // stop()
  ShdrAdapter(const ShdrAdapter&) = delete;
  ShdrAdapter& operator=(const ShdrAdapter&) = delete;

  void start();  // accepts on its own thread; call once
  void stop();   // closes every connection, joins the thread; idempotent

  std::uint16_t port() const noexcept;
  const std::string& bind_address() const noexcept;
  std::size_t connection_count() const;
  ShdrStats stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// One SHDR line (with its '\n') for an observation: `time|item|value`, or
// for a condition `time|item|LEVEL||||`. '|' and line breaks in the value
// become spaces (SHDR has no escape for them).
std::string shdr_line(const ItemObservation& o);

}  // namespace mtc::bridge
