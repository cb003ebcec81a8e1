// Stream parts are rendered once per query and position and shared among
// streams (a thousand clients of one /sample?interval=0 cost one render per
// change): a shared part must be exactly the part the stream would have got
// on its own, never one from before a change, never one of another query,
// and the memory they hold stays bounded whatever the clients ask.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "bridge_test_util.hpp"

namespace mtc::bridge {
namespace {

using test::Doc;
using test::value;

constexpr std::int64_t kT0 = 1'700'000'000'000'000'000;

StreamPlan plan_for(Agent& agent, const std::string& target) {
  Routed r = agent.route("GET", target);
  if (!r.stream) throw std::runtime_error("not a stream: " + target);
  return *r.stream;
}

core::ObservedValue load(int i) {
  return value("mill-0001", "mill.material_load.req",
               i % 2 != 0 ? core::InteractionState::Active : core::InteractionState::Ready,
               kT0 + i);
}

TEST(AgentSharedParts, StreamsAtOnePositionShareOneRendering) {
  auto agent = test::announced_cell();
  const std::string target = "/sample?interval=0&from=" + std::to_string(agent->next_sequence());
  agent->add_value(load(1));
  std::vector<StreamPlan> plans(5, plan_for(*agent, target));
  const AgentStats before = agent->stats();
  std::vector<Response> parts;
  parts.reserve(plans.size());
  for (StreamPlan& plan : plans) parts.push_back(agent->next_part(plan));
  const AgentStats after = agent->stats();
  EXPECT_EQ(after.stream_parts_rendered - before.stream_parts_rendered, 1u);
  EXPECT_EQ(after.stream_parts_shared - before.stream_parts_shared, 4u);
  for (std::size_t i = 0; i < parts.size(); ++i) {
    ASSERT_EQ(parts[i].status, 200);
    EXPECT_EQ(test::without_creation_time(parts[i].body),
              test::without_creation_time(parts[0].body));
    EXPECT_EQ(plans[i].next_sequence, plans[0].next_sequence);
  }
  EXPECT_EQ(Doc(parts[0].body).text("//MaterialLoad"), "ACTIVE");
}

TEST(AgentSharedParts, NewObservationIsInTheVeryNextPart) {
  auto agent = test::announced_cell();
  const std::string target = "/sample?interval=0&from=" + std::to_string(agent->next_sequence());
  StreamPlan a = plan_for(*agent, target);
  StreamPlan b = a;
  const Response empty = agent->next_part(a);  // renders the empty part at this position
  EXPECT_EQ(Doc(empty.body).count("//MaterialLoad"), 0u);
  agent->add_value(load(1));
  // b stands where a stood, but the buffer moved: no part from before.
  const Response fresh = agent->next_part(b);
  EXPECT_EQ(Doc(fresh.body).text("//MaterialLoad"), "ACTIVE");
  EXPECT_EQ(b.next_sequence, agent->next_sequence());
  // a goes on from the empty part and gets the same observation.
  EXPECT_EQ(Doc(agent->next_part(a).body).text("//MaterialLoad"), "ACTIVE");
}

TEST(AgentSharedParts, EachQueryGetsItsOwnPart) {
  auto agent = test::announced_cell();
  const std::string from = std::to_string(agent->next_sequence());
  agent->add_value(load(1));
  agent->add_value(value("mill-0001", "mill.door.door_state", core::DoorState::Open, kT0 + 2));
  StreamPlan all = plan_for(*agent, "/sample?interval=0&from=" + from);
  StreamPlan doors = plan_for(*agent, "/sample?interval=0&path=//DoorInterface&from=" + from);
  StreamPlan robot = plan_for(*agent, "/robot/sample?interval=0&from=" + from);
  StreamPlan one = plan_for(*agent, "/sample?interval=0&count=1&from=" + from);
  StreamPlan json = plan_for(*agent, "/sample?interval=0&format=json&from=" + from);
  const Doc d_all(agent->next_part(all).body);
  const Doc d_doors(agent->next_part(doors).body);
  const Doc d_robot(agent->next_part(robot).body);
  const Doc d_one(agent->next_part(one).body);
  const Response r_json = agent->next_part(json);
  EXPECT_EQ(d_all.count("//MaterialLoad"), 1u);
  EXPECT_EQ(d_all.count("//DoorState"), 1u);
  EXPECT_EQ(d_doors.count("//MaterialLoad"), 0u);
  EXPECT_EQ(d_doors.count("//DoorState"), 1u);
  EXPECT_EQ(d_robot.count("//DeviceStream[@name='mill']"), 0u);
  EXPECT_EQ(d_one.count("//MaterialLoad") + d_one.count("//DoorState"), 1u);
  EXPECT_EQ(one.next_sequence + 1, all.next_sequence);
  EXPECT_EQ(r_json.content_type, "application/json");
  EXPECT_EQ(r_json.body.front(), '{');
}

TEST(AgentSharedParts, SharedPartsHaveTheResponseTimeAsCreationTime) {
  auto agent = test::announced_cell();
  const std::string target = "/sample?interval=0&from=" + std::to_string(agent->next_sequence());
  StreamPlan a = plan_for(*agent, target);
  StreamPlan b = a;
  const std::string first = agent->next_part(a).body;
  // A heartbeat part may be served long after the first rendering at its
  // position. Polls the clock (at most a second) until its second turns.
  using std::chrono::floor;
  using std::chrono::seconds;
  using std::chrono::system_clock;
  const auto rendered = floor<seconds>(system_clock::now());
  while (floor<seconds>(system_clock::now()) == rendered) std::this_thread::yield();
  const std::uint64_t shared = agent->stats().stream_parts_shared;
  const std::string again = agent->next_part(b).body;
  EXPECT_EQ(agent->stats().stream_parts_shared, shared + 1);
  EXPECT_NE(test::creation_time(again), test::creation_time(first));
  EXPECT_EQ(test::without_creation_time(again), test::without_creation_time(first));
}

TEST(AgentSharedParts, MemoryIsBoundedWhateverTheQueries) {
  auto agent = test::announced_cell(SchemaVersion::V1_6, 4096);
  for (int i = 0; i < 400; ++i) agent->add_value(load(i));
  const std::string from = "1";  // nothing overwritten yet in 4,096
  // 1,000 distinct queries at one position: each a part of up to ~100
  // observations.
  for (int count = 1; count <= 1000; ++count) {
    StreamPlan p =
        plan_for(*agent, "/sample?interval=0&from=" + from + "&count=" + std::to_string(count));
    ASSERT_EQ(agent->next_part(p).status, 200);
  }
  const AgentStats s = agent->stats();
  EXPECT_LE(s.shared_part_bytes, std::size_t{4} << 20);
  EXPECT_GT(s.shared_part_bytes, 0u);
  // A change empties the cache: what it held can never be served again.
  agent->add_value(load(400));  // differs from load(399): appended
  StreamPlan p = plan_for(*agent, "/sample?interval=0&from=" + from + "&count=1");
  ASSERT_EQ(agent->next_part(p).status, 200);
  EXPECT_LT(agent->stats().shared_part_bytes, std::size_t{4} << 10);
}

}  // namespace
}  // namespace mtc::bridge
