// Opening a listening TCP socket the way every front of the bridge does (the
// HTTP server, the SHDR adapter): one place for the address check, the
// SO_REUSEADDR choice and errors that say what failed on which address.
#pragma once

#include <boost/asio/ip/tcp.hpp>
#include <cstdint>
#include <string>

namespace mtc::bridge {

// Opens, binds and listens `acceptor` on bind_address:port (0 = any free
// port) and returns the port it listens on. Throws std::system_error naming
// the step and the address; `whose` (e.g. "SHDR", empty for HTTP) tells an
// operator which of the bridge's listeners it was.
std::uint16_t listen_on(boost::asio::ip::tcp::acceptor& acceptor, const std::string& bind_address,
                        std::uint16_t port, const std::string& whose = {});

}  // namespace mtc::bridge
