// One client connection's byte stream: plain TCP, or TLS over it when the
// server has a certificate (ServerOptions::tls_certificate_file). The
// session's code is the same either way; timeouts, shutdown and close always
// act on the TCP layer underneath.
#pragma once

#include <boost/asio/ssl/context.hpp>
#include <boost/asio/write.hpp>
#include <boost/beast/core/tcp_stream.hpp>
#include <boost/beast/http/read.hpp>
#include <boost/beast/ssl/ssl_stream.hpp>
#include <memory>
#include <string>
#include <utility>
#include <variant>

namespace mtc::bridge::detail {

namespace asio = boost::asio;
namespace beast = boost::beast;

class Connection {
 public:
  using Tls = beast::ssl_stream<beast::tcp_stream>;

  // `tls` null: plain HTTP. Otherwise it must outlive the connection.
  Connection(asio::ip::tcp::socket socket, asio::ssl::context* tls)
      : stream_(make(std::move(socket), tls)) {}

  bool is_tls() const noexcept { return std::holds_alternative<Tls>(stream_); }

  // The TCP layer: timeouts, socket options, shutdown, close, executor.
  // get_if, not std::visit: visit throws on a valueless variant, which
  // stream_ never is (set once, by the constructor).
  beast::tcp_stream& tcp() noexcept {
    if (auto* tls = std::get_if<Tls>(&stream_)) return beast::get_lowest_layer(*tls);
    return *std::get_if<beast::tcp_stream>(&stream_);
  }

  // The TLS server handshake (call only when is_tls()).
  template <typename Handler>
  void async_handshake(Handler&& handler) {
    std::get<Tls>(stream_).async_handshake(asio::ssl::stream_base::server,
                                           std::forward<Handler>(handler));
  }

  template <typename Buffers, typename Handler>
  void async_read_some(const Buffers& buffers, Handler&& handler) {
    std::visit([&](auto& s) { s.async_read_some(buffers, std::forward<Handler>(handler)); },
               stream_);
  }

  template <typename Buffers, typename Handler>
  void async_write(const Buffers& buffers, Handler&& handler) {
    std::visit([&](auto& s) { asio::async_write(s, buffers, std::forward<Handler>(handler)); },
               stream_);
  }

  template <typename Parser, typename Handler>
  void async_read_header(beast::flat_buffer& buffer, Parser& parser, Handler&& handler) {
    std::visit(
        [&](auto& s) {
          beast::http::async_read_header(s, buffer, parser, std::forward<Handler>(handler));
        },
        stream_);
  }

 private:
  static std::variant<beast::tcp_stream, Tls> make(asio::ip::tcp::socket socket,
                                                   asio::ssl::context* tls) {
    if (tls == nullptr) {
      return std::variant<beast::tcp_stream, Tls>(std::in_place_type<beast::tcp_stream>,
                                                  std::move(socket));
    }
    return std::variant<beast::tcp_stream, Tls>(std::in_place_type<Tls>, std::move(socket), *tls);
  }

  std::variant<beast::tcp_stream, Tls> stream_;
};

// The server's TLS context from PEM files; throws std::invalid_argument
// naming the file that cannot be used.
std::unique_ptr<asio::ssl::context> make_tls_context(const std::string& certificate_file,
                                                     const std::string& private_key_file);

}  // namespace mtc::bridge::detail
