// mtc-bridge as an SHDR adapter, end to end: a device publishes on DDS, the
// test plays the MTConnect agent on the bridge's SHDR port and sees the
// initial state, a DDS transition as a line, PING/PONG, and the device's
// comms loss as UNAVAILABLE. DDS domain 83 (see CMakeLists.txt).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "child_process.hpp"
#include "line_client.hpp"
#include "mtc/dds/equipment.hpp"

namespace mtc::bridge::test {
namespace {

using namespace std::chrono_literals;

using ShdrClient = mtc::test::LineClient;  // the agent's end of an SHDR connection

TEST(BridgeShdr, AnAgentOnTheShdrPortFollowsADdsDevice) {
  mtc::test::ChildProcess bridge({MTC_BRIDGE_EXE, "--domain-ids", "83", "--heartbeat-ms", "100",
                                  "--port", "0", "--shdr-port", "0", "--transport", "loopback"});
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
