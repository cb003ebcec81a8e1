// One client connection: reads requests under strict limits, answers them
// through the Agent, and turns a StreamPlan into a chunked multipart stream.
// Every handler of a session runs on that session's strand (or, with one io
// thread, on that thread: one at a time all the same). A streaming session's
// handlers also hold its stream mutex, which the thread feeding the agent
// tries (never waits for) to write a part directly.
#pragma once

#include <array>
#include <atomic>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/http/empty_body.hpp>
#include <boost/beast/http/parser.hpp>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>

#include "connection.hpp"
#include "mtc/bridge/http_server.hpp"

namespace mtc::bridge::detail {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = asio::ip::tcp;

class Session;

// What every session of one server shares; outlives them all.
struct ServerShared {
  std::shared_ptr<Agent> agent;
  ServerOptions options;
  std::unique_ptr<asio::ssl::context> tls;  // null: plain HTTP
  std::atomic<bool> stopping{false};
  // Answer bytes on their way to clients (ServerOptions::max_pending_bytes).
  std::atomic<std::size_t> pending_bytes{0};
  // Connections being answered 503 (not in `sessions`); beyond
  // max_connections more are closed without an answer.
  std::atomic<std::size_t> rejecting{0};
  // Streams open, i.e. subscribed to the agent (ServerOptions::
  // direct_stream_writes), and parts written directly by the thread that
  // fed the agent.
  std::atomic<std::size_t> streams{0};
  std::atomic<std::uint64_t> direct_parts{0};

  std::mutex mutex;  // guards sessions
  std::unordered_map<std::uint64_t, std::weak_ptr<Session>> sessions;
  std::uint64_t next_id = 1;
};

class Session : public std::enable_shared_from_this<Session> {
 public:
  // `remote`: the client's address, for the per-client limit.
  Session(tcp::socket socket, std::shared_ptr<ServerShared> shared, std::uint64_t id,
          std::string remote);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  void start();        // serve requests
  void reject_busy();  // answer 503 and close (over the connection limit)
  void shutdown();     // server stop: end a stream with its boundary, close
  void evict();        // make room for a new connection: close

  // The connection's strand (the io_context's executor with one io thread).
  asio::any_io_executor executor() { return stream_.tcp().get_executor(); }
  const std::string& remote() const noexcept { return remote_; }
  std::uint64_t id() const noexcept { return id_; }
  // Since when (steady clock, ns) the connection waits for a request or the
  // rest of one; 0 while one is being answered or streamed. Read under the
  // server's mutex from the accepting thread.
  std::int64_t waiting_since() const noexcept { return waiting_since_.load(); }

 private:
  struct Stream;

  void wait_for_request();
  void read_header();
  void on_header(beast::error_code ec);
  void handle_request();
  void answer(Response response, bool keep_alive, bool head_only);
  void answer_error(int status, std::string_view code, std::string_view message);
  void on_answered(beast::error_code ec, bool keep_alive);
  void linger_close();
  void close();
  void mark_waiting(bool waiting);
  // Counts an answer's bytes in ServerShared::pending_bytes until written;
  // false (nothing counted) when a large one would pass the limit.
  bool hold_pending(std::size_t bytes);
  void release_pending();

  void start_stream(StreamPlan plan);
  void read_until_eof();
  void on_new_data();  // the agent's subscriber, on the thread that fed it
  bool write_part_directly();
  void on_wake();
  void pump();
  void arm_timer(std::chrono::steady_clock::time_point due);
  using PartBuffers = std::array<asio::const_buffer, 3>;  // part head, body, tail
  void write_part();
  std::size_t write_now(const PartBuffers& buffers);
  PartBuffers part_buffers() const;
  void write_rest(std::size_t written);
  void end_subscription();  // unsubscribes and stops counting the stream
  void write_stream_end();
  void on_part_written(beast::error_code ec, bool last);

  std::shared_ptr<ServerShared> shared_;
  std::uint64_t id_;
  std::string remote_;
  std::atomic<std::int64_t> waiting_since_{0};
  std::chrono::steady_clock::time_point first_deadline_;  // whole first header
  std::size_t pending_ = 0;                               // this session's share of pending_bytes
  Connection stream_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::empty_body>> parser_;
  unsigned version_ = 11;
  bool first_request_ = true;
  bool closed_ = false;
  bool lingering_ = false;
  std::size_t lingered_ = 0;
  std::chrono::steady_clock::time_point linger_deadline_{};
  std::string head_;  // response header / chunk framing, reused
  std::string body_;
  std::unique_ptr<Stream> stream_state_;
  // Held by every handler of a streaming session, and by a direct part.
  std::mutex stream_mutex_;
};

}  // namespace mtc::bridge::detail
