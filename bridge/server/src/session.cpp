#include "session.hpp"

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>

#include <array>
#include <boost/asio/post.hpp>
#include <boost/asio/write.hpp>
#include <boost/beast/http/error.hpp>
#include <boost/beast/http/read.hpp>
#include <mutex>
#include <utility>

#include "session_stream.hpp"
#include "wire.hpp"

namespace mtc::bridge::detail {
namespace {

using Clock = std::chrono::steady_clock;

// Bytes read per wait for a new request; requests are small.
constexpr std::size_t kReadChunk = 4096;
// How long a connection we answered with an error may keep sending before
// we close it; draining first keeps the error from being lost to a reset.
constexpr std::chrono::milliseconds kLingerTimeout{1000};
constexpr std::size_t kLingerLimit = std::size_t{64} * 1024;
// Answers up to this size always go (errors, /current, /probe); larger ones
// count against ServerOptions::max_pending_bytes.
constexpr std::size_t kSmallAnswer = std::size_t{64} << 10;
// An answer this large is freed once written: a keep-alive client that
// took a large sample and stays connected must not keep its copy alive.
constexpr std::size_t kLargeBody = std::size_t{1} << 20;

std::int64_t steady_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch())
      .count();
}

bool is_quiet_close(const beast::error_code& ec) {
  return ec == http::error::end_of_stream || ec == http::error::partial_message ||
         ec == asio::error::eof || ec == asio::error::connection_reset ||
         ec == asio::error::operation_aborted || ec == beast::error::timeout ||
         ec == asio::error::broken_pipe || ec == asio::error::bad_descriptor;
}

// True when the request line in `data` ends in a well-formed "HTTP/d.d",
// i.e. the client speaks a version we do not (Beast accepts only 1.0/1.1).
bool names_other_http_version(std::string_view data) {
  const auto end = data.find("\r\n");
  if (end == std::string_view::npos || end < 8) {
    return false;
  }
  const auto version = data.substr(end - 8, 8);
  auto digit = [](char c) { return c >= '0' && c <= '9'; };
  return version.substr(0, 5) == "HTTP/" && digit(version[5]) && version[6] == '.' &&
         digit(version[7]);
}

}  // namespace

Session::Session(tcp::socket socket, std::shared_ptr<ServerShared> shared, std::uint64_t id,
                 std::string remote)
    : shared_(std::move(shared)),
      id_(id),
      remote_(std::move(remote)),
      waiting_since_(steady_ns()),
      first_deadline_(Clock::now() + shared_->options.header_timeout),
      stream_(std::move(socket), shared_->tls.get()) {
  beast::error_code ec;
  stream_.tcp().socket().set_option(tcp::no_delay(true), ec);  // best effort
  // A peer that vanished without FIN or RST (cable pulled, host down) would
  // keep a stream's unacknowledged parts retransmitting for ~15 minutes;
  // the kernel gives up after the write timeout instead, which also ends
  // the pending read and so the session.
  const auto user_timeout = static_cast<unsigned>(shared_->options.write_timeout.count());
  ::setsockopt(stream_.tcp().socket().native_handle(), IPPROTO_TCP, TCP_USER_TIMEOUT, &user_timeout,
               sizeof user_timeout);
}

Session::~Session() {
  end_subscription();
  release_pending();
  if (id_ == 0) {  // a connection answered 503 (HttpServer::Impl::on_accept)
    --shared_->rejecting;
    return;
  }
  std::lock_guard<std::mutex> lock(shared_->mutex);
  shared_->sessions.erase(id_);
}

void Session::mark_waiting(bool waiting) {
  waiting_since_ = waiting ? steady_ns() : 0;
}

bool Session::hold_pending(std::size_t bytes) {
  const std::size_t before = shared_->pending_bytes.fetch_add(bytes);
  if (bytes > kSmallAnswer && before + bytes > shared_->options.max_pending_bytes) {
    shared_->pending_bytes.fetch_sub(bytes);
    return false;
  }
  pending_ += bytes;
  return true;
}

void Session::release_pending() {
  if (pending_ == 0) return;
  shared_->pending_bytes.fetch_sub(pending_);
  pending_ = 0;
  if (body_.capacity() >= kLargeBody) std::string().swap(body_);
}

// A stream is counted in ServerShared::streams exactly while it is
// subscribed to the agent.
void Session::end_subscription() {
  if (stream_state_ && stream_state_->subscribed) {
    shared_->agent->unsubscribe(stream_state_->subscription);
    stream_state_->subscribed = false;
    --shared_->streams;
  }
}

void Session::evict() {
  const std::lock_guard lock(stream_mutex_);
  close();
}

void Session::start() {
  if (shared_->stopping) {
    close();
    return;
  }
  if (!stream_.is_tls()) {
    wait_for_request();
    return;
  }
  // The TLS handshake counts against the first request's header timeout.
  stream_.tcp().expires_at(first_deadline_);
  stream_.async_handshake([self = shared_from_this()](beast::error_code ec) {
    if (ec) {
      self->close();
      return;
    }
    self->wait_for_request();
  });
}

// Waits for the first byte of the next request under the idle timeout (the
// header timeout for a new connection), then parses under the header timeout.
void Session::wait_for_request() {
  if (buffer_.size() > 0) {  // pipelined request already here
    read_header();
    return;
  }
  const auto& options = shared_->options;
  if (first_request_) {
    stream_.tcp().expires_at(first_deadline_);
  } else {
    mark_waiting(true);
    stream_.tcp().expires_after(options.idle_timeout);
  }
  stream_.async_read_some(buffer_.prepare(kReadChunk),
                          [self = shared_from_this()](beast::error_code ec, std::size_t bytes) {
                            if (ec) {
                              self->close();
                              return;
                            }
                            self->buffer_.commit(bytes);
                            self->read_header();
                          });
}

void Session::read_header() {
  parser_.emplace();
  parser_->header_limit(static_cast<std::uint32_t>(shared_->options.header_limit));
  if (first_request_) {
    stream_.tcp().expires_at(first_deadline_);
  } else {
    stream_.tcp().expires_after(shared_->options.header_timeout);
  }
  stream_.async_read_header(
      buffer_, *parser_,
      [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_header(ec); });
}

void Session::on_header(beast::error_code ec) {
  first_request_ = false;
  if (!ec) {
    handle_request();
    return;
  }
  // Answer what can be answered; a client that left or stalled gets nothing.
  const bool answerable = !closed_ && !is_quiet_close(ec);
  if (answerable && (ec == http::error::header_limit || ec == http::error::buffer_overflow)) {
    answer_error(431, "INVALID_REQUEST", "request line and headers exceed the size limit");
  } else if (answerable && ec == http::error::bad_version &&
             names_other_http_version(
                 {static_cast<const char*>(buffer_.data().data()), buffer_.size()})) {
    answer_error(505, "INVALID_REQUEST", "only HTTP/1.0 and HTTP/1.1 are served");
  } else if (answerable &&
             ec.category() == http::make_error_code(http::error::bad_target).category()) {
    answer_error(400, "INVALID_REQUEST", "malformed HTTP request: " + ec.message());
  } else {
    close();
  }
}

void Session::handle_request() {
  mark_waiting(false);
  const auto& message = parser_->get();
  version_ = message.version() == 10 ? 10 : 11;  // the parser admits no other
  const bool head_only = message.method() == http::verb::head;
  const std::string_view method =
      head_only ? std::string_view("GET")
                : std::string_view(message.method_string().data(), message.method_string().size());
  bool keep_alive = message.keep_alive();

  // The agent is read-only: a request body is never read. GET with one is
  // refused; other methods still get the agent's UNSUPPORTED answer.
  if (!parser_->is_done()) {
    keep_alive = false;
    if (method == "GET") {
      answer_error(413, "INVALID_REQUEST", "requests to this agent carry no body");
      return;
    }
  }

  // The target is split here, once; the agent types its parameters once,
  // and a stream keeps them for every part.
  const auto accept = message[http::field::accept];
  const Request request = parse_request(method, {message.target().data(), message.target().size()},
                                        {accept.data(), accept.size()});
  Routed routed = shared_->agent->route(request);
  if (routed.stream && !head_only && !shared_->stopping) {
    start_stream(std::move(*routed.stream));
  } else if (routed.stream) {
    Response response;  // HEAD of a stream: headers only, then close
    answer(std::move(response), false, true);
  } else if (routed.response) {
    answer(std::move(*routed.response), keep_alive && !shared_->stopping, head_only);
  } else {
    answer_error(500, "INTERNAL_ERROR", "the agent produced no answer");
  }
}

void Session::answer(Response response, bool keep_alive, bool head_only) {
  body_ = std::move(response.body);
  HeadFields fields;
  fields.status = response.status;
  fields.version = version_;
  fields.content_type = response.content_type;
  fields.content_length = body_.size();
  fields.keep_alive = keep_alive;
  fields.server_name = shared_->options.server_name;
  write_head(head_, fields);
  if (head_only) {
    body_.clear();
  }
  if (!hold_pending(head_.size() + body_.size())) {
    // Clients that do not read hold enough already; this one may retry.
    body_.clear();
    answer_error(503, "INTERNAL_ERROR",
                 "too many answers are waiting for their clients; try again later");
    return;
  }

  stream_.tcp().expires_after(shared_->options.write_timeout);
  const std::array<asio::const_buffer, 2> buffers{asio::buffer(head_), asio::buffer(body_)};
  stream_.async_write(buffers,
                      [self = shared_from_this(), keep_alive](beast::error_code ec, std::size_t) {
                        self->on_answered(ec, keep_alive);
                      });
}

void Session::answer_error(int status, std::string_view code, std::string_view message) {
  Response response = shared_->agent->error_document(status, code, message);
  response.status = status;
  answer(std::move(response), false, false);
}

void Session::on_answered(beast::error_code ec, bool keep_alive) {
  release_pending();
  if (ec) {
    close();
  } else if (keep_alive && !shared_->stopping) {
    wait_for_request();
  } else {
    linger_close();
  }
}

// Half-closes, then discards what the client still sends (bounded in time
// and bytes) so the kernel does not reset the connection under our answer.
void Session::linger_close() {
  if (!lingering_) {
    lingering_ = true;
    waiting_since_ = 1;  // the first to make room for a new connection
    linger_deadline_ = Clock::now() + kLingerTimeout;
    beast::error_code ec;
    stream_.tcp().socket().shutdown(tcp::socket::shutdown_send, ec);
    if (ec) {
      close();
      return;
    }
  }
  lingered_ += buffer_.size();
  buffer_.consume(buffer_.size());
  if (lingered_ > kLingerLimit) {
    close();
    return;
  }
  stream_.tcp().expires_at(linger_deadline_);
  stream_.async_read_some(buffer_.prepare(kReadChunk),
                          [self = shared_from_this()](beast::error_code read_ec, std::size_t n) {
                            if (read_ec) {
                              self->close();
                              return;
                            }
                            self->buffer_.commit(n);
                            self->linger_close();
                          });
}

void Session::close() {
  if (closed_) {
    return;
  }
  closed_ = true;
  release_pending();
  if (stream_state_) {
    stream_state_->timer.cancel();
    end_subscription();
  }
  beast::error_code ec;
  stream_.tcp().socket().shutdown(tcp::socket::shutdown_both, ec);
  stream_.tcp().close();
}

void Session::reject_busy() {
  first_request_ = false;
  answer_error(503, "INTERNAL_ERROR", "too many connections; try again later");
}

void Session::shutdown() {
  const std::lock_guard lock(stream_mutex_);
  if (closed_) {
    return;
  }
  if (!stream_state_) {
    close();
    return;
  }
  auto& state = *stream_state_;
  state.ending = true;
  if (!state.writing) {
    write_stream_end();
    return;
  }
  // A part is on its way; the boundary follows it unless the client is too
  // slow to take it, in which case the connection is simply closed.
  state.timer.expires_after(kStreamEndTimeout);
  state.timer.async_wait([self = shared_from_this()](beast::error_code ec) {
    if (!ec) {
      const std::lock_guard timer_lock(self->stream_mutex_);
      self->close();
    }
  });
}

}  // namespace mtc::bridge::detail
