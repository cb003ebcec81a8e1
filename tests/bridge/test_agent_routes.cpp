// The agent's route table and its side of the Agent contract beyond single
// documents: how paths pick a route, how queries are read, errors the HTTP
// front finds itself, and the defaults the options give requests that name
// none.
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
        i % 2 != 0 ? core::InteractionState::Active : core::InteractionState::Ready, kT0 + i));
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

std::string code_of(MtconnectAgent& agent, const std::string& target) {
  const Response r = test::get(agent, target);
  return r.status == 200 ? "200"
                         : std::to_string(r.status) + " " + Doc(r.body).text("//Error/@errorCode");
}

TEST(AgentRoutes, LiteralSegmentsWinOverADeviceOfTheSameName) {
  auto agent = test::announced_cell();
  core::ObservedDevice probe = test::robot();
  probe.device_uuid = "probe-0001";
  probe.name = "probe";
  agent->add_device(probe);
  // "/probe" is the agent's probe (every device), not the device "probe".
  EXPECT_EQ(Doc(test::get(*agent, "/probe").body).count("//Devices/Device"), 4u);
  // Under a device placeholder the name still works.
  const Doc current(test::get(*agent, "/probe/current").body);
  EXPECT_EQ(current.count("//DeviceStream"), 1u);
  EXPECT_EQ(current.text("//DeviceStream/@name"), "probe");
}

TEST(AgentRoutes, TheTemplateThatExplainsMostOfThePathGivesTheError) {
  auto agent = test::announced_cell();
  EXPECT_EQ(code_of(*agent, "/nosuch"), "404 NO_DEVICE");
  EXPECT_EQ(code_of(*agent, "/nosuch/bogus"), "404 NO_DEVICE");
  EXPECT_EQ(code_of(*agent, "/mill/bogus"), "404 INVALID_URI");
  EXPECT_EQ(code_of(*agent, "/mill/current/x"), "404 INVALID_URI");
  EXPECT_EQ(code_of(*agent, "/assets/A1"), "404 ASSET_NOT_FOUND");
  EXPECT_EQ(code_of(*agent, "/mill/assets"), "200");
}

TEST(AgentRoutes, QueriesAreReadAsTheRouteDeclares) {
  auto agent = test::announced_cell();
  // Unknown parameters are ignored, but not given twice.
  EXPECT_EQ(code_of(*agent, "/current?foo=1"), "200");
  EXPECT_EQ(code_of(*agent, "/current?foo=1&foo=2"), "400 INVALID_REQUEST");
  // Another request's parameter is an error, even when well-formed.
  EXPECT_EQ(code_of(*agent, "/current?count=5"), "400 INVALID_REQUEST");
  EXPECT_EQ(code_of(*agent, "/probe?from=1"), "400 INVALID_REQUEST");
  // Types are checked before routes: an overflow is OUT_OF_RANGE anywhere.
  EXPECT_EQ(code_of(*agent, "/current?count=99999999999999999999"), "400 OUT_OF_RANGE");
  // probe and assets read their query as current does.
  EXPECT_EQ(code_of(*agent, "/probe?at=1&pretty=true"), "200");
  EXPECT_EQ(code_of(*agent, "/assets?interval=-1"), "400 OUT_OF_RANGE");
  // Asset ids are answered before any query is read.
  EXPECT_EQ(code_of(*agent, "/asset/A1?from=x"), "404 ASSET_NOT_FOUND");
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
