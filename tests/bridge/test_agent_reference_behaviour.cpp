// Where the standard leaves room, the bridge answers as the MTConnect
// reference agent (cppagent) does: empty DeviceStreams left out, nextSequence
// after `at` and after a negative `count`, documents valid in every version.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "bridge_test_util.hpp"
#include "xmllint.hpp"

namespace mtc::bridge {
namespace {

using test::Doc;
using test::get;
using test::value;

constexpr std::int64_t kT0 = 1'700'000'000'000'000'000;

void expect_valid(const std::string& body, const char* kind, SchemaVersion v) {
  const test::Lint lint = test::xmllint(body, test::schema(kind, v));
  EXPECT_EQ(lint.exit_code, 0) << to_string(v) << ": " << lint.output << body.substr(0, 2000);
}

TEST(ReferenceAgent, FilteredCurrentOmitsDevicesWithNothingSelected) {
  for (const SchemaVersion v : {SchemaVersion::V1_3, SchemaVersion::V1_6, SchemaVersion::V2_0}) {
    auto agent = test::announced_cell(v);
    const Response r =
        get(*agent, "/current?path=//Device[@name='mill']//DataItem[@type='INTERFACE_STATE']");
    Doc d(r.body);
    EXPECT_EQ(d.count("//DeviceStream"), 1u) << to_string(v);
    EXPECT_EQ(d.count("//DeviceStream[@name='mill']"), 1u) << to_string(v);
    expect_valid(r.body, "MTConnectStreams", v);
  }
}

TEST(ReferenceAgent, StreamHeartbeatsCarryNoDeviceStream) {
  for (const SchemaVersion v : {SchemaVersion::V1_6, SchemaVersion::V2_0}) {
    auto agent = test::announced_cell(v);
    const std::string from = std::to_string(agent->next_sequence());
    // A sample with nothing new: what a stream sends as its heartbeat.
    const Response r = get(*agent, "/sample?from=" + from);
    EXPECT_EQ(Doc(r.body).count("//DeviceStream"), 0u) << to_string(v) << r.body;
    expect_valid(r.body, "MTConnectStreams", v);
  }
  // 1.3 requires one DeviceStream: the first device's, empty.
  auto agent = test::announced_cell(SchemaVersion::V1_3);
  const Response r = get(*agent, "/sample?from=" + std::to_string(agent->next_sequence()));
  Doc d(r.body);
  EXPECT_EQ(d.count("//DeviceStream"), 1u);
  EXPECT_EQ(d.count("//ComponentStream"), 0u);
  expect_valid(r.body, "MTConnectStreams", SchemaVersion::V1_3);
}

TEST(ReferenceAgent, NextSequenceAfterAtIsTheBuffersNext) {
  auto agent = test::announced_cell();
  agent->add_value(value("mill-0001", "mill.open_door.rsp", core::InteractionState::Ready, kT0));
  const std::uint64_t at = agent->next_sequence() - 1;
  agent->add_value(value("mill-0001", "mill.open_door.rsp", core::InteractionState::Active, kT0));
  Doc d(get(*agent, "/current?at=" + std::to_string(at)).body);
  EXPECT_EQ(d.text("//OpenDoor"), "READY");
  EXPECT_EQ(d.number("//Header/@nextSequence"), agent->next_sequence());
  EXPECT_EQ(d.number("//Header/@lastSequence"), agent->next_sequence() - 1);
}

TEST(ReferenceAgent, NegativeCountWalksBackAndPointsBelowTheOldest) {
  auto agent = test::announced_cell();
  const std::uint64_t start = agent->next_sequence();
  for (int i = 0; i < 10; ++i) {
    agent->add_value(value(
        "mill-0001", "mill.material_load.req",
        i % 2 != 0 ? core::InteractionState::Active : core::InteractionState::Ready, kT0 + i));
  }
  // The last three: start+7 .. start+9; nextSequence start+6, the one a
  // client walking back asks for next.
  Doc last(get(*agent, "/sample?count=-3").body);
  ASSERT_EQ(last.count("//MaterialLoad"), 3u);
  EXPECT_EQ(last.number("(//MaterialLoad)[1]/@sequence"), start + 7);
  EXPECT_EQ(last.number("(//MaterialLoad)[3]/@sequence"), start + 9);
  EXPECT_EQ(last.number("//Header/@nextSequence"), start + 6);
  // `from` is where the walk back starts.
  Doc back(get(*agent, "/sample?count=-2&from=" + std::to_string(start + 4)).body);
  ASSERT_EQ(back.count("//MaterialLoad"), 2u);
  EXPECT_EQ(back.number("(//MaterialLoad)[1]/@sequence"), start + 3);
  EXPECT_EQ(back.number("(//MaterialLoad)[2]/@sequence"), start + 4);
  EXPECT_EQ(back.number("//Header/@nextSequence"), start + 2);
}

// Every device has ASSET_CHANGED and ASSET_REMOVED (added to a Devices file
// that lacks them), reading UNAVAILABLE; probe and current validate.
TEST(ReferenceAgent, EveryDeviceHasTheAssetItems) {
  for (const SchemaVersion v : {SchemaVersion::V1_3, SchemaVersion::V1_6, SchemaVersion::V2_0}) {
    auto announced = test::announced_cell(v);
    AgentOptions o = test::cell_options(v);
    o.devices_file = test::devices_file("cell_" + std::string(to_string(v)) + ".xml");
    auto from_file = make_agent(o);
    for (MtconnectAgent* agent : {announced.get(), from_file.get()}) {
      const Response probe = get(*agent, "/probe");
      Doc p(probe.body);
      const std::size_t devices = p.count("//Device");
      EXPECT_EQ(p.count("//Device/DataItems/DataItem[@type='ASSET_CHANGED']"), devices);
      EXPECT_EQ(p.count("//Device/DataItems/DataItem[@type='ASSET_REMOVED']"), devices);
      // The 2.0 Devices XSD has no interface elements (schemas README):
      // checked below with a device without interfaces.
      if (v != SchemaVersion::V2_0) expect_valid(probe.body, "MTConnectDevices", v);
      const Response current = get(*agent, "/current");
      Doc c(current.body);
      EXPECT_EQ(c.count("//AssetChanged[.='UNAVAILABLE']"), devices) << to_string(v);
      EXPECT_EQ(c.count("//AssetRemoved[.='UNAVAILABLE']"), devices) << to_string(v);
      expect_valid(current.body, "MTConnectStreams", v);
    }
  }
  auto bare = make_agent(test::cell_options(SchemaVersion::V2_0));
  core::ObservedDevice mill = test::mill();
  mill.interfaces.clear();
  bare->add_device(mill);
  const Response probe = get(*bare, "/probe");
  EXPECT_EQ(Doc(probe.body).count("//DataItem[@type='ASSET_REMOVED']"), 1u);
  expect_valid(probe.body, "MTConnectDevices", SchemaVersion::V2_0);
}

TEST(ReferenceAgent, ProbeBeforeAnyDeviceValidates) {
  for (const SchemaVersion v :
       {SchemaVersion::V1_3, SchemaVersion::V1_6, SchemaVersion::V1_8, SchemaVersion::V2_0}) {
    auto agent = make_agent(test::cell_options(v));
    const Response probe = get(*agent, "/probe");
    EXPECT_EQ(probe.status, 200);
    expect_valid(probe.body, "MTConnectDevices", v);
    // The stand-in has no data items: nothing streams that probe lacks.
    EXPECT_EQ(Doc(probe.body).count("//DataItem"), 0u);
    expect_valid(get(*agent, "/current").body, "MTConnectStreams", v);
    agent->add_device(test::mill());  // a real device replaces the stand-in
    Doc after(get(*agent, "/probe").body);
    EXPECT_EQ(after.count("//Device"), 1u);
    EXPECT_EQ(after.text("//Device/@name"), "mill");
  }
}

TEST(ReferenceAgent, CreationTimeIsTheResponseTimeEvenFromTheCache) {
  auto agent = test::announced_cell();
  const std::vector<std::string> targets{"/current", "/probe", "/current?format=json",
                                         "/robot/probe"};
  std::vector<std::string> first;
  first.reserve(targets.size());
  for (const std::string& t : targets) first.push_back(get(*agent, t).body);  // cached now
  // Polls the clock (at most a second) until its second turns.
  using std::chrono::floor;
  using std::chrono::seconds;
  using std::chrono::system_clock;
  const auto rendered = floor<seconds>(system_clock::now());
  while (floor<seconds>(system_clock::now()) == rendered) std::this_thread::yield();
  for (std::size_t i = 0; i < targets.size(); ++i) {
    const std::string again = get(*agent, targets[i]).body;
    EXPECT_NE(test::creation_time(again), test::creation_time(first[i])) << targets[i];
    EXPECT_FALSE(test::creation_time(again).empty()) << targets[i];
    // The same document otherwise: served from the cache.
    EXPECT_EQ(test::without_creation_time(again), test::without_creation_time(first[i]))
        << targets[i];
  }
}

}  // namespace
}  // namespace mtc::bridge
