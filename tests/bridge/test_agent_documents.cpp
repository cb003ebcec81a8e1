// The agent end to end without HTTP: values in, documents out, asserted with
// XPath on the parsed XML.
#include <gtest/gtest.h>

#include <algorithm>

#include "bridge_test_util.hpp"

namespace mtc::bridge {
namespace {

using test::Doc;
using test::get;
using test::value;

constexpr std::int64_t kT0 = 1'700'000'000'000'000'000;  // 2023-11-14T22:13:20Z

TEST(Agent, ProbeListsAnnouncedDevicesAndInterfaces) {
  auto agent = test::announced_cell();
  const Response r = get(*agent, "/probe");
  EXPECT_EQ(r.status, 200);
  Doc d(r.body);
  ASSERT_TRUE(d.ok);
  EXPECT_EQ(d.count("/MTConnectDevices/Devices/Device"), 3u);
  EXPECT_EQ(d.count("//Device[@name='mill']//MaterialHandlerInterface"), 1u);
  EXPECT_EQ(d.count("//Device[@name='mill']//BarFeederInterface//DataItem"), 2u);
  EXPECT_EQ(d.text("//DataItem[@id='robot.material_load.rsp']/@subType"), "RESPONSE");
  EXPECT_EQ(d.text("/MTConnectDevices/Header/@instanceId"), "42");
  EXPECT_EQ(d.text("/MTConnectDevices/Header/@version"), "1.6.0.0");
  EXPECT_STREQ(d.xml.document_element().attribute("xmlns").value(),
               "urn:mtconnect.org:MTConnectDevices:1.6");
  // One device, by name and by uuid.
  EXPECT_EQ(Doc(get(*agent, "/robot/probe").body).count("//Device"), 1u);
  EXPECT_EQ(Doc(get(*agent, "/robot-0001").body).count("//Device[@name='robot']"), 1u);
  EXPECT_EQ(Doc(get(*agent, "/").body).count("//Device"), 3u);
}

TEST(Agent, EveryItemIsUnavailableUntilItsFirstValue) {
  auto agent = test::announced_cell();
  Doc d(get(*agent, "/current").body);
  ASSERT_TRUE(d.ok);
  EXPECT_EQ(d.count("//Events/*[. != 'UNAVAILABLE' and name() != 'Availability']"), 0u);
  EXPECT_EQ(d.text("//MaterialLoad[@dataItemId='mill.material_load.req']"), "UNAVAILABLE");
  // Announced devices are AVAILABLE.
  EXPECT_EQ(d.count("//Availability[. = 'AVAILABLE']"), 3u);
}

TEST(Agent, CurrentShowsLatestValuesWithAttributes) {
  auto agent = test::announced_cell();
  agent->add_value(
      value("mill-0001", "mill.material_load.req", core::InteractionState::Ready, kT0));
  agent->add_value(
      value("mill-0001", "mill.material_load.req", core::InteractionState::Active, kT0 + 1500));
  Doc d(get(*agent, "/current").body);
  const char* load =
      "//DeviceStream[@name='mill']/ComponentStream[@component='MaterialHandlerInterface']"
      "/Events/MaterialLoad";
  ASSERT_EQ(d.count(load), 1u);
  EXPECT_EQ(d.text(load), "ACTIVE");
  EXPECT_EQ(d.text((std::string(load) + "/@subType").c_str()), "REQUEST");
  EXPECT_EQ(d.text((std::string(load) + "/@timestamp").c_str()), "2023-11-14T22:13:20.000001Z");
  EXPECT_EQ(d.text("//ComponentStream[@component='MaterialHandlerInterface'][1]/@componentId"),
            "mill_mh");
  const std::uint64_t seq = d.number((std::string(load) + "/@sequence").c_str());
  EXPECT_EQ(seq + 1, d.number("//Header/@nextSequence"));
  EXPECT_EQ(d.number("//Header/@lastSequence"), seq);
}

// The observer hands last known values over again after a loss; one equal
// to what the buffer holds adds nothing.
TEST(Agent, UnchangedValuesCreateNoObservations) {
  auto agent = test::announced_cell();
  agent->add_value(value("robot-0001", "robot.mh.state", core::InterfaceState::Enabled, kT0));
  const std::uint64_t next = agent->next_sequence();
  for (int i = 1; i <= 5; ++i) {
    agent->add_value(
        value("robot-0001", "robot.mh.state", core::InterfaceState::Enabled, kT0 + 100, true));
  }
  EXPECT_EQ(agent->next_sequence(), next);
  EXPECT_EQ(agent->stats().duplicates, 5u);
  // A value handed over again that differs is a change we had missed.
  agent->add_value(
      value("robot-0001", "robot.mh.state", core::InterfaceState::Disabled, kT0 + 200, true));
  EXPECT_EQ(agent->next_sequence(), next + 1);
}

TEST(Agent, LivelinessLossTurnsItemsUnavailable) {
  auto agent = test::announced_cell();
  agent->add_value(value("mill-0001", "mill.door.door_state", core::DoorState::Open, kT0));
  agent->add_value(value("mill-0001", "mill.open_door.rsp", core::InteractionState::Ready, kT0));
  agent->items_lost("mill-0001", {"mill.door.door_state", "mill.open_door.rsp", "no.such.item"});
  Doc d(get(*agent, "/mill/current").body);
  EXPECT_EQ(d.text("//DoorState[@dataItemId='mill.door.door_state']"), "UNAVAILABLE");
  EXPECT_EQ(d.text("//OpenDoor"), "UNAVAILABLE");
  EXPECT_EQ(agent->stats().unknown_values, 1u);
  // The transitions are all in the sample, in order.
  Doc s(get(*agent, "/mill/sample?path=//DataItem[@type='DOOR_STATE']").body);
  ASSERT_EQ(s.count("//DoorState"), 3u);
  EXPECT_EQ(s.text("(//DoorState)[2]"), "OPEN");
  EXPECT_EQ(s.text("(//DoorState)[3]"), "UNAVAILABLE");
}

TEST(Agent, DeviceLossTurnsEveryItemAndAvailabilityUnavailable) {
  auto agent = test::announced_cell();
  agent->add_value(value("robot-0001", "robot.mh.state", core::InterfaceState::Enabled, kT0));
  agent->device_lost("robot-0001");
  Doc d(get(*agent, "/robot/current").body);
  EXPECT_EQ(d.text("//Availability"), "UNAVAILABLE");
  EXPECT_EQ(d.count("//Events/*[. != 'UNAVAILABLE']"), 0u);
  // Back again.
  agent->add_device(test::robot());
  EXPECT_EQ(Doc(get(*agent, "/robot/current").body).text("//Availability"), "AVAILABLE");
}

TEST(Agent, ValuesForUnknownItemsAreCountedAndDropped) {
  auto agent = make_agent(test::cell_options());
  agent->add_value(value("ghost-0001", "ghost.thing", core::InteractionState::Ready, kT0));
  EXPECT_EQ(agent->stats().unknown_values, 1u);
  EXPECT_EQ(agent->stats().last_unknown, "ghost-0001/ghost.thing");
  EXPECT_EQ(get(*agent, "/current").status, 200);
}

TEST(Agent, ValueBeforeAnnouncementIsAppliedWhenTheDeviceAppears) {
  auto agent = make_agent(test::cell_options());
  agent->add_value(
      value("feeder-0001", "feeder.material_feed.rsp", core::InteractionState::Ready, kT0));
  agent->add_device(test::feeder());
  Doc d(get(*agent, "/feeder/current").body);
  EXPECT_EQ(d.text("//MaterialFeed"), "READY");
}

TEST(Agent, NewAnnouncementsRebuildTheModel) {
  auto agent = make_agent(test::cell_options(SchemaVersion::V2_0));
  agent->add_device(test::feeder());
  Doc before(get(*agent, "/probe").body);
  EXPECT_EQ(before.count("//Device"), 1u);
  agent->add_device(test::feeder());  // same announcement again: no change
  EXPECT_EQ(agent->stats().model_changes, 1u);
  agent->add_device(test::robot());
  Doc after(get(*agent, "/probe").body);
  EXPECT_EQ(after.count("//Device"), 2u);
  EXPECT_EQ(agent->stats().model_changes, 2u);
  EXPECT_FALSE(after.text("//Header/@deviceModelChangeTime").empty());
}

TEST(Agent, DevicesFileItemsNeverReceivedStayUnavailable) {
  AgentOptions o = test::cell_options();
  o.devices_file = test::devices_file("cell_1.6.xml");
  std::vector<std::string> warnings;
  o.on_warning = [&](const std::string& w) { warnings.push_back(w); };
  auto agent = make_agent(o);
  agent->add_device(test::cell_machine());
  agent->add_value(value("cell-machine", "material_handler_material_load_request",
                         core::InteractionState::Ready, kT0));
  agent->add_value(value("cell-machine", "not.in.file", core::InteractionState::Ready, kT0));
  agent->add_value(value("cell-machine", "not.in.file", core::InteractionState::Active, kT0));
  ASSERT_EQ(warnings.size(), 1u);  // once per item
  EXPECT_NE(warnings[0].find("device 'cell-machine'"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("item 'not.in.file'"), std::string::npos) << warnings[0];
  Doc d(get(*agent, "/current").body);
  EXPECT_EQ(d.text("//MaterialLoad[@dataItemId='machine_material_handler_material_load_request']"),
            "READY");
  EXPECT_EQ(d.text("//Position[@dataItemId='machine_x_pos']"), "UNAVAILABLE");
  EXPECT_EQ(d.text("//ComponentStream[@componentId='machine_x']/@component"), "Linear");
  EXPECT_EQ(d.count("//Condition/Unavailable[@dataItemId='machine_system'][@type='SYSTEM']"), 1u);
  EXPECT_EQ(d.text("//DeviceStream[@name='machine']//Availability"), "AVAILABLE");
  EXPECT_EQ(d.text("//DeviceStream[@name='robot']//Availability"), "UNAVAILABLE");
  EXPECT_EQ(agent->stats().unknown_values, 2u);
  // The file's version is used when none is forced.
  AgentOptions o13;
  o13.devices_file = test::devices_file("cell_1.3.xml");
  EXPECT_EQ(make_agent(o13)->schema_version(), SchemaVersion::V1_3);
}

TEST(Agent, DevicesFileDeviceIsFoundByNameWhenTheUuidDiffers) {
  AgentOptions o = test::cell_options();
  o.devices_file = test::devices_file("cell_1.6.xml");
  auto agent = make_agent(o);
  core::ObservedDevice robot = test::cell_robot();
  robot.device_uuid = "robot-serial-7731";  // the file says cell-robot
  agent->add_device(robot);
  agent->add_value(value("robot-serial-7731", "material_handler_material_load_response",
                         core::InteractionState::Ready, kT0));
  Doc d(get(*agent, "/robot/current").body);
  EXPECT_EQ(d.text("//MaterialLoad"), "READY");
  EXPECT_EQ(d.text("//Availability"), "AVAILABLE");
  agent->device_lost("robot-serial-7731");
  EXPECT_EQ(Doc(get(*agent, "/robot/current").body).text("//MaterialLoad"), "UNAVAILABLE");
  EXPECT_EQ(agent->stats().unknown_values, 0u);
}

TEST(Agent, DevicesFileItemsAreMatchedByTypeFromValues) {
  AgentOptions o = test::cell_options();
  o.devices_file = test::devices_file("cell_1.6.xml");
  auto agent = make_agent(o);
  core::ObservedValue v =
      value("cell-feeder", "vendor_feed_rsp", core::InteractionState::Active, kT0);
  v.interface_id = "bar_feeder";
  v.service = core::Service::MaterialFeed;
  v.sub_type = core::SubType::Response;
  agent->add_value(v);
  Doc d(get(*agent, "/feeder/current").body);
  EXPECT_EQ(d.text("//MaterialFeed"), "ACTIVE");
  EXPECT_EQ(agent->stats().unknown_values, 0u);
}

TEST(Agent, MalformedDevicesFileThrowsModelError) {
  AgentOptions o = test::cell_options();
  o.devices_file = "/nonexistent/cell.xml";
  EXPECT_THROW(make_agent(o), ModelError);
  o.devices_file.clear();
  o.buffer_size = 1;
  EXPECT_THROW(make_agent(o), std::invalid_argument);
}

TEST(Agent, CurrentAtAnswersThePastState) {
  auto agent = test::announced_cell();
  agent->add_value(value("mill-0001", "mill.open_door.rsp", core::InteractionState::Ready, kT0));
  const std::uint64_t ready_seq = agent->next_sequence() - 1;
  agent->add_value(
      value("mill-0001", "mill.open_door.rsp", core::InteractionState::Active, kT0 + 1));
  Doc d(get(*agent, "/current?at=" + std::to_string(ready_seq)).body);
  EXPECT_EQ(d.text("//OpenDoor"), "READY");
  // As the reference agent: the buffer's nextSequence, not at + 1.
  EXPECT_EQ(d.number("//Header/@nextSequence"), agent->next_sequence());
  EXPECT_EQ(Doc(get(*agent, "/current").body).text("//OpenDoor"), "ACTIVE");
}

TEST(Agent, SampleHonoursFromCountAndTo) {
  auto agent = test::announced_cell();
  const std::uint64_t start = agent->next_sequence();
  for (int i = 0; i < 10; ++i) {
    agent->add_value(value(
        "mill-0001", "mill.material_load.req",
        i % 2 != 0 ? core::InteractionState::Active : core::InteractionState::Ready, kT0 + i));
  }
  Doc d(get(*agent, "/sample?from=" + std::to_string(start) + "&count=4").body);
  ASSERT_EQ(d.count("//MaterialLoad"), 4u);
  EXPECT_EQ(d.number("(//MaterialLoad)[1]/@sequence"), start);
  EXPECT_EQ(d.number("//Header/@nextSequence"), start + 4);
  Doc t(get(*agent, "/sample?from=" + std::to_string(start) + "&to=" + std::to_string(start + 2))
            .body);
  EXPECT_EQ(t.count("//MaterialLoad"), 2u);
  EXPECT_EQ(t.number("//Header/@nextSequence"), start + 2);
  Doc n(get(*agent, "/sample?count=-3").body);
  ASSERT_EQ(n.count("//MaterialLoad"), 3u);
  EXPECT_EQ(n.number("(//MaterialLoad)[3]/@sequence"), start + 9);
  EXPECT_LT(n.number("(//MaterialLoad)[1]/@sequence"), n.number("(//MaterialLoad)[2]/@sequence"));
}

TEST(Agent, SampleAfterWrapAroundStartsAtFirstSequence) {
  auto agent = test::announced_cell(SchemaVersion::V1_6, 16);
  for (int i = 0; i < 100; ++i) {
    agent->add_value(value(
        "robot-0001", "robot.open_door.req",
        i % 2 != 0 ? core::InteractionState::Active : core::InteractionState::Ready, kT0 + i));
  }
  Doc d(get(*agent, "/sample").body);
  EXPECT_EQ(d.count("//OpenDoor"), 16u);
  const std::uint64_t first = d.number("//Header/@firstSequence");
  EXPECT_EQ(d.number("//Header/@lastSequence") - first + 1, 16u);
  EXPECT_EQ(d.number("(//OpenDoor)[1]/@sequence"), first);
  const Response old = get(*agent, "/sample?from=" + std::to_string(first - 1));
  EXPECT_EQ(old.status, 400);
  EXPECT_EQ(Doc(old.body).text("//Error/@errorCode"), "OUT_OF_RANGE");
  // /current still has items whose last change fell out of the ring.
  EXPECT_EQ(Doc(get(*agent, "/current").body)
                .text("//MaterialLoad[@dataItemId='robot.material_load.rsp']"),
            "UNAVAILABLE");
}

TEST(Agent, PathFiltersStreams) {
  auto agent = test::announced_cell();
  Doc d(get(*agent, "/current?path=//DataItem[@type=%22INTERFACE_STATE%22]").body);
  EXPECT_EQ(d.count("//InterfaceState"), 6u);
  EXPECT_EQ(d.count("//Events/*[name() != 'InterfaceState']"), 0u);
  Doc m(get(*agent, "/mill/current?path=//DataItem[@type='INTERFACE_STATE']").body);
  EXPECT_EQ(m.count("//InterfaceState"), 4u);
  EXPECT_EQ(m.count("//DeviceStream"), 1u);
  Doc c(get(*agent, "/current?path=//DoorInterface").body);
  EXPECT_EQ(c.count("//ComponentStream"), 1u);
  EXPECT_EQ(c.count("//ComponentStream/Events/*"), 4u);
}

TEST(Agent, PrettyOutputCarriesTheSameDocument) {
  auto agent = test::announced_cell();
  const std::string raw = get(*agent, "/mill/current").body;
  const std::string pretty = get(*agent, "/mill/current?pretty=true").body;
  EXPECT_GT(std::count(pretty.begin(), pretty.end(), '\n'), 10);
  EXPECT_EQ(Doc(raw).count("//Events/*"), Doc(pretty).count("//Events/*"));
}

TEST(Agent, CurrentAtWithPathAfterWrapAround) {
  auto agent = test::announced_cell(SchemaVersion::V1_6, 40);
  std::uint64_t seq_of_third = 0;
  // Consecutive values always differ, so each one is an observation.
  const auto state_at = [](int i) { return core::kAllInteractionStates[i % 6]; };
  for (int i = 0; i < 100; ++i) {
    agent->add_value(value("mill-0001", "mill.open_chuck.rsp", state_at(i), kT0 + i));
    if (i == 90) seq_of_third = agent->next_sequence() - 1;
  }
  Doc d(get(*agent,
            "/current?at=" + std::to_string(seq_of_third) + "&path=//DataItem[@type='OPEN_CHUCK']")
            .body);
  ASSERT_EQ(d.count("//OpenChuck"), 2u);  // mill's and robot's
  EXPECT_EQ(d.text("//OpenChuck[@dataItemId='mill.open_chuck.rsp']"),
            core::to_string(state_at(90)));
  EXPECT_EQ(d.text("//OpenChuck[@dataItemId='robot.open_chuck.req']"), "UNAVAILABLE");
}

TEST(Agent, AssetsIsAnEmptyDocument) {
  auto agent = test::announced_cell();
  const Response r = get(*agent, "/assets");
  EXPECT_EQ(r.status, 200);
  Doc d(r.body);
  EXPECT_EQ(d.count("/MTConnectAssets/Assets"), 1u);
  EXPECT_EQ(d.text("//Header/@assetCount"), "0");
}

TEST(Agent, RepeatedCurrentIsServedFromCacheUntilDataChanges) {
  auto agent = test::announced_cell();
  const std::string a = get(*agent, "/current").body;
  const std::string b = get(*agent, "/current").body;
  EXPECT_EQ(test::without_creation_time(a), test::without_creation_time(b));
  agent->add_value(
      value("mill-0001", "mill.material_load.req", core::InteractionState::Ready, kT0));
  const std::string c = get(*agent, "/current").body;
  EXPECT_NE(Doc(c).text("//MaterialLoad[@dataItemId='mill.material_load.req']"), "UNAVAILABLE");
}

// The cache keeps one document per device, path and format: a cached
// document of one filter is never served for another, and a change reaches
// every one of them on its next request.
TEST(Agent, CachedCurrentDocumentsKeepTheirFilters) {
  auto agent = test::announced_cell();
  const std::vector<std::string> targets{"/current", "/current?path=//DoorInterface",
                                         "/robot/current", "/current?format=json"};
  for (int pass = 0; pass < 2; ++pass) {  // the second pass is served from the cache
    EXPECT_EQ(Doc(get(*agent, targets[1]).body).count("//MaterialLoad"), 0u);
    EXPECT_GT(Doc(get(*agent, targets[1]).body).count("//DoorState"), 0u);
    EXPECT_EQ(Doc(get(*agent, targets[2]).body).count("//DeviceStream[@name='mill']"), 0u);
    EXPECT_GT(Doc(get(*agent, targets[0]).body).count("//DeviceStream[@name='mill']"), 0u);
    EXPECT_GT(Doc(get(*agent, targets[0]).body).count("//MaterialLoad"), 0u);
    EXPECT_EQ(get(*agent, targets[3]).body.front(), '{');
    EXPECT_EQ(get(*agent, targets[3]).body.find("\"OPEN\""), std::string::npos);
  }
  agent->add_value(value("mill-0001", "mill.door.door_state", core::DoorState::Open, kT0));
  const char* door = "//DoorState[@dataItemId='mill.door.door_state']";
  EXPECT_EQ(Doc(get(*agent, targets[0]).body).text(door), "OPEN");
  EXPECT_EQ(Doc(get(*agent, targets[1]).body).text(door), "OPEN");
  EXPECT_NE(get(*agent, targets[3]).body.find("\"OPEN\""), std::string::npos);
}

}  // namespace
}  // namespace mtc::bridge
