// HTTPS (issue 11): with a certificate and key the server speaks TLS; a
// client that verifies the certificate against it gets the agent's answers,
// one that trusts another CA refuses the server, a plain HTTP client gets
// nothing, and unusable files are refused naming them. Certificates come
// from the openssl command in a temporary directory.
#include <gtest/gtest.h>

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl.hpp>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "server_fixture.hpp"

namespace mtc::bridge::test {
namespace {

namespace asio = boost::asio;
namespace ssl = boost::asio::ssl;
namespace fs = std::filesystem;

// A self-signed certificate for 127.0.0.1 (its own CA) and an unrelated CA.
class Certificates {
 public:
  Certificates() {
    char pattern[] = "/tmp/mtc-https-XXXXXX";
    const char* made = ::mkdtemp(pattern);
    if (made == nullptr) throw std::runtime_error("mkdtemp failed");
    dir_ = made;
    self_signed("server", "/CN=127.0.0.1", "subjectAltName=IP:127.0.0.1");
    self_signed("other", "/CN=another CA", "basicConstraints=critical,CA:TRUE");
  }
  ~Certificates() {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }
  Certificates(const Certificates&) = delete;  // owns the directory
  Certificates& operator=(const Certificates&) = delete;
  std::string cert(const std::string& name) const { return dir_ + "/" + name + "_cert.pem"; }
  std::string key(const std::string& name) const { return dir_ + "/" + name + "_key.pem"; }
  const std::string& dir() const { return dir_; }

 private:
  void self_signed(const std::string& name, const std::string& subject,
                   const std::string& extension) {
    const std::string command =
        "openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -days 2 "
        "-keyout '" +
        key(name) + "' -out '" + cert(name) + "' -subj '" + subject + "' -addext '" + extension +
        "' 2>/dev/null";
    // Test bodies run on one thread; nothing else touches the environment.
    if (std::system(command.c_str()) != 0) {  // NOLINT(concurrency-mt-unsafe)
      throw std::runtime_error("openssl failed: " + command);
    }
  }
  std::string dir_;
};

const Certificates& certificates() {
  static const Certificates certs;
  return certs;
}

ServerOptions https_options() {
  ServerOptions options = test_options();
  options.tls_certificate_file = certificates().cert("server");
  options.tls_private_key_file = certificates().key("server");
  return options;
}

// One GET over TLS from a client that trusts `ca_file` and checks that the
// certificate names 127.0.0.1. Returns the raw answer; throws
// boost::system::system_error when the handshake is refused.
std::string https_get(std::uint16_t port, const std::string& ca_file, const std::string& target) {
  asio::io_context io;
  ssl::context context(ssl::context::tls_client);
  context.load_verify_file(ca_file);
  ssl::stream<asio::ip::tcp::socket> stream(io, context);
  stream.set_verify_mode(ssl::verify_peer);
  stream.set_verify_callback(ssl::host_name_verification("127.0.0.1"));
  stream.lowest_layer().connect({asio::ip::make_address("127.0.0.1"), port});
  stream.handshake(ssl::stream_base::client);
  const std::string request =
      "GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n";
  asio::write(stream, asio::buffer(request));
  std::string answer;
  char chunk[4096];
  boost::system::error_code ec;
  while (!ec) {
    const std::size_t n = stream.read_some(asio::buffer(chunk), ec);
    answer.append(chunk, n);
  }
  return answer;
}

class Https : public ServerTest {
 protected:
  void SetUp() override { start(https_options()); }
};

TEST_F(Https, AClientThatVerifiesTheCertificateGetsTheAgentsAnswer) {
  EXPECT_TRUE(server_->is_https());
  const std::string answer = https_get(port(), certificates().cert("server"), "/probe");
  EXPECT_EQ(answer.rfind("HTTP/1.1 200", 0), 0u) << answer;
  EXPECT_NE(answer.find("<MTConnectDevices>"), std::string::npos) << answer;
}

TEST_F(Https, AClientThatTrustsAnotherCaRefusesTheServer) {
  try {
    https_get(port(), certificates().cert("other"), "/probe");
    FAIL() << "the handshake succeeded with a certificate of an untrusted CA";
  } catch (const boost::system::system_error& e) {
    EXPECT_NE(std::string(e.what()).find("certificate verify failed"), std::string::npos)
        << e.what();
  }
  // The server goes on serving those that trust it.
  EXPECT_EQ(https_get(port(), certificates().cert("server"), "/probe").rfind("HTTP/1.1 200", 0),
            0u);
}

TEST_F(Https, APlainHttpClientGetsNoAnswer) {
  RawClient client(port());
  client.send(get_request("/probe"));
  EXPECT_FALSE(client.read_response());
}

TEST(HttpsFiles, UnusableFilesAreRefusedNamingThem) {
  auto agent = std::make_shared<FakeAgent>();
  ServerOptions missing_key = https_options();
  missing_key.tls_private_key_file = certificates().dir() + "/none.pem";
  try {
    HttpServer server(agent, missing_key);
    FAIL() << "a missing key was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(missing_key.tls_private_key_file), std::string::npos)
        << e.what();
  }
  ServerOptions wrong_key = https_options();
  wrong_key.tls_private_key_file = certificates().key("other");
  EXPECT_THROW((HttpServer{agent, wrong_key}), std::invalid_argument);
  ServerOptions only_cert = test_options();
  only_cert.tls_certificate_file = certificates().cert("server");
  EXPECT_THROW((HttpServer{agent, only_cert}), std::invalid_argument);
}

}  // namespace
}  // namespace mtc::bridge::test
