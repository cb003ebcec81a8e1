// The bridge's HTTPS context: TLS 1.2 or later, the certificate chain and
// key from PEM files, checked to belong together before any client comes.
#include <boost/asio/ssl/context.hpp>
#include <stdexcept>

#include "connection.hpp"

namespace mtc::bridge::detail {

std::unique_ptr<asio::ssl::context> make_tls_context(const std::string& certificate_file,
                                                     const std::string& private_key_file) {
  auto context = std::make_unique<asio::ssl::context>(asio::ssl::context::tls_server);
  context->set_options(asio::ssl::context::default_workarounds | asio::ssl::context::no_sslv2 |
                       asio::ssl::context::no_sslv3 | asio::ssl::context::no_tlsv1 |
                       asio::ssl::context::no_tlsv1_1 | asio::ssl::context::single_dh_use);
  boost::system::error_code ec;
  context->use_certificate_chain_file(certificate_file, ec);
  if (ec) {
    throw std::invalid_argument(certificate_file + ": not a usable PEM certificate chain (" +
                                ec.message() + ")");
  }
  context->use_private_key_file(private_key_file, asio::ssl::context::pem, ec);
  if (ec) {
    throw std::invalid_argument(private_key_file +
                                ": not a usable PEM private key, or not the key of " +
                                certificate_file + " (" + ec.message() + ")");
  }
  return context;
}

}  // namespace mtc::bridge::detail
