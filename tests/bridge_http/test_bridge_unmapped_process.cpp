// mtc-bridge with a Devices file: a DDS value that no DataItem of the file
// takes is named once in the bridge's log (stderr), however often it
// changes. DDS domain 84 (see CMakeLists.txt).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <memory>
#include <string>

#include "child_process.hpp"
#include "mtc/dds/equipment.hpp"

namespace mtc::bridge::test {
namespace {

using namespace std::chrono_literals;

std::size_t occurrences(const std::string& text, const std::string& needle) {
  std::size_t n = 0;
  for (auto at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) ++n;
  return n;
}

TEST(BridgeDevicesFile, AValueNoDataItemTakesIsLoggedOnceByName) {
  mtc::test::ChildProcess bridge(
      {MTC_BRIDGE_EXE, "--devices", std::string(MTC_DEVICES_DIR) + "/cell_1.6.xml", "--domain-ids",
       "84", "--heartbeat-ms", "100", "--port", "0", "--transport", "loopback"});
  ASSERT_TRUE(bridge.wait_for_line({"serving"}, 20s)) << bridge.stderr_text();

  // The file's machine has a material handler interface with REQUEST items
  // only: a responder's MATERIAL_LOAD RESPONSE maps to nothing.
  dds::EquipmentOptions options;
  options.domain_id = 84;
  options.device_uuid = "cell-machine";
  options.transport = qos::Transport::LoopbackTest;
  dds::Equipment machine(options);
  machine.add_interface({"mh9", core::InterfaceType::MaterialHandler, "", {}});
  auto& load = machine.add_responder("mh9", core::Service::MaterialLoad, dds::ResponderCallbacks{});
  machine.start();

  const std::string warning =
      "mtc-bridge: warning: DDS values of device 'cell-machine' interface 'mh9' item "
      "'mh9_material_load_response'";
  const auto deadline = std::chrono::steady_clock::now() + 15s;
  while (bridge.stderr_text().find(warning) == std::string::npos &&
         std::chrono::steady_clock::now() < deadline) {
    bridge.wait_for_line({"\x01 never printed"}, 100ms);  // reads stdout and stderr
  }
  ASSERT_NE(bridge.stderr_text().find(warning), std::string::npos) << bridge.stderr_text();
  for (int i = 0; i < 6; ++i) load.set_ready(i % 2 == 1).get();
  bridge.wait_for_line({"\x01 never printed"}, 500ms);
  bridge.send_signal(SIGTERM);
  ASSERT_EQ(bridge.wait_exit(10s), 0);
  EXPECT_EQ(occurrences(bridge.stderr_text(), warning), 1u) << bridge.stderr_text();
}

}  // namespace
}  // namespace mtc::bridge::test
