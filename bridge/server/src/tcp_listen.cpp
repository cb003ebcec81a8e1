#include "mtc/bridge/tcp_listen.hpp"

#include <system_error>

namespace mtc::bridge {

std::uint16_t listen_on(boost::asio::ip::tcp::acceptor& acceptor, const std::string& bind_address,
                        std::uint16_t port, const std::string& whose) {
  namespace asio = boost::asio;
  boost::system::error_code ec;
  const auto address = asio::ip::make_address(bind_address, ec);
  if (ec) {
    const std::string prefix = whose.empty() ? "" : whose + " ";
    throw std::system_error(ec, "invalid " + prefix + "bind address '" + bind_address + "'");
  }
  const asio::ip::tcp::endpoint endpoint(address, port);
  auto check = [&](const char* what) {
    if (ec) {
      const std::string suffix = whose.empty() ? "" : " (" + whose + ")";
      throw std::system_error(
          ec, std::string(what) + " " + bind_address + ":" + std::to_string(port) + suffix);
    }
  };
  acceptor.open(endpoint.protocol(), ec);
  check("cannot open a socket for");
  acceptor.set_option(asio::socket_base::reuse_address(true), ec);
  check("cannot set SO_REUSEADDR on");
  acceptor.bind(endpoint, ec);
  check("cannot bind");
  acceptor.listen(asio::socket_base::max_listen_connections, ec);
  check("cannot listen on");
  return acceptor.local_endpoint().port();
}

}  // namespace mtc::bridge
