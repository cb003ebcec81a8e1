// The HTTP/1.1 front of the bridge: accepts connections, parses requests
// with hard limits, hands each request target to an mtc::bridge::Agent and
// writes what it answers, including multipart/x-mixed-replace streams.
//
// It knows nothing of XML: documents come from the Agent, including those
// for the few errors the server finds itself (unparsable request, oversized
// header, request body, too many connections: Agent::error_document).
//
// Threads: `io_threads` threads run one io_context; with more than one, every
// connection lives on its own strand. A slow or hostile client never blocks
// another one: no handler waits on a client.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "mtc/bridge/agent.hpp"

namespace mtc::bridge {

// The server's limits. Under abuse (slow or idle connections by the
// thousand, clients that never read) they keep memory bounded and keep
// well-behaved clients served: a connection that is only waiting (for its
// first request, for the rest of a header, or idle between requests) is
// closed, oldest first, to make room for a new one.
struct ServerOptions {
  std::string bind_address = "127.0.0.1";  // loopback unless told otherwise
  std::uint16_t port = 5000;               // 0 = any free port (tests)
  unsigned io_threads = 1;
  // Open connections. A new one beyond it takes the place of the one that
  // has waited longest without a request in progress; when every one is
  // busy (answering, streaming), it is answered 503 and closed.
  std::size_t max_connections = 256;
  // Open connections from one client address, so that a single host cannot
  // take every place; beyond it, that host's longest-waiting connection
  // makes room, or the new one is answered 503.
  std::size_t max_connections_per_client = 64;
  std::size_t header_limit = 8192;  // request line + headers, bytes
  // A new connection must have sent its whole first request header this
  // long after it was accepted; a later request's header must be complete
  // this long after its first byte (1 byte a second gets nowhere).
  std::chrono::milliseconds header_timeout{10000};
  // A keep-alive connection with no new request is closed after this.
  std::chrono::milliseconds idle_timeout{30000};
  // A write (response or stream part) the client does not take in this
  // long closes the connection: a stalled reader cannot pin memory.
  std::chrono::milliseconds write_timeout{30000};
  // Bytes of answers written to sockets and not yet taken by their
  // clients, all connections together. An answer larger than 64 KiB that
  // would go beyond it is replaced by a 503 (a stream's part waits), so
  // clients that never read cannot pin more; small answers always go.
  std::size_t max_pending_bytes = std::size_t{64} << 20;
  // While at most this many streams are open, a plain-HTTP stream's part is
  // written by the thread that fed the agent (the DDS observer's), straight
  // after the value, when the stream is idle and the socket takes the part
  // at once: one thread wake-up less on the way to the client (~25 us on
  // the 2-vCPU machine of docs/benchmarks.md). What the socket does not take
  // at once, a stream that is busy or TLS, and every stream beyond this
  // many go through the io threads. That thread's cost is one non-blocking
  // send per such stream; 0 sends every part from the io threads.
  std::size_t direct_stream_writes = 4;
  std::string server_name = "mtc-bridge";
  // HTTPS: PEM certificate (chain) and private key. Both set: every
  // connection speaks TLS (a plain HTTP client fails its handshake); both
  // empty: plain HTTP. One without the other, or a file that cannot be used,
  // is refused by the constructor (std::invalid_argument naming it).
  std::string tls_certificate_file;
  std::string tls_private_key_file;
};

class HttpServer {
 public:
  // Binds and listens at once (so the port is known and errors surface
  // here); throws std::system_error when the address cannot be bound and
  // std::invalid_argument for unusable TLS files.
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
  bool is_https() const noexcept;

  // Connections open right now (tests, diagnostics).
  std::size_t connection_count() const noexcept;
  // Answer bytes written and not yet taken by clients (max_pending_bytes).
  std::size_t pending_bytes() const noexcept;
  // Stream parts written by the thread that fed the agent, not by an io
  // thread (ServerOptions::direct_stream_writes), since start.
  std::uint64_t direct_stream_parts() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mtc::bridge
