// The mtc-bridge executable as an operator runs it: exit codes, signals,
// and end to end from a DDS writer to /current.
// DDS domains: 80 end-to-end, 81 process lifecycle, 82 repeated losses, 85
// the bridge on Cyclone DDS (see CMakeLists.txt).
#include <gtest/gtest.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <memory>
#include <pugixml.hpp>
#include <string>
#include <thread>
#include <vector>

#include "child_process.hpp"
#include "mtc/dds/equipment.hpp"
#include "mtc/dds/middleware.hpp"
#include "raw_client.hpp"
#include "transport.hpp"

namespace mtc::bridge::test {
namespace {

using mtc::test::ChildProcess;

constexpr const char* kBridge = MTC_BRIDGE_EXE;

// mtc-bridge with `args` as a child process, on loopback unless `args`
// choose a transport.
std::unique_ptr<ChildProcess> start_bridge(const std::vector<std::string>& args) {
  std::vector<std::string> argv{kBridge};
  const auto chosen = mtc::test::with_loopback_transport(args);
  argv.insert(argv.end(), chosen.begin(), chosen.end());
  return std::make_unique<ChildProcess>(argv);
}

// Starts mtc-bridge on a free port and waits for its "serving" line.
class RunningBridge {
 public:
  explicit RunningBridge(std::vector<std::string> args) {
    args.insert(args.end(), {"--port", "0"});
    process_ = start_bridge(args);
    const auto line = process_->wait_for_line({"serving"}, std::chrono::seconds(20));
    if (!line) {
      ADD_FAILURE() << "mtc-bridge did not start; stderr: " << process_->stderr_text();
      return;
    }
    const auto colon = line->rfind(':', line->find("/ ("));
    port_ = static_cast<std::uint16_t>(std::stoi(line->substr(colon + 1)));
    serving_line_ = *line;
  }
  std::uint16_t port() const { return port_; }
  const std::string& serving_line() const { return serving_line_; }
  ChildProcess& process() { return *process_; }

  std::optional<HttpResponse> get(const std::string& target) {
    RawClient client(port_);
    client.send(get_request(target));
    return client.read_response(std::chrono::seconds(5));
  }

  // Value of data item `id` in /current, "" when absent.
  std::string current_value(const std::string& id) {
    const auto response = get("/current");
    if (!response || response->status != 200) {
      return {};
    }
    pugi::xml_document doc;
    doc.load_string(response->body.c_str());
    const std::string query = "//*[@dataItemId='" + id + "']";
    return doc.select_node(query.c_str()).node().text().get();
  }

 private:
  std::unique_ptr<ChildProcess> process_;
  std::uint16_t port_ = 0;
  std::string serving_line_;
};

template <typename Condition>
bool eventually(Condition condition, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!condition()) {
    if (std::chrono::steady_clock::now() > deadline) {
      return false;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return true;
}

std::string write_temp(const std::string& name, const std::string& text) {
  std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

int exit_code_of(const std::vector<std::string>& args, std::string* err = nullptr) {
  const auto process = start_bridge(args);
  const auto code = process->wait_exit(std::chrono::seconds(20));
  if (err != nullptr) {
    *err = process->stderr_text();
  }
  return code.value_or(-1);
}

TEST(BridgeProcess, HelpExitsZero) {
  const auto process = start_bridge({"--help"});
  EXPECT_EQ(process->wait_exit(std::chrono::seconds(10)), 0);
  EXPECT_NE(process->stdout_text().find("--domain-ids"), std::string::npos);
}

TEST(BridgeProcess, ConfigurationErrorsExitTwoNamingTheProblem) {
  std::string err;
  const auto bad = write_temp("bridge_bad.cfg", "Port = 5000\nPrto = 1\n");
  EXPECT_EQ(exit_code_of({"--config", bad}, &err), 2);
  EXPECT_NE(err.find(bad + ":2: unknown key 'Prto'"), std::string::npos) << err;

  EXPECT_EQ(exit_code_of({"--config", "/nonexistent/agent.cfg"}, &err), 2);
  EXPECT_NE(err.find("cannot open config file"), std::string::npos) << err;

  EXPECT_EQ(exit_code_of({"--io-threads", "zero"}, &err), 2);
  EXPECT_NE(err.find("--io-threads: IoThreads must be an integer"), std::string::npos) << err;

  EXPECT_EQ(
      exit_code_of({"--devices", "/nonexistent/Devices.xml", "--port", "0", "--domain-ids", "81"},
                   &err),
      2);
  EXPECT_NE(err.find("Devices file"), std::string::npos) << err;
  std::remove(bad.c_str());
}

// Files an attacker or an accident hands the bridge: each is refused at
// once with exit code 2 and a message naming the file (and the line).
TEST(BridgeProcess, HostileFilesExitTwoNamingFileAndLine) {
  const auto not_xml = write_temp("bridge_not_xml.xml", "Devices = cell.xml\n");
  const auto bomb = write_temp("bridge_bomb.xml",
                               "<?xml version='1.0'?>\n<!DOCTYPE d [<!ENTITY a 'aaaa'>\n"
                               "<!ENTITY b '&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;'>]>\n"
                               "<MTConnectDevices><Devices/></MTConnectDevices>\n");
  std::string deep = "<MTConnectDevices><Devices><Device id='d' name='n' uuid='u'>\n";
  for (int i = 0; i < 20000; ++i) deep += "<Components><Axes id='c" + std::to_string(i) + "'>";
  for (int i = 0; i < 20000; ++i) deep += "</Axes></Components>";
  deep += "</Device></Devices></MTConnectDevices>\n";
  const auto nested = write_temp("bridge_nested.xml", deep);
  const auto duplicate =
      write_temp("bridge_duplicate.xml",
                 "<MTConnectDevices><Devices>\n<Device id='a' name='mill' uuid='u'/>\n"
                 "<Device id='b' name='lathe' uuid='u'/>\n</Devices></MTConnectDevices>\n");
  const auto buffer = write_temp("bridge_buffer.cfg", "DomainIds = 81\nBufferSize = 30\n");
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases{
      {{"--devices", not_xml}, not_xml + ":2: not well-formed XML"},
      {{"--devices", bomb}, bomb + ":2: DOCTYPE"},
      {{"--devices", nested}, nested + ":2: elements nested deeper than 64"},
      {{"--devices", duplicate}, duplicate + ":3: duplicate device uuid 'u'"},
      {{"--devices", "/dev/zero"}, "/dev/zero:0: the Devices file is larger than"},
      {{"--config", "/dev/zero"}, "/dev/zero: config file is larger than"},
      {{"--config", buffer}, buffer + ":2: BufferSize (exponent) must be an integer from 1 to 24"},
  };
  for (const auto& [args, message] : cases) {
    std::vector<std::string> line = args;
    line.insert(line.end(), {"--port", "0", "--domain-ids", "81"});
    if (args[0] == "--config") line.resize(2);  // the file is the point
    std::string err;
    EXPECT_EQ(exit_code_of(line, &err), 2) << args[1];
    EXPECT_NE(err.find(message), std::string::npos) << err;
  }
  for (const auto& path : {not_xml, bomb, nested, duplicate, buffer}) std::remove(path.c_str());
}

// An integrator's agent.cfg from the reference agent runs as it is; what
// the bridge does not use is named on stderr.
TEST(BridgeProcess, AReferenceAgentCfgRunsWithWarnings) {
  const auto cfg = write_temp("bridge_reference.cfg",
                              "PidFile = /tmp/agent.pid\nDomainIds = 81\nAllowPut = true\n"
                              "Adapters {\n  Mazak {\n    Port = 7878\n  }\n}\n");
  RunningBridge bridge({"--config", cfg});
  ASSERT_NE(bridge.port(), 0);
  const auto probe = bridge.get("/probe");
  ASSERT_TRUE(probe);
  EXPECT_EQ(probe->status, 200);
  bridge.process().send_signal(SIGTERM);
  EXPECT_EQ(bridge.process().wait_exit(std::chrono::seconds(10)), 0);  // all stderr read
  const std::string err = bridge.process().stderr_text();
  EXPECT_NE(err.find("warning: " + cfg +
                     ":1: PidFile is a key of the reference agent that mtc-bridge does not use"),
            std::string::npos)
      << err;
  EXPECT_NE(err.find(cfg + ":4: block 'Adapters'"), std::string::npos) << err;
  std::remove(cfg.c_str());
}

TEST(BridgeProcess, ServesThenStopsCleanlyOnSigterm) {
  RunningBridge bridge({"--domain-ids", "81"});
  ASSERT_NE(bridge.port(), 0);
  const auto probe = bridge.get("/probe");
  ASSERT_TRUE(probe);
  EXPECT_EQ(probe->status, 200);
  EXPECT_NE(probe->body.find("MTConnectDevices"), std::string::npos);

  // A streaming client gets the closing boundary when the bridge stops.
  RawClient stream(bridge.port());
  stream.send(get_request("/sample?interval=0&heartbeat=60000"));
  ASSERT_TRUE(stream.read_stream_head());
  ASSERT_TRUE(stream.read_part());

  bridge.process().send_signal(SIGTERM);
  EXPECT_EQ(bridge.process().wait_exit(std::chrono::seconds(10)), 0);
  EXPECT_TRUE(stream.read_stream_end(std::chrono::seconds(2)));
  EXPECT_NE(bridge.process().stdout_text().find("mtc-bridge: stopped"), std::string::npos);
}

TEST(BridgeProcess, ServesADevicesFileWithItsSchemaVersion) {
  const auto cfg = write_temp("bridge_devices.cfg", std::string("Devices = ") + MTC_DEVICES_DIR +
                                                        "/cell_2.0.xml\nDomainIds = 81\n");
  RunningBridge bridge({"--config", cfg});
  ASSERT_NE(bridge.port(), 0);
  EXPECT_NE(bridge.process().stdout_text().find("MTConnect 2.0"), std::string::npos);
  const auto probe = bridge.get("/probe");
  ASSERT_TRUE(probe);
  EXPECT_EQ(probe->status, 200);
  pugi::xml_document doc;
  ASSERT_TRUE(doc.load_string(probe->body.c_str()));
  EXPECT_TRUE(doc.select_node("//*[local-name()='Device' and @uuid]"));
  // Items no device has published yet read UNAVAILABLE.
  const auto current = bridge.get("/current");
  ASSERT_TRUE(current);
  EXPECT_NE(current->body.find("UNAVAILABLE"), std::string::npos);
  std::remove(cfg.c_str());
}

TEST(BridgeProcess, ABusyPortExitsOne) {
  RunningBridge first({"--domain-ids", "81"});
  ASSERT_NE(first.port(), 0);
  std::string err;
  EXPECT_EQ(exit_code_of({"--port", std::to_string(first.port()), "--domain-ids", "81"}, &err), 1);
  EXPECT_NE(err.find("cannot bind"), std::string::npos) << err;
}

// A device publishes on DDS; the bridge's /current follows its transition,
// and a comms loss (every datagram of the device dropped) reads UNAVAILABLE.
TEST(BridgeEndToEnd, TransitionAndLivelinessLossReachCurrent) {
  RunningBridge bridge({"--domain-ids", "80", "--heartbeat-ms", "100"});
  ASSERT_NE(bridge.port(), 0);

  dds::EquipmentOptions options;
  options.domain_id = 80;
  options.device_uuid = "e2e-robot";
  options.transport = qos::Transport::LoopbackTest;
  options.faults.outage = std::make_shared<std::atomic<bool>>(false);
  dds::Equipment robot(options);
  robot.add_interface({"mh1", core::InterfaceType::MaterialHandler, "", {}});
  auto& load = robot.add_responder("mh1", core::Service::MaterialLoad, dds::ResponderCallbacks{});
  robot.start();

  const std::string item = "mh1_material_load_response";
  EXPECT_TRUE(
      eventually([&] { return bridge.current_value(item) == "READY"; }, std::chrono::seconds(15)))
      << "last /current value: '" << bridge.current_value(item) << "'";

  load.set_ready(false).get();
  EXPECT_TRUE(eventually([&] { return bridge.current_value(item) == "NOT_READY"; },
                         std::chrono::seconds(10)));

  options.faults.outage->store(true);  // the cable is pulled
  EXPECT_TRUE(eventually([&] { return bridge.current_value(item) == "UNAVAILABLE"; },
                         std::chrono::seconds(10)));
}

// A device frozen (every datagram dropped, as SIGSTOP would) three times:
// its Availability reads UNAVAILABLE on each loss, not only on the first,
// and AVAILABLE again each time it comes back.
TEST(BridgeEndToEnd, AvailabilityFollowsEveryLoss) {
  // The bridge on the device's transport: the fault-injecting test transport
  // discovers through the SPDP multicast group, which the default loopback
  // transport no longer listens to. After an outage the device (which kept
  // hearing the bridge) would announce itself only there, and a loopback
  // bridge that had dropped it would never see it again.
  RunningBridge bridge({"--domain-ids", "82", "--heartbeat-ms", "100", "--transport", "test"});
  ASSERT_NE(bridge.port(), 0);
  dds::EquipmentOptions options;
  options.domain_id = 82;
  options.device_uuid = "frozen-robot";
  options.transport = qos::Transport::LoopbackTest;
  options.faults.outage = std::make_shared<std::atomic<bool>>(false);
  dds::Equipment robot(options);
  robot.add_interface({"mh1", core::InterfaceType::MaterialHandler, "", {}});
  robot.add_responder("mh1", core::Service::MaterialLoad, dds::ResponderCallbacks{});
  robot.start();

  // The announced device's AVAILABILITY item (model_from_announcements).
  const std::string availability = "frozen-robot_avail";
  const std::string item = "mh1_material_load_response";
  ASSERT_TRUE(eventually([&] { return bridge.current_value(availability) == "AVAILABLE"; },
                         std::chrono::seconds(15)))
      << "'" << bridge.current_value(availability) << "'";
  for (int freeze = 1; freeze <= 3; ++freeze) {
    options.faults.outage->store(true);
    EXPECT_TRUE(eventually([&] { return bridge.current_value(item) == "UNAVAILABLE"; },
                           std::chrono::seconds(10)))
        << "freeze " << freeze;
    EXPECT_TRUE(eventually([&] { return bridge.current_value(availability) == "UNAVAILABLE"; },
                           std::chrono::seconds(10)))
        << "freeze " << freeze << ": Availability reads '" << bridge.current_value(availability)
        << "' while " << item << " reads UNAVAILABLE";
    options.faults.outage->store(false);
    EXPECT_TRUE(eventually([&] { return bridge.current_value(availability) == "AVAILABLE"; },
                           std::chrono::seconds(10)))
        << "thaw " << freeze;
    EXPECT_TRUE(
        eventually([&] { return bridge.current_value(item) == "READY"; }, std::chrono::seconds(10)))
        << "thaw " << freeze;
  }
}

// `--middleware cyclone` (issue 9 section 3): the bridge observes through
// Cyclone DDS a device on Fast DDS, its changes and its leave, since the
// wire contract is the IDL and the QoS. A build without Cyclone (the
// sanitizer builds) refuses the option, naming the CMake switch.
TEST(BridgeEndToEnd, ABridgeOnCycloneFollowsADeviceOnFastDds) {
  if (!dds::middleware_available(dds::Middleware::Cyclone)) {
    std::string err;
    EXPECT_EQ(exit_code_of({"--domain-ids", "85", "--middleware", "cyclone"}, &err), 2);
    EXPECT_NE(err.find("configure with -DMTC_CYCLONE=ON"), std::string::npos) << err;
    return;
  }
  RunningBridge bridge({"--domain-ids", "85", "--heartbeat-ms", "100", "--middleware", "cyclone"});
  ASSERT_NE(bridge.port(), 0);
  EXPECT_NE(bridge.serving_line().find("DDS domains 85 over cyclone;"), std::string::npos)
      << bridge.serving_line();
  dds::EquipmentOptions options;
  options.domain_id = 85;
  options.device_uuid = "fastdds-machine";
  options.transport = qos::Transport::Loopback;
  options.middleware = dds::Middleware::FastDds;
  auto machine = std::make_unique<dds::Equipment>(options);
  machine->add_interface({"mh1", core::InterfaceType::MaterialHandler, "", {}});
  auto& load = machine->add_responder("mh1", core::Service::MaterialLoad, {});
  machine->start();

  const std::string item = "mh1_material_load_response";
  const std::string availability = "fastdds-machine_avail";
  EXPECT_TRUE(
      eventually([&] { return bridge.current_value(item) == "READY"; }, std::chrono::seconds(15)))
      << "last /current value: '" << bridge.current_value(item) << "'";
  EXPECT_EQ(bridge.current_value(availability), "AVAILABLE");
  load.set_ready(false).get();
  EXPECT_TRUE(eventually([&] { return bridge.current_value(item) == "NOT_READY"; },
                         std::chrono::seconds(10)));
  machine.reset();  // its leave: the last heartbeats say so
  EXPECT_TRUE(eventually([&] { return bridge.current_value(item) == "UNAVAILABLE"; },
                         std::chrono::seconds(10)));
  EXPECT_EQ(bridge.current_value(availability), "UNAVAILABLE");
}

}  // namespace
}  // namespace mtc::bridge::test
