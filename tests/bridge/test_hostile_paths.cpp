// The `path` XPath filter under hostile input: an expression whose
// evaluation would take minutes (count() nested six deep over //*) is
// refused before pugixml runs it, in microseconds; so are those too long,
// too deeply nested or calling what XPath does not define. The paths
// MTConnect clients use stay accepted, on the sample cell and on a model a
// hundred times its size.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "bridge_test_util.hpp"
#include "mtc/bridge/path_cost.hpp"

namespace mtc::bridge {
namespace {

using test::Doc;

// The adversarial review's request: six count() nested over //*.
constexpr const char* kSixDeep = "//*[count(//*[count(//*[count(//*[count(//*[count(//*)])])])])]";

std::unique_ptr<MtconnectAgent> file_agent() {
  AgentOptions o = test::cell_options();
  o.devices_file = test::devices_file("cell_1.6.xml");
  return make_agent(o);
}

// A Devices model about a hundred times the sample cell: 300 devices.
std::unique_ptr<MtconnectAgent> large_agent() {
  auto agent = make_agent(test::cell_options());
  for (int i = 0; i < 100; ++i) {
    for (core::ObservedDevice d : {test::mill(), test::robot(), test::feeder()}) {
      d.device_uuid += "-" + std::to_string(i);
      d.name += "-" + std::to_string(i);
      agent->add_device(d);
    }
  }
  return agent;
}

TEST(HostilePath, CountNestedSixDeepIsRefusedAtOnce) {
  auto agent = file_agent();
  const auto start = std::chrono::steady_clock::now();
  const Response r = test::get(*agent, std::string("/current?path=") + kSixDeep);
  const auto took = std::chrono::steady_clock::now() - start;
  EXPECT_EQ(r.status, 400);
  Doc d(r.body);
  EXPECT_EQ(d.text("//Error/@errorCode"), "INVALID_PATH");
  EXPECT_NE(d.text("//Error").find("nested deeper than 8"), std::string::npos) << r.body;
  // Generous (2 cores shared in CI): unguarded, this request runs minutes.
  EXPECT_LT(took, std::chrono::seconds(1));
  // A stream with it is refused too, instead of evaluating it per part.
  const Routed stream = agent->route("GET", std::string("/sample?interval=0&path=") + kSixDeep);
  EXPECT_FALSE(stream.stream.has_value());
  ASSERT_TRUE(stream.response.has_value());
  EXPECT_EQ(stream.response->status, 400);
}

TEST(HostilePath, ThePathsClientsUseAreAccepted) {
  for (const bool large : {false, true}) {
    SCOPED_TRACE(large ? "large model" : "sample cell");
    auto agent = large ? large_agent() : file_agent();
    for (const char* path :
         {"//DataItem[@type='DOOR_STATE']", "//DoorInterface",
          "//Device[@name='robot']//DataItem[@subType='REQUEST']",
          "//DataItem[@category='EVENT' and (@type='OPEN_DOOR' or @type='CLOSE_DOOR')]",
          "//Components/Interfaces//DataItem", "//*[@type='AVAILABILITY']",
          "/MTConnectDevices/Devices/Device/DataItems/DataItem", "//DataItem[contains(@id,'door')]",
          "//Interfaces/*[1]", "//DoorInterface | //Device",
          "//DataItem[starts-with(@type, 'MATERIAL')][last()]"}) {
      const Response r = test::get(*agent, std::string("/current?path=") + path);
      // An empty selection (the large model has no device named robot) is
      // a 400 too, but not a refusal.
      EXPECT_EQ(Doc(r.body).text("//Error").find("not accepted"), std::string::npos) << path << "\n"
                                                                                     << r.body;
    }
  }
}

TEST(HostilePath, OverTheLimitsIsRefusedWithTheReason) {
  auto agent = file_agent();
  auto error_of = [&](const std::string& path) {
    return Doc(test::get(*agent, "/current?path=" + path).body).text("//Error");
  };
  EXPECT_NE(error_of(std::string(2000, '/') + "DataItem").find("longer than 1024"),
            std::string::npos);
  EXPECT_NE(error_of("//DataItem[((((((((((@id))))))))))]").find("nested deeper than 8"),
            std::string::npos);
  EXPECT_NE(error_of("//DataItem[@id=$x]").find("variables"), std::string::npos);
  EXPECT_NE(error_of("//DataItem[id('x')]").find("'id()'"), std::string::npos);
  EXPECT_NE(error_of("//DataItem[system('x')]").find("'system()'"), std::string::npos);
  EXPECT_NE(error_of("//DataItem[@id='x").find("unterminated"), std::string::npos);
  // Quadratic shapes that are cheap on the cell stay allowed, cubic ones
  // over //* do not.
  EXPECT_EQ(error_of("//*[count(//*) > 1]"), "");
  EXPECT_NE(error_of("//*[count(//*[count(//*) > 1]) > 1]").find("could visit"), std::string::npos);
  EXPECT_NE(error_of("//*[. = //*]").find("could visit"), std::string::npos);
  EXPECT_NE(error_of("//*[following::*[preceding::*]]").find("could visit"), std::string::npos);
}

// The estimate is an upper bound built from the tree's shape: more nodes of
// a name mean a larger estimate, a name the tree lacks means no predicate
// work at all.
TEST(HostilePath, TheEstimateFollowsTheTreeShape) {
  TreeShape shape;
  shape.nodes = 1000;
  shape.elements = 500;
  shape.attributes = 1500;
  shape.max_children = 20;
  shape.max_attributes = 5;
  shape.height = 10;
  shape.text_bytes = 20000;
  shape.max_attribute_bytes = 40;
  shape.element_names = {{"DataItem", 300}, {"Device", 3}};
  shape.attribute_names = {{"id", 500}, {"type", 300}};
  PathLimits limits;
  limits.max_nesting = 32;  // the cost alone must refuse kSixDeep
  const auto cost = [&](const char* path) {
    const PathCost c = estimate_path_cost(path, shape, limits);
    EXPECT_TRUE(c.accepted) << path << ": " << c.error;
    return c.visits;
  };
  EXPECT_LT(cost("//Device[@name='x']"), cost("//DataItem[@name='x']"));
  EXPECT_LT(cost("//Nothing[count(//*) > 0]"), cost("//Device[count(//*) > 0]"));
  EXPECT_LT(cost("//DataItem"), cost("//DataItem[@type='X']"));
  EXPECT_GE(cost("//*"), 1000.0);  // every node may be walked
  const PathCost refused = estimate_path_cost(kSixDeep, shape, limits);
  EXPECT_FALSE(refused.accepted);
  EXPECT_GT(refused.visits, 1e15);
  EXPECT_NE(refused.error.find("could visit up to"), std::string::npos) << refused.error;
}

}  // namespace
}  // namespace mtc::bridge
