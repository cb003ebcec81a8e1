// A deliberately low-level HTTP client for the server tests: POSIX sockets,
// exact bytes out, deadline-bounded reads in (poll), and small parsers for a
// response, a chunked body and multipart parts. Garbage, slow and half-open
// clients are written with it.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>

namespace mtc::bridge::test {

using namespace std::chrono_literals;

struct HttpResponse {
  int status = 0;
  std::string version;                         // "HTTP/1.1"
  std::map<std::string, std::string> headers;  // names lower-cased
  std::string body;

  std::string header(const std::string& name) const {
    const auto it = headers.find(name);
    return it == headers.end() ? std::string() : it->second;
  }
};

struct Part {
  std::map<std::string, std::string> headers;  // names lower-cased
  std::string body;
};

// How an abusive client connects.
struct ConnectOptions {
  // Source address, e.g. "127.0.0.2": every 127/8 address is loopback, so
  // tests can be several clients as the server counts them (per address).
  const char* source = nullptr;
  // SO_RCVBUF before connecting: a small window fills fast when the client
  // never reads. 0: the kernel's default.
  int receive_buffer = 0;
};

class RawClient {
 public:
  // Connects to 127.0.0.1:port; throws on failure.
  explicit RawClient(std::uint16_t port, const ConnectOptions& options = {});
  ~RawClient();
  RawClient(const RawClient&) = delete;
  RawClient& operator=(const RawClient&) = delete;

  void send(std::string_view bytes);               // all of them, or throws
  bool try_send(std::string_view bytes) noexcept;  // false once the peer is gone
  void shutdown_write();
  void close();
  void reset();  // close with SO_LINGER 0: the peer gets a RST

  // Reads until `done(buffer)` holds, EOF, or the timeout; returns done().
  bool read_until(const std::function<bool(const std::string&)>& done,
                  std::chrono::milliseconds timeout = 5s);
  // True once the server closed the connection (EOF or reset) in time.
  bool wait_closed(std::chrono::milliseconds timeout = 5s);
  bool eof() const noexcept { return eof_; }

  // One complete response (Content-Length framed, or until EOF when the
  // server closes without one). `head_only` for answers to HEAD.
  std::optional<HttpResponse> read_response(std::chrono::milliseconds timeout = 5s,
                                            bool head_only = false);

  // Streaming: reads the response head, then de-chunks and splits parts.
  std::optional<HttpResponse> read_stream_head(std::chrono::milliseconds timeout = 5s);
  std::optional<Part> read_part(std::chrono::milliseconds timeout = 5s);
  // True when the closing boundary and the zero chunk have arrived.
  bool read_stream_end(std::chrono::milliseconds timeout = 5s);

  std::string& buffer() noexcept { return buffer_; }

 private:
  bool fill(std::chrono::steady_clock::time_point deadline);  // one read
  bool dechunk();  // moves complete chunks from buffer_ to body_

  int fd_ = -1;
  bool eof_ = false;
  std::string buffer_;  // raw bytes received, not yet consumed
  std::string body_;    // de-chunked stream body, not yet consumed
  bool last_chunk_ = false;
  std::string boundary_;
};

// "GET <target> HTTP/1.1" with Host, optionally more header lines.
std::string get_request(std::string_view target, std::string_view extra_headers = {});

}  // namespace mtc::bridge::test
