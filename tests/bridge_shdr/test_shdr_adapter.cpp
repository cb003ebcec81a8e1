// The bridge as an SHDR adapter, with the test as the MTConnect agent:
// connect, read the initial dump, see a transition as a line, PING/PONG,
// disconnect and reconnect, comms loss as UNAVAILABLE, several agents, a
// slow agent dropped rather than queued for.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "bridge_test_util.hpp"
#include "line_client.hpp"
#include "mtc/bridge/shdr_adapter.hpp"

namespace mtc::bridge {
namespace {

using namespace std::chrono_literals;
constexpr std::int64_t kT0 = 1'700'000'000'000'000'000;  // 2023-11-14T22:13:20Z

using AgentSide = mtc::test::LineClient;  // the MTConnect agent's end

struct Fixture {
  std::shared_ptr<MtconnectAgent> agent;
  std::unique_ptr<ShdrAdapter> adapter;

  explicit Fixture(std::size_t buffer = 1024, std::chrono::milliseconds heartbeat = 10000ms) {
    agent = std::shared_ptr<MtconnectAgent>(test::announced_cell(SchemaVersion::V1_6, buffer));
    ShdrOptions o;
    o.port = 0;
    o.heartbeat = heartbeat;
    o.batch = 64;
    adapter = std::make_unique<ShdrAdapter>(agent, o);
    adapter->start();
  }
};

core::ObservedValue load(core::InteractionState state) {
  return test::value("mill-0001", "mill.material_load.req", state, kT0);
}

TEST(ShdrAdapter, FormatsLinesAsAgentsReadThem) {
  ItemObservation o{1, kT0, "mill.door.door_state", "CLOSED", false};
  EXPECT_EQ(shdr_line(o), "2023-11-14T22:13:20.000000Z|mill.door.door_state|CLOSED\n");
  o.value = "A|B\nC";
  EXPECT_EQ(shdr_line(o), "2023-11-14T22:13:20.000000Z|mill.door.door_state|A B C\n");
  ItemObservation c{2, kT0, "system", "UNAVAILABLE", true};
  EXPECT_EQ(shdr_line(c), "2023-11-14T22:13:20.000000Z|system|UNAVAILABLE||||\n");
}

TEST(ShdrAdapter, ListensOnLoopbackByDefault) {
  EXPECT_EQ(ShdrOptions{}.bind_address, "127.0.0.1");
  EXPECT_EQ(ShdrOptions{}.port, 7878);
}

TEST(ShdrAdapter, SendsTheFullStateThenEachChangeAsALine) {
  Fixture f;
  AgentSide agent(f.adapter->port());
  ASSERT_TRUE(agent.connected());
  const std::vector<std::string> dump = agent.lines_until_quiet();
  std::uint64_t next = 0;
  EXPECT_EQ(dump.size(), f.agent->latest_observations(next).size());
  bool saw_load = false;
  for (const std::string& l : dump) {
    ASSERT_EQ(l.find('|'), 27u) << l;  // timestamp|item|value
    if (l.substr(28) == "mill.material_load.req|UNAVAILABLE") saw_load = true;
  }
  EXPECT_TRUE(saw_load);
  f.agent->add_value(load(core::InteractionState::Ready));
  const auto line = agent.line_with("mill.material_load.req");
  ASSERT_TRUE(line);
  EXPECT_EQ(line->substr(27), "|mill.material_load.req|READY");
  EXPECT_EQ(line->substr(0, 27), "2023-11-14T22:13:20.000000Z");
}

TEST(ShdrAdapter, AnswersPingWithPongAndTheHeartbeat) {
  Fixture f(1024, 2500ms);
  AgentSide agent(f.adapter->port());
  agent.lines_until_quiet();
  agent.send("* PING\n");
  EXPECT_EQ(agent.line(), "* PONG 2500");
  agent.send("* PING\r\n");
  EXPECT_EQ(agent.line(), "* PONG 2500");
  EXPECT_EQ(f.adapter->stats().pongs, 2u);
}

TEST(ShdrAdapter, CommsLossReadsUnavailable) {
  Fixture f;
  AgentSide agent(f.adapter->port());
  f.agent->add_value(load(core::InteractionState::Ready));
  ASSERT_TRUE(agent.line_with("mill.material_load.req|READY"));
  f.agent->device_lost("mill-0001");
  const std::vector<std::string> lines = agent.lines_until_quiet();
  auto has = [&](const std::string& tail) {
    return std::any_of(lines.begin(), lines.end(), [&](const std::string& l) {
      return l.size() > tail.size() && l.compare(l.size() - tail.size(), tail.size(), tail) == 0;
    });
  };
  EXPECT_TRUE(has("|mill.material_load.req|UNAVAILABLE"));
  EXPECT_TRUE(has("|mill_avail|UNAVAILABLE"));
  EXPECT_FALSE(has("|robot_avail|UNAVAILABLE"));  // only the lost device
}

TEST(ShdrAdapter, ServesSeveralAgentsAndAReconnect) {
  Fixture f;
  auto first = std::make_unique<AgentSide>(f.adapter->port());
  AgentSide second(f.adapter->port());
  first->lines_until_quiet();
  second.lines_until_quiet();
  EXPECT_EQ(f.adapter->connection_count(), 2u);
  f.agent->add_value(load(core::InteractionState::Active));
  EXPECT_TRUE(first->line_with("|ACTIVE"));
  EXPECT_TRUE(second.line_with("|ACTIVE"));
  first.reset();  // the agent goes away ...
  f.agent->add_value(load(core::InteractionState::Complete));
  EXPECT_TRUE(second.line_with("|COMPLETE"));
  AgentSide again(f.adapter->port());  // ... and comes back: the state again
  const auto state = again.line_with("mill.material_load.req");
  ASSERT_TRUE(state);
  EXPECT_NE(state->find("|COMPLETE"), std::string::npos) << *state;
  EXPECT_EQ(f.adapter->stats().connections, 3u);
}

TEST(ShdrAdapter, ASlowAgentIsDroppedNotQueuedFor) {
  Fixture f(256);  // a small buffer: a reader that stops falls behind it fast
  AgentSide slow(f.adapter->port(), 4096);  // connects, then never reads
  ASSERT_TRUE(slow.connected());
  // Until the adapter gives up on it: the kernel's socket buffers (the
  // send side autotunes up to megabytes on loopback) absorb a varying part
  // of the lines first, so no fixed count is sure to overflow the adapter's
  // own buffer. The cap is far beyond them; an adapter that queued for the
  // slow agent instead would reach it and fail.
  constexpr int kCap = 2'000'000;
  for (int i = 0; i < kCap && f.adapter->stats().dropped == 0; ++i) {
    f.agent->add_value(
        load(i % 2 != 0 ? core::InteractionState::Ready : core::InteractionState::Active));
  }
  EXPECT_GE(f.adapter->stats().dropped, 1u);
  EXPECT_TRUE(slow.closed_by_peer(10s));
  // A new connection (the agent reconnecting) gets the state again.
  AgentSide again(f.adapter->port());
  EXPECT_TRUE(again.line_with("mill.material_load.req|"));
}

}  // namespace
}  // namespace mtc::bridge
