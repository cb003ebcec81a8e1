// A started HttpServer on a free loopback port in front of a FakeAgent.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <pugixml.hpp>
#include <thread>

#include "fake_agent.hpp"
#include "mtc/bridge/http_server.hpp"
#include "raw_client.hpp"

namespace mtc::bridge::test {

inline ServerOptions test_options() {
  ServerOptions options;
  options.port = 0;
  options.io_threads = 2;
  return options;
}

// Polls `condition` until it holds or `timeout` passes (for state that has
// no event to wait on, such as the server's connection count).
template <typename Condition>
bool eventually(Condition condition, std::chrono::milliseconds timeout = 5s) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!condition()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(5ms);
  }
  return true;
}

inline pugi::xml_document parse_xml(const std::string& text) {
  pugi::xml_document doc;
  const auto result = doc.load_string(text.c_str());
  EXPECT_TRUE(result) << result.description() << " in: " << text;
  return doc;
}

class ServerTest : public ::testing::Test {
 protected:
  void start(ServerOptions options = test_options()) {
    server_ = std::make_unique<HttpServer>(agent_, std::move(options));
    server_->start();
  }
  void SetUp() override { start(); }
  void TearDown() override {
    if (server_) server_->stop();
  }
  void restart(ServerOptions options) {
    server_->stop();
    start(std::move(options));
  }

  std::uint16_t port() const { return server_->port(); }

  // One GET on a fresh connection.
  HttpResponse get(const std::string& target) {
    RawClient client(port());
    client.send(get_request(target));
    auto response = client.read_response();
    EXPECT_TRUE(response) << "no response to " << target;
    return response ? *response : HttpResponse{};
  }

  std::shared_ptr<FakeAgent> agent_ = std::make_shared<FakeAgent>();
  std::unique_ptr<HttpServer> server_;
};

}  // namespace mtc::bridge::test
