// The streaming half of a Session (/sample and /current with interval): a
// subscription to the agent, and parts written when new data is due, a
// heartbeat when nothing is, and the final boundary at the end.
#include "session_stream.hpp"

#include <boost/asio/post.hpp>
#include <boost/beast/core/buffers_suffix.hpp>
#include <mutex>
#include <utility>

#include "session.hpp"
#include "wire.hpp"

namespace mtc::bridge::detail {
namespace {

using Clock = std::chrono::steady_clock;

// A stream part held back by max_pending_bytes is tried again after this.
constexpr std::chrono::milliseconds kPendingRetry{50};

}  // namespace

void Session::start_stream(StreamPlan plan) {
  const std::lock_guard lock(stream_mutex_);
  stream_state_ = std::make_unique<Stream>(stream_.tcp().get_executor());
  auto& state = *stream_state_;
  state.plan = std::move(plan);
  state.boundary = make_boundary();
  if (!stream_.is_tls()) {
    // Set once, here: a direct part (another thread) only reads the flag.
    beast::error_code ec;
    stream_.tcp().socket().non_blocking(true, ec);
  }
  std::weak_ptr<Session> weak = shared_from_this();
  state.subscription = shared_->agent->subscribe([weak] {
    if (auto self = weak.lock()) {
      self->on_new_data();
    }
  });
  state.subscribed = true;
  ++shared_->streams;  // until end_subscription()

  stream_.tcp().expires_never();
  read_until_eof();  // notices a client that hangs up between parts
  write_stream_head(head_, state.boundary, shared_->options.server_name);
  write_part();  // head and first part leave together
}

// On the thread that fed the agent: the part goes from here when it can,
// else this thread only flips a flag and posts, and the io thread does it.
void Session::on_new_data() {
  if (write_part_directly()) {
    return;
  }
  if (!stream_state_->wake_pending.exchange(true)) {
    asio::post(stream_.tcp().get_executor(), [self = shared_from_this()] { self->on_wake(); });
  }
}

// True when this thread wrote the new part (or its first bytes, the rest
// then goes from the io thread). False leaves everything to the io thread:
// the stream busy (writing, a handler running, a part not yet due), TLS,
// too many streams, or a socket that takes nothing now.
bool Session::write_part_directly() {
  const auto& options = shared_->options;
  if (stream_.is_tls() || shared_->streams.load() > options.direct_stream_writes) {
    return false;
  }
  const std::unique_lock lock(stream_mutex_, std::try_to_lock);
  auto& state = *stream_state_;
  if (!lock.owns_lock() || closed_ || state.writing || state.ending || state.ended ||
      !state.plan.is_sample || shared_->agent->next_sequence() <= state.plan.next_sequence ||
      Clock::now() < state.last_part + state.plan.interval) {
    return false;
  }
  const StreamPlan before = state.plan;
  Response part = shared_->agent->next_part(state.plan);
  if (part.status != 200 || !hold_pending(part.body.size())) {
    state.plan = before;  // the io thread meets the same answer and handles it
    return false;
  }
  body_ = std::move(part.body);
  write_part_head(head_, state.boundary, part.content_type, body_.size());
  const PartBuffers buffers = part_buffers();
  const std::size_t written = write_now(buffers);
  if (written == 0) {
    state.plan = before;
    head_.clear();
    release_pending();
    return false;
  }
  ++shared_->direct_parts;
  if (written == asio::buffer_size(buffers)) {
    head_.clear();
    release_pending();
    state.last_part = Clock::now();
    return true;
  }
  state.writing = true;  // the rest under the write timeout, from the io thread
  asio::post(stream_.tcp().get_executor(), [self = shared_from_this(), written] {
    const std::lock_guard io_lock(self->stream_mutex_);
    self->write_rest(written);
  });
  return true;
}

void Session::read_until_eof() {
  auto& sink = stream_state_->sink;
  stream_.async_read_some(asio::buffer(sink),
                          [self = shared_from_this()](beast::error_code ec, std::size_t) {
                            const std::lock_guard lock(self->stream_mutex_);
                            if (ec) {
                              self->close();
                              return;
                            }
                            self->read_until_eof();
                          });
}

void Session::on_wake() {
  const std::lock_guard lock(stream_mutex_);
  stream_state_->wake_pending.store(false);
  pump();
}

// Decides when the next part is due: new data, no sooner than `interval`
// after the last part; with nothing new, a heartbeat after `heartbeat`;
// /current?interval parts come every interval regardless.
void Session::pump() {
  if (closed_ || !stream_state_) {
    return;
  }
  auto& state = *stream_state_;
  if (state.writing || state.ended) {
    return;
  }
  if (state.ending) {
    write_stream_end();
    return;
  }
  const bool has_data = shared_->agent->next_sequence() > state.plan.next_sequence;
  const bool periodic = !state.plan.is_sample && state.plan.interval.count() > 0;
  const auto wait = (has_data || periodic) ? state.plan.interval : state.plan.heartbeat;
  const auto due = state.last_part + wait;
  if (Clock::now() >= due) {
    write_part();
  } else {
    arm_timer(due);
  }
}

void Session::arm_timer(Clock::time_point due) {
  auto& state = *stream_state_;
  // A timer due no later stays: when it fires, pump() finds whether a part
  // is due and arms it again. Moving it after every part (the heartbeat's
  // due moves with each part) cost a cancel, an aborted handler and a new
  // wait per part, for every client of a busy stream.
  if (state.armed_for <= due) {
    return;
  }
  state.armed_for = due;
  state.timer.expires_at(due);
  state.timer.async_wait([self = shared_from_this()](beast::error_code ec) {
    if (ec == asio::error::operation_aborted) {
      return;
    }
    const std::lock_guard lock(self->stream_mutex_);
    self->stream_state_->armed_for = Clock::time_point::max();
    self->pump();
  });
}

void Session::write_part() {
  auto& state = *stream_state_;
  const StreamPlan before = state.plan;
  Response part = shared_->agent->next_part(state.plan);
  if (!hold_pending(part.body.size())) {
    // Too much is waiting for clients: this part waits too, from where it
    // started (the client may fall behind the buffer, then it is told).
    state.plan = before;
    arm_timer(Clock::now() + kPendingRetry);
    return;
  }
  // An error part (e.g. the client fell out of the buffer) ends the stream.
  state.stop_after_write = part.status != 200;
  body_ = std::move(part.body);
  // Appends: the first part leaves together with the stream head.
  write_part_head(head_, state.boundary, part.content_type, body_.size());

  state.writing = true;
  const PartBuffers buffers = part_buffers();
  const std::size_t written = write_now(buffers);
  if (written == asio::buffer_size(buffers)) {
    // Posted, not called: a client that keeps up with a burst must not
    // recurse through pump() once per part, and with many streams woken at
    // once every stream's send goes before any stream's bookkeeping (done
    // at once, the fan-out's p99 rose by 7 %: docs/benchmarks.md).
    asio::post(stream_.tcp().get_executor(), [self = shared_from_this()] {
      const std::lock_guard lock(self->stream_mutex_);
      self->on_part_written({}, false);
    });
    return;
  }
  write_rest(written);
}

Session::PartBuffers Session::part_buffers() const {
  return {asio::buffer(head_), asio::buffer(body_),
          asio::buffer(kPartTail.data(), kPartTail.size())};
}

// The part in head_ and body_ from byte `written` on, asynchronously under
// the write timeout.
void Session::write_rest(std::size_t written) {
  beast::buffers_suffix<PartBuffers> rest(part_buffers());
  rest.consume(written);
  stream_.tcp().expires_after(shared_->options.write_timeout);  // read side stays unbounded
  stream_.async_write(rest, [self = shared_from_this()](beast::error_code ec, std::size_t) {
    const std::lock_guard lock(self->stream_mutex_);
    self->on_part_written(ec, false);
  });
}

// Plain TCP: what the socket's buffer takes now, nearly always the whole
// part. Such a part needs no write timer armed and cancelled and no
// asynchronous operation: that machinery, per part and per client, was most
// of the io thread's time with 1,000 streams (docs/benchmarks.md). What
// is left goes asynchronously under the write timeout, as before. TLS
// always goes asynchronously (its records are not ours to split).
std::size_t Session::write_now(const PartBuffers& buffers) {
  if (stream_.is_tls()) return 0;
  auto& socket = stream_.tcp().socket();
  if (!socket.non_blocking()) return 0;  // start_stream could not set it
  beast::error_code ec;
  const std::size_t n = socket.write_some(buffers, ec);
  return ec ? 0 : n;  // the asynchronous write meets the error again and closes
}

void Session::write_stream_end() {
  auto& state = *stream_state_;
  state.ended = true;
  state.writing = true;
  state.timer.cancel();
  detail::write_stream_end(head_, state.boundary);
  stream_.tcp().expires_after(kStreamEndTimeout);
  stream_.async_write(asio::buffer(head_),
                      [self = shared_from_this()](beast::error_code ec, std::size_t) {
                        const std::lock_guard lock(self->stream_mutex_);
                        self->on_part_written(ec, true);
                      });
}

void Session::on_part_written(beast::error_code ec, bool last) {
  release_pending();
  auto& state = *stream_state_;
  state.writing = false;
  head_.clear();
  if (ec || last) {
    close();
    return;
  }
  if (state.stop_after_write) {
    write_stream_end();
    return;
  }
  state.last_part = Clock::now();
  pump();
}

}  // namespace mtc::bridge::detail
