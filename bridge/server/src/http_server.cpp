#include "mtc/bridge/http_server.hpp"

#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <system_error>
#include <thread>
#include <vector>

#include "mtc/bridge/tcp_listen.hpp"
#include "session.hpp"

namespace mtc::bridge {

using detail::asio::ip::tcp;
namespace asio = detail::asio;

struct HttpServer::Impl {
  Impl(std::shared_ptr<Agent> agent, ServerOptions options)
      : ioc(static_cast<int>(options.io_threads == 0 ? 1 : options.io_threads)),
        accept_strand(asio::make_strand(ioc)),
        acceptor(accept_strand),
        retry_timer(accept_strand),
        shared(std::make_shared<detail::ServerShared>()) {
    if (!agent) {
      throw std::invalid_argument("HttpServer: no agent");
    }
    if (options.io_threads == 0) {
      options.io_threads = 1;
    }
    const bool has_cert = !options.tls_certificate_file.empty();
    if (has_cert != !options.tls_private_key_file.empty()) {
      throw std::invalid_argument("HTTPS needs both a certificate and its private key (only the " +
                                  std::string(has_cert ? "certificate" : "private key") +
                                  " is given)");
    }
    if (has_cert) {
      shared->tls =
          detail::make_tls_context(options.tls_certificate_file, options.tls_private_key_file);
    }
    shared->agent = std::move(agent);
    shared->options = std::move(options);
  }

  // What becomes of a new connection: admitted or not, and the waiting
  // connection closed to make room for it.
  struct Admission {
    bool admit = true;
    std::shared_ptr<detail::Session> evict;
  };

  void listen();
  void accept();
  void on_accept(const boost::system::error_code& ec, tcp::socket socket);
  // Caller holds shared->mutex. Sessions it looks at are kept in `keep`,
  // to be released after the mutex (a last reference would destroy a
  // session, whose destructor takes the mutex).
  Admission admit(const std::string& remote,
                  std::vector<std::shared_ptr<detail::Session>>& keep) const;

  asio::io_context ioc;
  // The acceptor and its retry timer are not thread-safe: every operation on
  // them (accept, retry, close at stop) runs on this one strand, while the
  // io threads serve connections (TSan saw stop()'s close race an accept).
  asio::strand<asio::io_context::executor_type> accept_strand;
  tcp::acceptor acceptor;
  asio::steady_timer retry_timer;  // backs off after accept errors (EMFILE)
  std::shared_ptr<detail::ServerShared> shared;
  std::optional<asio::executor_work_guard<asio::io_context::executor_type>> work;
  std::vector<std::thread> threads;
  std::uint16_t port = 0;
  bool started = false;
  bool stopped = false;
};

void HttpServer::Impl::listen() {
  const auto& options = shared->options;
  port = listen_on(acceptor, options.bind_address, options.port);
}

void HttpServer::Impl::accept() {
  auto on_accepted = [this](const boost::system::error_code& ec, tcp::socket socket) {
    on_accept(ec, std::move(socket));
  };
  // Each connection gets its own strand: its handlers never run
  // concurrently, while different connections use every io thread. One io
  // thread runs handlers one at a time anyway; a strand would only add a
  // lock and a queue to each of them.
  if (shared->options.io_threads == 1) {
    acceptor.async_accept(ioc, std::move(on_accepted));
  } else {
    acceptor.async_accept(asio::make_strand(ioc), std::move(on_accepted));
  }
}

void HttpServer::Impl::on_accept(const boost::system::error_code& ec, tcp::socket socket) {
  if (ec == asio::error::operation_aborted || shared->stopping) {
    return;
  }
  if (ec) {
    // Out of descriptors or a connection reset before accept: wait a bit
    // instead of spinning, then keep serving.
    retry_timer.expires_after(std::chrono::milliseconds(50));
    retry_timer.async_wait([this](const boost::system::error_code& wait_ec) {
      if (!wait_ec && !shared->stopping) {
        accept();
      }
    });
    return;
  }
  boost::system::error_code endpoint_ec;
  const auto endpoint = socket.remote_endpoint(endpoint_ec);
  const std::string remote = endpoint_ec ? std::string() : endpoint.address().to_string();
  std::vector<std::shared_ptr<detail::Session>> keep;  // released after the lock
  std::shared_ptr<detail::Session> session;
  Admission admission;
  {
    std::lock_guard<std::mutex> lock(shared->mutex);
    admission = admit(remote, keep);
    if (admission.evict) shared->sessions.erase(admission.evict->id());
    if (!admission.admit && shared->rejecting >= shared->options.max_connections) {
      // Thousands at once: not even a 503 each. The socket closes here.
      accept();
      return;
    }
    if (!admission.admit) ++shared->rejecting;
    const std::uint64_t id = admission.admit ? shared->next_id++ : 0;
    session = std::make_shared<detail::Session>(std::move(socket), shared, id, remote);
    if (admission.admit) {
      shared->sessions.emplace(id, session);
    }
  }
  if (admission.evict) {
    asio::post(admission.evict->executor(), [evicted = admission.evict] { evicted->evict(); });
  }
  const bool busy = !admission.admit;
  // Start on the connection's strand, not the acceptor's thread.
  auto executor = session->executor();
  asio::post(executor, [session, busy] {
    if (busy) {
      session->reject_busy();
    } else {
      session->start();
    }
  });
  accept();
}

HttpServer::Impl::Admission HttpServer::Impl::admit(
    const std::string& remote, std::vector<std::shared_ptr<detail::Session>>& keep) const {
  const auto& options = shared->options;
  std::size_t from_client = 0;
  std::shared_ptr<detail::Session> oldest;            // waiting longest
  std::shared_ptr<detail::Session> oldest_of_client;  // of those from `remote`
  for (const auto& entry : shared->sessions) {
    auto session = entry.second.lock();
    if (!session) continue;
    const bool same_client = session->remote() == remote;
    from_client += same_client ? 1 : 0;
    const std::int64_t since = session->waiting_since();
    if (since != 0 && (!oldest || since < oldest->waiting_since())) oldest = session;
    if (since != 0 && same_client &&
        (!oldest_of_client || since < oldest_of_client->waiting_since())) {
      oldest_of_client = session;
    }
    keep.push_back(std::move(session));
  }
  if (from_client >= options.max_connections_per_client) {
    return {oldest_of_client != nullptr, oldest_of_client};
  }
  if (shared->sessions.size() >= options.max_connections) return {oldest != nullptr, oldest};
  return {};
}

HttpServer::HttpServer(std::shared_ptr<Agent> agent, ServerOptions options)
    : impl_(std::make_unique<Impl>(std::move(agent), std::move(options))) {
  impl_->listen();
}

HttpServer::~HttpServer() {
  // stop() posts to the acceptor's strand and the sessions' executors,
  // which allocate; a destructor must not throw, so a failure there is
  // reported and the rest of the teardown goes on.
  try {
    stop();
  } catch (const std::exception& e) {
    std::cerr << "mtc::bridge::HttpServer: stop failed: " << e.what() << '\n';
  } catch (...) {
    std::cerr << "mtc::bridge::HttpServer: stop failed\n";
  }
}

void HttpServer::start() {
  if (impl_->started) {
    return;
  }
  impl_->started = true;
  impl_->work.emplace(impl_->ioc.get_executor());
  impl_->accept();
  for (unsigned i = 0; i < impl_->shared->options.io_threads; ++i) {
    impl_->threads.emplace_back([this] { impl_->ioc.run(); });
  }
}

void HttpServer::stop() {
  if (!impl_ || impl_->stopped) {
    return;
  }
  impl_->stopped = true;
  auto& shared = *impl_->shared;
  shared.stopping = true;
  asio::post(impl_->accept_strand, [impl = impl_.get()] {
    boost::system::error_code ec;
    impl->acceptor.close(ec);
    impl->retry_timer.cancel();
  });
  std::vector<std::shared_ptr<detail::Session>> open;
  {
    std::lock_guard<std::mutex> lock(shared.mutex);
    for (auto& entry : shared.sessions) {
      if (auto session = entry.second.lock()) {
        open.push_back(std::move(session));
      }
    }
  }
  for (auto& session : open) {
    asio::post(session->executor(), [session] { session->shutdown(); });
  }
  open.clear();
  // Sessions finish their last writes (bounded by timeouts); then run()
  // returns because no work is left.
  impl_->work.reset();
  for (auto& thread : impl_->threads) {
    thread.join();
  }
  impl_->threads.clear();
  if (!impl_->started) {
    boost::system::error_code ec;
    impl_->acceptor.close(ec);
  }
}

std::uint16_t HttpServer::port() const noexcept {
  return impl_->port;
}

const std::string& HttpServer::bind_address() const noexcept {
  return impl_->shared->options.bind_address;
}

bool HttpServer::is_https() const noexcept {
  return impl_->shared->tls != nullptr;
}

std::size_t HttpServer::pending_bytes() const noexcept {
  return impl_->shared->pending_bytes.load();
}

std::uint64_t HttpServer::direct_stream_parts() const noexcept {
  return impl_->shared->direct_parts.load();
}

std::size_t HttpServer::connection_count() const noexcept {
  std::lock_guard<std::mutex> lock(impl_->shared->mutex);
  return impl_->shared->sessions.size();
}

}  // namespace mtc::bridge
