// The HTTP/1.1 front of the bridge: accepts connections, parses requests
// with hard limits, hands each request target to an mtc::bridge::Agent and
// writes what it answers, including multipart/x-mixed-replace streams.
//
// It knows nothing of XML: documents come from the Agent, including those
// for the few errors the server finds itself (unparsable request, oversized
// header, request body, too many connections: Agent::error_document).
//
// Threads: `io_threads` threads run one io_context; every connection lives on
// its own strand, so a slow or hostile client never blocks another one.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "mtc/bridge/agent.hpp"

namespace mtc::bridge {

struct ServerOptions {
  std::string bind_address = "127.0.0.1";  // loopback unless told otherwise
  std::uint16_t port = 5000;               // 0 = any free port (tests)
  unsigned io_threads = 1;
  std::size_t max_connections = 256;  // more are answered 503 and closed
  std::size_t header_limit = 8192;    // request line + headers, bytes
  // A request's header must be complete this long after its first byte.
  std::chrono::milliseconds header_timeout{10000};
  // A keep-alive connection with no new request is closed after this.
  std::chrono::milliseconds idle_timeout{30000};
  // A write (response or stream part) the client does not take in this
  // long closes the connection: a stalled reader cannot pin memory.
  std::chrono::milliseconds write_timeout{30000};
  std::string server_name = "mtc-bridge";
};

class HttpServer {
 public:
  // Binds and listens at once (so the port is known and errors surface
  // here); throws std::system_error when the address cannot be bound.
  HttpServer(std::shared_ptr<Agent> agent, ServerOptions options);
  ~HttpServer();  // stop()
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  // Starts accepting on the io threads. Call once.
  void start();

  // Closes the listener, ends every stream with its closing boundary,
  // closes every connection and joins the io threads. Idempotent.
  void stop();

  // The bound port (useful when options.port was 0).
  std::uint16_t port() const noexcept;
  const std::string& bind_address() const noexcept;

  // Connections open right now (tests, diagnostics).
  std::size_t connection_count() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mtc::bridge
