// Hostile announcements (issue 11): anyone on an unsecured DDS domain may
// announce devices. The agent accepts a bounded number, lets devices that
// left make room for new ones, and never lets an announcement take over a
// device of the Devices file.
#include <gtest/gtest.h>

#include "bridge_test_util.hpp"

namespace mtc::bridge {
namespace {

using test::Doc;
using test::get;
using test::value;

constexpr std::int64_t kT0 = 1'700'000'000'000'000'000;

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(HostileAnnouncements, DevicesBeyondTheLimitAreRefusedUntilOneLeaves) {
  AgentOptions o = test::cell_options();
  o.max_announced_devices = 2;
  std::vector<std::string> warnings;
  o.on_warning = [&](const std::string& w) { warnings.push_back(w); };
  auto agent = make_agent(o);
  agent->add_device(test::mill());
  agent->add_device(test::robot());
  agent->add_device(test::feeder());
  {
    Doc probe(get(*agent, "/probe").body);
    EXPECT_EQ(probe.count("//Device"), 2u);
    EXPECT_EQ(probe.count("//Device[@uuid='feeder-0001']"), 0u);
  }
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_TRUE(contains(warnings[0], "feeder-0001") && contains(warnings[0], "MaxAnnouncedDevices"))
      << warnings[0];
  // A known device re-announcing is not a new one.
  agent->add_device(test::robot());
  EXPECT_EQ(warnings.size(), 1u);

  // The robot leaves: the feeder takes its place.
  agent->device_lost("robot-0001");
  agent->add_device(test::feeder());
  Doc probe(get(*agent, "/probe").body);
  EXPECT_EQ(probe.count("//Device"), 2u);
  EXPECT_EQ(probe.count("//Device[@uuid='feeder-0001']"), 1u);
  EXPECT_EQ(probe.count("//Device[@uuid='robot-0001']"), 0u);
  EXPECT_EQ(probe.count("//Device[@uuid='mill-0001']"), 1u);
}

// Three thousand fake devices, as an attacker flooded the bridge with: the
// model stays at the limit.
TEST(HostileAnnouncements, AFloodOfDevicesStaysAtTheLimit) {
  AgentOptions o = test::cell_options();
  o.max_announced_devices = 16;
  std::size_t warnings = 0;
  o.on_warning = [&](const std::string&) { ++warnings; };
  auto agent = make_agent(o);
  for (int i = 0; i < 3000; ++i) {
    auto fake = test::feeder();
    fake.device_uuid = "fake-" + std::to_string(i);
    fake.name = fake.device_uuid;
    agent->add_device(fake);
  }
  Doc probe(get(*agent, "/probe").body);
  EXPECT_EQ(probe.count("//Device"), 16u);
  EXPECT_EQ(warnings, 3000u - 16u);
}

TEST(HostileAnnouncements, AnAnnouncementNeverTakesOverADeviceOfTheDevicesFile) {
  AgentOptions o = test::cell_options();
  o.devices_file = test::devices_file("cell_1.6.xml");
  std::vector<std::string> warnings;
  o.on_warning = [&](const std::string& w) { warnings.push_back(w); };
  auto agent = make_agent(o);
  agent->add_device(test::cell_machine());
  const Doc before(get(*agent, "/probe").body);

  // Another uuid naming the file's machine, with other interfaces.
  auto rogue = test::cell_robot();
  rogue.device_uuid = "rogue-1";
  rogue.name = "machine";
  agent->add_device(rogue);
  agent->add_value(value("rogue-1", "material_handler_material_load_request",
                         core::InteractionState::Active, kT0));
  ASSERT_FALSE(warnings.empty());
  EXPECT_TRUE(contains(warnings[0], "rogue-1") && contains(warnings[0], "machine")) << warnings[0];
  const std::string probe = get(*agent, "/probe").body;
  EXPECT_FALSE(contains(probe, "rogue-1"));
  EXPECT_EQ(Doc(probe).count("//DataItem"), before.count("//DataItem"));
  EXPECT_EQ(Doc(probe).text("//Header/@deviceModelChangeTime"),
            before.text("//Header/@deviceModelChangeTime"));
  Doc current(get(*agent, "/current").body);
  EXPECT_EQ(
      current.text("//MaterialLoad[@dataItemId='machine_material_handler_material_load_request']"),
      "UNAVAILABLE");

  // The machine itself still feeds its items.
  agent->add_value(value("cell-machine", "material_handler_material_load_request",
                         core::InteractionState::Ready, kT0));
  Doc after(get(*agent, "/current").body);
  EXPECT_EQ(
      after.text("//MaterialLoad[@dataItemId='machine_material_handler_material_load_request']"),
      "READY");
}

}  // namespace
}  // namespace mtc::bridge
