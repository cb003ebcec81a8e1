// The agent's side of the Agent contract beyond single documents: errors the
// HTTP front finds itself, printed by the agent, and the defaults the
// agent's options give requests that name none.
#include <gtest/gtest.h>

#include "bridge_test_util.hpp"

namespace mtc::bridge {
namespace {

using test::Doc;
using namespace std::chrono_literals;

constexpr std::int64_t kT0 = 1'700'000'000'000'000'000;

std::unique_ptr<MtconnectAgent> cell_with(const AgentOptions& options) {
  auto agent = make_agent(options);
  agent->add_device(test::mill());
  agent->add_device(test::robot());
  agent->add_device(test::feeder());
  return agent;
}

void feed(MtconnectAgent& agent, int values) {
  for (int i = 0; i < values; ++i) {
    agent.add_value(test::value(
        "mill-0001", "mill.material_load.req",
        i % 2 ? core::InteractionState::Active : core::InteractionState::Ready, kT0 + i));
  }
}

TEST(AgentContract, ErrorDocumentsForTheFrontEndCarryTheAgentsHeader) {
  auto agent = test::announced_cell(SchemaVersion::V1_6, 64);
  const Response r = agent->error_document(431, "INVALID_REQUEST", "header too large");
  EXPECT_EQ(r.status, 431);
  EXPECT_EQ(r.content_type, "text/xml");
  Doc d(r.body);
  ASSERT_TRUE(d.ok) << r.body;
  EXPECT_EQ(d.text("/MTConnectError/Errors/Error/@errorCode"), "INVALID_REQUEST");
  EXPECT_EQ(d.text("/MTConnectError/Errors/Error"), "header too large");
  EXPECT_EQ(d.text("/MTConnectError/Header/@instanceId"), "42");
  EXPECT_EQ(d.text("/MTConnectError/Header/@bufferSize"), "64");
  EXPECT_EQ(d.text("/MTConnectError/Header/@sender"), "mtc-bridge");
}

TEST(AgentDefaults, ConfiguredStreamHeartbeatAppliesOnlyWhenTheRequestNamesNone) {
  AgentOptions options = test::cell_options();
  options.stream_heartbeat = 250ms;
  auto agent = cell_with(options);
  const Routed defaulted = agent->route("GET", "/sample?interval=0");
  ASSERT_TRUE(defaulted.stream);
  EXPECT_EQ(defaulted.stream->heartbeat, 250ms);
  const Routed current = agent->route("GET", "/mill/current?interval=100");
  ASSERT_TRUE(current.stream);
  EXPECT_EQ(current.stream->heartbeat, 250ms);
  const Routed named = agent->route("GET", "/sample?interval=0&heartbeat=60000");
  ASSERT_TRUE(named.stream);
  EXPECT_EQ(named.stream->heartbeat, 60000ms);
}

TEST(AgentDefaults, ConfiguredCountAppliesOnlyWhenTheRequestNamesNone) {
  AgentOptions options = test::cell_options();
  options.default_count = 3;
  auto agent = cell_with(options);
  feed(*agent, 10);
  const std::string from = "/sample?from=" + std::to_string(agent->next_sequence() - 10);
  EXPECT_EQ(Doc(test::get(*agent, from).body).count("//MaterialLoad"), 3u);
  EXPECT_EQ(Doc(test::get(*agent, from + "&count=5").body).count("//MaterialLoad"), 5u);
}

TEST(AgentDefaults, DefaultCountNeverExceedsTheBuffer) {
  AgentOptions options = test::cell_options(SchemaVersion::V1_6, 8);
  options.default_count = 100;
  auto agent = cell_with(options);
  feed(*agent, 20);
  const Response r = test::get(*agent, "/sample");
  EXPECT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(Doc(r.body).count("//*[@sequence]"), 8u);
}

TEST(AgentDefaults, UnusableDefaultsAreRefused) {
  AgentOptions no_count = test::cell_options();
  no_count.default_count = 0;
  EXPECT_THROW(make_agent(no_count), std::invalid_argument);
  AgentOptions no_heartbeat = test::cell_options();
  no_heartbeat.stream_heartbeat = 0ms;
  EXPECT_THROW(make_agent(no_heartbeat), std::invalid_argument);
}

}  // namespace
}  // namespace mtc::bridge
