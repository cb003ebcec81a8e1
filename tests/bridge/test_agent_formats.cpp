// What a request's format asks for (issue 12): the live page at `/` for
// browsers and the probe for every other client, the page's files, and
// MTConnect JSON (format=json or Accept: application/json) for documents,
// streams and errors alike. The JSON's structure against the XML of the
// same request: tests/web/check_json_documents.py, over a running cell.
#include <gtest/gtest.h>

#include "bridge_test_util.hpp"

namespace mtc::bridge {
namespace {

using test::Doc;

constexpr std::int64_t kT0 = 1'700'000'000'000'000'000;
constexpr const char* kBrowserAccept =
    "text/html,application/xhtml+xml,application/xml;q=0.9,image/avif,*/*;q=0.8";

Response get(Agent& agent, const std::string& target, const std::string& accept) {
  Routed r = agent.route(parse_request("GET", target, accept));
  if (!r.response) return Response{0, "", "<stream/>"};
  return *r.response;
}

bool starts_with(const std::string& text, const std::string& prefix) {
  return text.compare(0, prefix.size(), prefix) == 0;
}

TEST(AgentFormats, RootServesThePageToBrowsersOnly) {
  auto agent = test::announced_cell();
  const Response page = get(*agent, "/", kBrowserAccept);
  EXPECT_EQ(page.status, 200);
  EXPECT_EQ(page.content_type, "text/html; charset=utf-8");
  EXPECT_NE(page.body.find("<script src=\"web/app.js\">"), std::string::npos) << page.body;
  // Clients of the reference agent get the probe at `/`, as there.
  for (const char* accept : {"", "*/*", "text/xml", "application/xml"}) {
    const Response probe = get(*agent, "/", accept);
    EXPECT_EQ(probe.content_type, "text/xml") << accept;
    EXPECT_EQ(Doc(probe.body).count("//Devices/Device"), 3u) << accept;
  }
  // A browser that names a format gets that format.
  EXPECT_EQ(get(*agent, "/?format=xml", kBrowserAccept).content_type, "text/xml");
  EXPECT_EQ(get(*agent, "/?format=json", kBrowserAccept).content_type, "application/json");
  // Only `/`: /probe stays a probe for a browser too.
  EXPECT_EQ(get(*agent, "/probe", kBrowserAccept).content_type, "text/xml");
}

TEST(AgentFormats, ThePagesFilesAreCompiledIn) {
  auto agent = test::announced_cell();
  const Response js = get(*agent, "/web/app.js", "");
  EXPECT_EQ(js.status, 200);
  EXPECT_EQ(js.content_type, "text/javascript; charset=utf-8");
  EXPECT_NE(js.body.find("format=json"), std::string::npos);
  const Response css = get(*agent, "/web/style.css", "");
  EXPECT_EQ(css.content_type, "text/css; charset=utf-8");
  EXPECT_FALSE(css.body.empty());
  const Response missing = get(*agent, "/web/nothing.js", "");
  EXPECT_EQ(missing.status, 404);
  EXPECT_EQ(Doc(missing.body).text("//Error/@errorCode"), "INVALID_URI");
}

TEST(AgentFormats, ADeviceNamedWebKeepsItsRoutes) {
  auto agent = test::announced_cell();
  core::ObservedDevice web = test::feeder();
  web.device_uuid = "web-0001";
  web.name = "web";
  agent->add_device(web);
  const Response probe = get(*agent, "/web/probe", "");
  EXPECT_EQ(probe.status, 200);
  EXPECT_EQ(Doc(probe.body).text("//Devices/Device/@name"), "web");
}

TEST(AgentFormats, JsonByParameterOrAcceptHeader) {
  auto agent = test::announced_cell();
  for (const char* target : {"/probe", "/current", "/sample", "/assets", "/mill/current"}) {
    const Response by_param = get(*agent, std::string(target) + "?format=json", "");
    EXPECT_EQ(by_param.status, 200) << target << by_param.body;
    EXPECT_EQ(by_param.content_type, "application/json") << target;
    EXPECT_TRUE(starts_with(by_param.body, "{\"MTConnect")) << by_param.body;
    const Response by_accept = get(*agent, target, "application/json");
    EXPECT_EQ(by_accept.content_type, "application/json") << target;
    // format= wins over Accept, as in the reference agent.
    EXPECT_EQ(get(*agent, std::string(target) + "?format=xml", "application/json").content_type,
              "text/xml");
  }
  const std::string probe = get(*agent, "/probe?format=json", "").body;
  EXPECT_TRUE(
      starts_with(probe, "{\"MTConnectDevices\":{\"jsonVersion\":2,\"schemaVersion\":\"1.6\""))
      << probe;
  EXPECT_NE(probe.find("\"DataItems\":{\"DataItem\":["), std::string::npos) << probe;
}

TEST(AgentFormats, JsonObservationsCarryNumbersWhereTheReferenceAgentDoes) {
  auto agent = test::announced_cell();
  agent->add_value(
      test::value("mill-0001", "mill.material_load.req", core::InteractionState::Active, kT0));
  const std::string body = get(*agent, "/mill/current?format=json", "").body;
  EXPECT_NE(body.find("\"Streams\":{\"DeviceStream\":[{\"name\":\"mill\",\"uuid\":\"mill-0001\""),
            std::string::npos)
      << body;
  EXPECT_NE(body.find("\"MaterialLoad\":[{\"dataItemId\":\"mill.material_load.req\""),
            std::string::npos)
      << body;
  EXPECT_NE(body.find("\"subType\":\"REQUEST\",\"value\":\"ACTIVE\"}"), std::string::npos) << body;
  EXPECT_NE(body.find("\"instanceId\":42,"), std::string::npos) << body;
}

TEST(AgentFormats, ErrorsComeInTheFormatAskedFor) {
  auto agent = test::announced_cell();
  const Response no_device = get(*agent, "/nothing/current?format=json", "");
  EXPECT_EQ(no_device.status, 404);
  EXPECT_EQ(no_device.content_type, "application/json");
  EXPECT_NE(no_device.body.find("\"errorCode\":\"NO_DEVICE\""), std::string::npos)
      << no_device.body;
  const Response zero = get(*agent, "/sample?count=0", "application/json");
  EXPECT_EQ(zero.status, 400);
  EXPECT_NE(zero.body.find("{\"MTConnectError\":{\"jsonVersion\":2,\"Header\":"), std::string::npos)
      << zero.body;
  EXPECT_NE(zero.body.find("\"Errors\":{\"Error\":[{\"errorCode\":\"OUT_OF_RANGE\""),
            std::string::npos)
      << zero.body;
  const Response bad = get(*agent, "/probe?format=yaml", "");
  EXPECT_EQ(bad.status, 400);
  EXPECT_EQ(Doc(bad.body).text("//Error/@errorCode"), "INVALID_REQUEST");
  // Quotes and control characters of a request end up escaped (those XML
  // forbids were replaced by U+FFFD already).
  const Response quoted = get(*agent, "/a%22b%09c%01/current?format=json", "");
  EXPECT_NE(quoted.body.find("a\\\"b\\tc\xEF\xBF\xBD'"), std::string::npos) << quoted.body;
}

TEST(AgentFormats, JsonStreamsKeepTheirFormatForEveryPart) {
  auto agent = test::announced_cell();
  Routed routed = agent->route(parse_request("GET", "/sample?interval=0&format=json"));
  ASSERT_TRUE(routed.stream);
  const Response part = agent->next_part(*routed.stream);
  EXPECT_EQ(part.content_type, "application/json");
  EXPECT_TRUE(starts_with(part.body, "{\"MTConnectStreams\"")) << part.body;
}

}  // namespace
}  // namespace mtc::bridge
