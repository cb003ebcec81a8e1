// Links mtc::bridge_server alone: the HTTP front binds a free loopback port
// for an Agent (here one that serves nothing), starts and stops.
#include <iostream>
#include <memory>

#include "mtc/bridge/http_server.hpp"

namespace {

class NoAgent final : public mtc::bridge::Agent {
 public:
  mtc::bridge::Routed route(const mtc::bridge::Request&) noexcept override {
    return {error_document(404, "INVALID_URI", "nothing here"), std::nullopt};
  }
  mtc::bridge::Response next_part(mtc::bridge::StreamPlan&) noexcept override { return {}; }
  mtc::bridge::Response error_document(int status, std::string_view,
                                       std::string_view message) noexcept override {
    return {status, "text/plain", std::string(message)};
  }
  std::uint64_t next_sequence() const noexcept override { return 1; }
  bool wait_for(std::uint64_t, std::chrono::milliseconds) const override { return false; }
  std::uint64_t subscribe(std::function<void()>) override { return 1; }
  void unsubscribe(std::uint64_t) override {}
};

}  // namespace

int main() {
  mtc::bridge::ServerOptions options;
  options.port = 0;  // any free port on 127.0.0.1
  mtc::bridge::HttpServer server(std::make_shared<NoAgent>(), options);
  server.start();
  const auto port = server.port();
  server.stop();
  std::cout << "mtc::bridge_server: listened on port " << port << "\n";
  return port != 0 ? 0 : 1;
}
