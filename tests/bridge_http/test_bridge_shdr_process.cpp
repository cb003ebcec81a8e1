// mtc-bridge as an SHDR adapter, end to end: a device publishes on DDS, the
// test plays the MTConnect agent on the bridge's SHDR port and sees the
// initial state, a DDS transition as a line, PING/PONG, and the device's
// comms loss as UNAVAILABLE. DDS domain 83 (see CMakeLists.txt).
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "child_process.hpp"
#include "mtc/dds/equipment.hpp"

namespace mtc::bridge::test {
namespace {

using namespace std::chrono_literals;

// The agent's end of an SHDR connection.
class ShdrClient {
 public:
  explicit ShdrClient(std::uint16_t port) {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(port);
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    connected_ = ::connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0;
  }
  ~ShdrClient() { ::close(fd_); }
  bool connected() const { return connected_; }
  void send(const std::string& text) const {
    EXPECT_EQ(::send(fd_, text.data(), text.size(), MSG_NOSIGNAL),
              static_cast<ssize_t>(text.size()));
  }
  // The first line containing `text` within `timeout`.
  std::optional<std::string> line_with(const std::string& text, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      for (auto nl = buffer_.find('\n'); nl != std::string::npos; nl = buffer_.find('\n')) {
        std::string line = buffer_.substr(0, nl);
        buffer_.erase(0, nl + 1);
        if (line.find(text) != std::string::npos) return line;
      }
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
          deadline - std::chrono::steady_clock::now());
      pollfd p{fd_, POLLIN, 0};
      if (left.count() <= 0 || ::poll(&p, 1, static_cast<int>(left.count())) <= 0) {
        return std::nullopt;
      }
      char chunk[8192];
      const ssize_t n = ::recv(fd_, chunk, sizeof chunk, 0);
      if (n <= 0) return std::nullopt;
      buffer_.append(chunk, static_cast<std::size_t>(n));
    }
  }

 private:
  int fd_ = -1;
  bool connected_ = false;
  std::string buffer_;
};

TEST(BridgeShdr, AnAgentOnTheShdrPortFollowsADdsDevice) {
  mtc::test::ChildProcess bridge({MTC_BRIDGE_EXE, "--domain-ids", "83", "--heartbeat-ms", "100",
                                  "--port", "0", "--shdr-port", "0"});
  const auto line = bridge.wait_for_line({"SHDR adapter"}, 20s);
  ASSERT_TRUE(line) << bridge.stderr_text();
  EXPECT_NE(line->find("on 127.0.0.1:"), std::string::npos) << *line;  // loopback by default
  const auto port = static_cast<std::uint16_t>(std::stoi(line->substr(line->rfind(':') + 1)));

  dds::EquipmentOptions options;
  options.domain_id = 83;
  options.device_uuid = "shdr-robot";
  options.transport = qos::Transport::LoopbackTest;
  options.faults.outage = std::make_shared<std::atomic<bool>>(false);
  dds::Equipment robot(options);
  robot.add_interface({"mh1", core::InterfaceType::MaterialHandler, "", {}});
  auto& load = robot.add_responder("mh1", core::Service::MaterialLoad, dds::ResponderCallbacks{});
  robot.start();

  ShdrClient agent(port);
  ASSERT_TRUE(agent.connected());
  const std::string item = "|mh1_material_load_response|";
  EXPECT_TRUE(agent.line_with(item + "READY", 15s));
  agent.send("* PING\n");
  EXPECT_TRUE(agent.line_with("* PONG ", 5s));
  load.set_ready(false).get();
  EXPECT_TRUE(agent.line_with(item + "NOT_READY", 10s));
  options.faults.outage->store(true);  // the cable is pulled
  EXPECT_TRUE(agent.line_with(item + "UNAVAILABLE", 10s));
}

}  // namespace
}  // namespace mtc::bridge::test
