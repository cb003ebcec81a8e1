// Devices files as integrators write them: interface items defined in
// another component and pointed at with References/DataItemRef (Part 5 1.6,
// 4.2.3.1), and DDS values no DataItem takes, reported once by name.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bridge_test_util.hpp"
#include "xmllint.hpp"

namespace mtc::bridge {
namespace {

using test::Doc;
using test::get;

constexpr std::int64_t kT0 = 1'700'000'000'000'000'000;

const std::string kReferencedFile = std::string(MTC_TEST_DEVICES_DIR) + "/referenced_1.6.xml";

core::ObservedValue machine_value(const std::string& interface_id, const std::string& item,
                                  core::ObservedState state) {
  core::ObservedValue v = test::value("cell-machine", item, state, kT0);
  v.interface_id = interface_id;
  return v;
}

std::unique_ptr<MtconnectAgent> referenced_agent(std::vector<std::string>* warnings = nullptr) {
  AgentOptions o = test::cell_options();
  o.devices_file = kReferencedFile;
  if (warnings) o.on_warning = [warnings](const std::string& w) { warnings->push_back(w); };
  auto agent = make_agent(o);
  agent->add_device(test::cell_machine());
  return agent;
}

TEST(DevicesFileReferences, TheTestFileIsAValidDevicesDocument) {
  std::ifstream in(kReferencedFile);
  std::ostringstream text;
  text << in.rdbuf();
  const test::Lint lint =
      test::xmllint(text.str(), test::schema("MTConnectDevices", SchemaVersion::V1_6));
  EXPECT_EQ(lint.exit_code, 0) << lint.output;
}

TEST(DevicesFileReferences, DoorAndChuckStatesReachTheReferencedItems) {
  std::vector<std::string> warnings;
  auto agent = referenced_agent(&warnings);
  // CLOSED: the 1.6 Streams schema's DoorState enumeration lacks OPEN.
  agent->add_value(machine_value("door", "door_door_state", core::DoorState::Closed));
  agent->add_value(machine_value("chuck", "chuck_chuck_state", core::ChuckState::Open));
  agent->add_value(machine_value("door", "door_interface_state", core::InterfaceState::Enabled));
  const Response r = get(*agent, "/current");
  Doc d(r.body);
  EXPECT_EQ(d.text("//ComponentStream[@componentId='front_door']/Events/DoorState"), "CLOSED");
  EXPECT_EQ(d.text("//ComponentStream[@componentId='main_chuck']/Events/ChuckState"), "OPEN");
  EXPECT_EQ(d.text("//*[@dataItemId='di_state']"), "ENABLED");
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  EXPECT_EQ(agent->stats().unknown_values, 0u);
  const test::Lint lint =
      test::xmllint(r.body, test::schema("MTConnectStreams", SchemaVersion::V1_6));
  EXPECT_EQ(lint.exit_code, 0) << lint.output;
}

TEST(DevicesFileReferences, AValueNoItemTakesIsReportedOnceByName) {
  std::vector<std::string> warnings;
  auto agent = referenced_agent(&warnings);
  // The file's Door/Chuck interfaces list no bar feeder: its values map to
  // nothing, however often they come.
  for (int i = 0; i < 5; ++i) {
    core::ObservedValue v =
        machine_value("bar_feeder", "bar_feeder_material_feed_request",
                      i % 2 != 0 ? core::InteractionState::Ready : core::InteractionState::Active);
    v.service = core::Service::MaterialFeed;
    v.sub_type = core::SubType::Request;
    agent->add_value(v);
  }
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("device 'cell-machine'"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("interface 'bar_feeder'"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("item 'bar_feeder_material_feed_request'"), std::string::npos)
      << warnings[0];
  EXPECT_NE(warnings[0].find("referenced_1.6.xml"), std::string::npos) << warnings[0];
  EXPECT_EQ(agent->stats().unknown_values, 5u);
}

}  // namespace
}  // namespace mtc::bridge
