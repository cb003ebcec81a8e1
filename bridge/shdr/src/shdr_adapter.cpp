// ShdrAdapter: one io thread, every connection handled on it (no strands).
// The agent's new-data callback (ingest thread) only posts a pump.
#include "mtc/bridge/shdr_adapter.hpp"

#include <atomic>
#include <boost/asio/buffer.hpp>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/read_until.hpp>
#include <boost/asio/streambuf.hpp>
#include <boost/asio/write.hpp>
#include <mutex>
#include <optional>
#include <set>
#include <stdexcept>
#include <system_error>
#include <thread>

#include "mtc/bridge/tcp_listen.hpp"

namespace mtc::bridge {

namespace asio = boost::asio;
using asio::ip::tcp;

namespace {

constexpr std::size_t kMaxLineBytes = 4096;  // what an agent sends: PINGs

struct Connection {
  explicit Connection(tcp::socket s) : socket(std::move(s)), input(kMaxLineBytes) {}
  tcp::socket socket;
  asio::streambuf input;
  std::string output;  // the write in flight
  std::uint64_t next = 0;
  bool writing = false;
  bool pong_due = false;
  bool closed = false;
};

}  // namespace

struct ShdrAdapter::Impl {
  Impl(std::shared_ptr<MtconnectAgent> a, ShdrOptions o)
      : agent(std::move(a)), options(std::move(o)), acceptor(ioc) {
    if (!agent) throw std::invalid_argument("ShdrAdapter: no agent");
    if (options.batch == 0) options.batch = 1;
  }

  void listen();
  void accept();
  void on_accept(tcp::socket socket);
  void read(const std::shared_ptr<Connection>& c);
  void on_line(const std::shared_ptr<Connection>& c, std::size_t bytes);
  void pump_all();
  void pump(const std::shared_ptr<Connection>& c);
  void write(const std::shared_ptr<Connection>& c);
  void close(const std::shared_ptr<Connection>& c, bool fell_behind = false);

  std::shared_ptr<MtconnectAgent> agent;
  ShdrOptions options;
  asio::io_context ioc{1};
  tcp::acceptor acceptor;
  std::optional<asio::executor_work_guard<asio::io_context::executor_type>> work;
  std::thread thread;
  std::set<std::shared_ptr<Connection>> connections;  // io thread only
  std::atomic<bool> pump_posted{false};
  std::uint64_t subscription = 0;
  std::uint16_t port = 0;
  bool started = false;
  bool stopped = false;
  mutable std::mutex stats_mutex;
  ShdrStats stats;
  std::size_t open = 0;  // under stats_mutex
};

void ShdrAdapter::Impl::listen() {
  port = listen_on(acceptor, options.bind_address, options.port, "SHDR");
}

void ShdrAdapter::Impl::accept() {
  acceptor.async_accept([this](const boost::system::error_code& ec, tcp::socket socket) {
    if (ec == asio::error::operation_aborted || stopped) return;
    if (!ec) on_accept(std::move(socket));
    accept();
  });
}

void ShdrAdapter::Impl::on_accept(tcp::socket socket) {
  if (connections.size() >= options.max_connections) {
    boost::system::error_code ignored;
    socket.close(ignored);
    return;
  }
  auto c = std::make_shared<Connection>(std::move(socket));
  boost::system::error_code ignored;
  c->socket.set_option(tcp::no_delay(true), ignored);
  connections.insert(c);
  {
    std::lock_guard lock(stats_mutex);
    ++stats.connections;
    open = connections.size();
  }
  // The full current state first, then changes from where it ends.
  for (const ItemObservation& o : agent->latest_observations(c->next)) c->output += shdr_line(o);
  write(c);
  read(c);
}

void ShdrAdapter::Impl::read(const std::shared_ptr<Connection>& c) {
  asio::async_read_until(c->socket, c->input, '\n',
                         [this, c](const boost::system::error_code& ec, std::size_t bytes) {
                           if (ec) {
                             close(c);  // EOF, reset, or a line over kMaxLineBytes
                             return;
                           }
                           on_line(c, bytes);
                         });
}

void ShdrAdapter::Impl::on_line(const std::shared_ptr<Connection>& c, std::size_t bytes) {
  std::string line(asio::buffers_begin(c->input.data()),
                   asio::buffers_begin(c->input.data()) + static_cast<std::ptrdiff_t>(bytes));
  c->input.consume(bytes);
  if (line.rfind("* PING", 0) == 0) {
    c->pong_due = true;
    pump(c);
  }
  read(c);
}

void ShdrAdapter::Impl::pump_all() {
  pump_posted = false;
  const std::vector<std::shared_ptr<Connection>> all(connections.begin(), connections.end());
  for (const auto& c : all) pump(c);
}

void ShdrAdapter::Impl::pump(const std::shared_ptr<Connection>& c) {
  if (c->closed) return;
  if (c->writing) {
    // The write's completion pumps again; meanwhile, a reader that stopped
    // reading is dropped once the buffer has overwritten its place.
    std::vector<ItemObservation> none;
    std::uint64_t ignored = 0;
    if (!agent->observations_since(c->next, 0, none, ignored)) close(c, true);
    return;
  }
  if (c->pong_due) {
    c->output += "* PONG " + std::to_string(options.heartbeat.count()) + "\n";
    c->pong_due = false;
    std::lock_guard lock(stats_mutex);
    ++stats.pongs;
  }
  std::vector<ItemObservation> changes;
  if (!agent->observations_since(c->next, options.batch, changes, c->next)) {
    close(c, true);  // fell behind the buffer: the agent reconnects for a fresh state
    return;
  }
  for (const ItemObservation& o : changes) c->output += shdr_line(o);
  {
    std::lock_guard lock(stats_mutex);
    stats.lines += changes.size();
  }
  if (!c->output.empty()) write(c);
}

void ShdrAdapter::Impl::write(const std::shared_ptr<Connection>& c) {
  if (c->output.empty() || c->closed) return;
  c->writing = true;
  asio::async_write(c->socket, asio::buffer(c->output),
                    [this, c](const boost::system::error_code& ec, std::size_t) {
                      c->writing = false;
                      c->output.clear();
                      if (ec) {
                        close(c);
                        return;
                      }
                      pump(c);
                    });
}

void ShdrAdapter::Impl::close(const std::shared_ptr<Connection>& c, bool fell_behind) {
  if (c->closed) return;
  c->closed = true;
  boost::system::error_code ignored;
  c->socket.shutdown(tcp::socket::shutdown_both, ignored);
  c->socket.close(ignored);
  connections.erase(c);
  std::lock_guard lock(stats_mutex);
  if (fell_behind) ++stats.dropped;
  open = connections.size();
}

ShdrAdapter::ShdrAdapter(std::shared_ptr<MtconnectAgent> agent, ShdrOptions options)
    : impl_(std::make_unique<Impl>(std::move(agent), std::move(options))) {
  impl_->listen();
}

ShdrAdapter::~ShdrAdapter() {
  stop();
}

void ShdrAdapter::start() {
  Impl& s = *impl_;
  if (s.started) return;
  s.started = true;
  s.work.emplace(s.ioc.get_executor());
  s.accept();
  s.subscription = s.agent->subscribe([impl = impl_.get()] {
    // Ingest thread: one pump at a time is enough, it reads up to now.
    if (!impl->pump_posted.exchange(true)) asio::post(impl->ioc, [impl] { impl->pump_all(); });
  });
  s.thread = std::thread([&s] { s.ioc.run(); });
}

void ShdrAdapter::stop() {
  Impl& s = *impl_;
  if (s.stopped) return;
  if (s.subscription != 0) s.agent->unsubscribe(s.subscription);
  if (!s.started) {
    s.stopped = true;
    return;
  }
  asio::post(s.ioc, [&s] {
    s.stopped = true;
    boost::system::error_code ignored;
    s.acceptor.close(ignored);
    const std::vector<std::shared_ptr<Connection>> all(s.connections.begin(), s.connections.end());
    for (const auto& c : all) s.close(c);
  });
  s.work.reset();
  s.thread.join();
  s.stopped = true;
}

std::uint16_t ShdrAdapter::port() const noexcept {
  return impl_->port;
}

const std::string& ShdrAdapter::bind_address() const noexcept {
  return impl_->options.bind_address;
}

std::size_t ShdrAdapter::connection_count() const {
  std::lock_guard lock(impl_->stats_mutex);
  return impl_->open;
}

ShdrStats ShdrAdapter::stats() const {
  std::lock_guard lock(impl_->stats_mutex);
  return impl_->stats;
}

}  // namespace mtc::bridge
