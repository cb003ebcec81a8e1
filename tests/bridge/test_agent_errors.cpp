// Bad requests become MTConnectError documents with the right code and HTTP
// status; garbage never crashes and never streams.
#include <gtest/gtest.h>

#include <random>

#include "../support/param_name.hpp"
#include "bridge_test_util.hpp"

namespace mtc::bridge {
namespace {

using test::Doc;

struct BadRequest {
  const char* target;
  int status;
  const char* code;
};

// What gtest lists for the parameter (see param_name.hpp).
void PrintTo(const BadRequest& p, std::ostream* os) {
  *os << mtc::test::printable(p.target);
}

class AgentErrors : public ::testing::TestWithParam<BadRequest> {
 protected:
  static void SetUpTestSuite() { agent_ = test::announced_cell(SchemaVersion::V1_6, 64).release(); }
  static void TearDownTestSuite() {
    delete agent_;
    agent_ = nullptr;
  }
  static MtconnectAgent* agent_;
};
MtconnectAgent* AgentErrors::agent_ = nullptr;

TEST_P(AgentErrors, AnswerWithErrorDocument) {
  const BadRequest& bad = GetParam();
  const Routed r = agent_->route("GET", bad.target);
  ASSERT_TRUE(r.response.has_value()) << bad.target;
  EXPECT_FALSE(r.stream.has_value());
  EXPECT_EQ(r.response->status, bad.status) << bad.target;
  Doc d(r.response->body);
  ASSERT_TRUE(d.ok) << r.response->body;
  EXPECT_EQ(d.count("/MTConnectError/Errors/Error"), 1u);
  EXPECT_EQ(d.text("//Error/@errorCode"), bad.code) << bad.target;
  EXPECT_FALSE(d.text("//Error").empty());
}

INSTANTIATE_TEST_SUITE_P(
    Table, AgentErrors,
    ::testing::Values(BadRequest{"/nosuchdevice/current", 404, "NO_DEVICE"},
                      BadRequest{"/nosuchdevice", 404, "NO_DEVICE"},
                      BadRequest{"/mill/bogus", 404, "INVALID_URI"},
                      BadRequest{"/a/b/c", 404, "INVALID_URI"}, BadRequest{"", 400, "INVALID_URI"},
                      BadRequest{"current", 400, "INVALID_URI"},
                      BadRequest{"/current%zz", 400, "INVALID_URI"},
                      BadRequest{"/current?path=%", 400, "INVALID_URI"},
                      BadRequest{"/cur%00rent", 400, "INVALID_URI"},
                      BadRequest{"/sample?from=abc", 400, "INVALID_REQUEST"},
                      BadRequest{"/sample?from=1.5", 400, "INVALID_REQUEST"},
                      BadRequest{"/sample?from=", 400, "INVALID_REQUEST"},
                      BadRequest{"/sample?from=+3", 400, "INVALID_REQUEST"},
                      BadRequest{"/sample?from=0x10", 400, "INVALID_REQUEST"},
                      BadRequest{"/sample?from=-1", 400, "OUT_OF_RANGE"},
                      BadRequest{"/sample?from=0", 400, "OUT_OF_RANGE"},
                      BadRequest{"/sample?from=999999", 400, "OUT_OF_RANGE"},
                      BadRequest{"/sample?from=99999999999999999999999", 400, "OUT_OF_RANGE"},
                      BadRequest{"/sample?count=0", 400, "OUT_OF_RANGE"},
                      BadRequest{"/sample?count=65", 400, "TOO_MANY"},
                      BadRequest{"/sample?count=-65", 400, "TOO_MANY"},
                      BadRequest{"/sample?count=ten", 400, "INVALID_REQUEST"},
                      BadRequest{"/sample?to=1", 400, "OUT_OF_RANGE"},
                      BadRequest{"/sample?from=5&to=5", 400, "OUT_OF_RANGE"},
                      BadRequest{"/sample?to=9999", 400, "OUT_OF_RANGE"},
                      BadRequest{"/sample?to=20&count=-2", 400, "OUT_OF_RANGE"},
                      BadRequest{"/sample?from=1&from=2", 400, "INVALID_REQUEST"},
                      BadRequest{"/sample?at=3", 400, "INVALID_REQUEST"},
                      BadRequest{"/current?from=3", 400, "INVALID_REQUEST"},
                      BadRequest{"/current?at=0", 400, "OUT_OF_RANGE"},
                      BadRequest{"/current?at=-4", 400, "OUT_OF_RANGE"},
                      BadRequest{"/current?at=100000", 400, "OUT_OF_RANGE"},
                      BadRequest{"/current?at=x", 400, "INVALID_REQUEST"},
                      BadRequest{"/current?at=3&interval=10", 400, "INVALID_REQUEST"},
                      BadRequest{"/sample?interval=-1", 400, "OUT_OF_RANGE"},
                      BadRequest{"/sample?interval=abc", 400, "INVALID_REQUEST"},
                      BadRequest{"/sample?interval=10&heartbeat=0", 400, "OUT_OF_RANGE"},
                      BadRequest{"/sample?interval=10&to=3", 400, "INVALID_REQUEST"},
                      BadRequest{"/sample?interval=10&path=//Nothing", 400, "INVALID_PATH"},
                      BadRequest{"/current?path=//DataItem[", 400, "INVALID_PATH"},
                      BadRequest{"/current?path=1%2B1", 400, "INVALID_PATH"},
                      BadRequest{"/current?path=", 400, "INVALID_PATH"},
                      BadRequest{"/current?pretty=maybe", 400, "INVALID_REQUEST"},
                      BadRequest{"/asset/A1", 404, "ASSET_NOT_FOUND"}),
    [](const ::testing::TestParamInfo<BadRequest>& param_info) {
      return mtc::test::param_name(param_info.index, param_info.param.target);
    });

TEST(AgentErrorsMisc, DevicePathScopesTheXPath) {
  auto agent = test::announced_cell();
  // The robot's items are not the mill's: nothing selected.
  const Response r = test::get(*agent, "/mill/current?path=//Device[@name='robot']");
  EXPECT_EQ(r.status, 400);
  EXPECT_EQ(Doc(r.body).text("//Error/@errorCode"), "INVALID_PATH");
}

TEST(AgentErrorsMisc, OtherMethodsAreUnsupported) {
  auto agent = test::announced_cell();
  for (const char* method : {"POST", "PUT", "DELETE", "PATCH", "", "get"}) {
    const Routed r = agent->route(method, "/current");
    ASSERT_TRUE(r.response.has_value());
    EXPECT_EQ(r.response->status, 405) << method;
    EXPECT_EQ(Doc(r.response->body).text("//Error/@errorCode"), "UNSUPPORTED");
  }
  EXPECT_EQ(agent->route("HEAD", "/current").response->status, 200);
}

TEST(AgentErrorsMisc, RandomGarbageNeverCrashes) {
  auto agent = test::announced_cell(SchemaVersion::V1_6, 32);
  std::mt19937 rng(1234);
  const std::string alphabet = "/?&=%[]'\"@:.*-_09azAZ \x01\xff#+";
  const char* seeds[] = {"/sample?", "/current?path=", "/mill/", "/", "/probe?", "/sample?count="};
  for (int i = 0; i < 3000; ++i) {
    std::string target = seeds[rng() % 6];
    const std::size_t len = rng() % 40;
    for (std::size_t k = 0; k < len; ++k) target.push_back(alphabet[rng() % alphabet.size()]);
    const Routed r = agent->route("GET", target);
    ASSERT_TRUE(r.response || r.stream) << target;
    if (r.response) {
      EXPECT_TRUE(Doc(r.response->body).ok) << target;
      EXPECT_TRUE(r.response->status == 200 || r.response->status == 400 ||
                  r.response->status == 404)
          << target << " -> " << r.response->status;
    }
  }
  std::string huge(20000, 'a');
  EXPECT_EQ(agent->route("GET", "/" + huge).response->status, 400);
}

}  // namespace
}  // namespace mtc::bridge
