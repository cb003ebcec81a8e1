// Control characters and invalid UTF-8, from a request URL or from a device
// announced over DDS, never reach a document as they are: every document
// stays XML and validates against the official XSDs (xmllint), for good.
#include <gtest/gtest.h>

#include <string>

#include "bridge_test_util.hpp"
#include "mtc/bridge/xml_text.hpp"
#include "xmllint.hpp"

namespace mtc::bridge {
namespace {

using test::schema;
using test::value;
using test::xmllint;

constexpr std::int64_t kT0 = 1'700'000'000'000'000'000;
constexpr SchemaVersion kVersion = SchemaVersion::V1_6;

void expect_valid(const Response& r, const char* kind, const std::string& what) {
  const test::Lint lint = xmllint(r.body, schema(kind, kVersion));
  EXPECT_EQ(lint.exit_code, 0) << what << "\n" << lint.output << "\n" << r.body.substr(0, 2000);
}

TEST(XmlText, FindsAndReplacesWhatXmlForbids) {
  EXPECT_EQ(find_unfit_xml_char("plain ASCII\ttab\r\n"), std::string::npos);
  EXPECT_EQ(find_unfit_xml_char("caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x98\x80"), std::string::npos);
  EXPECT_EQ(find_unfit_xml_char("a\x01"), 1U);
  EXPECT_EQ(find_unfit_xml_char("ab\x7F"), std::string::npos);  // DEL is an XML Char
  EXPECT_EQ(find_unfit_xml_char("\xC0\xAF"), 0U);               // overlong '/'
  EXPECT_EQ(find_unfit_xml_char("x\xED\xA0\x80"), 1U);          // a surrogate
  EXPECT_EQ(find_unfit_xml_char("\xEF\xBF\xBE"), 0U);           // U+FFFE
  EXPECT_EQ(find_unfit_xml_char("\xF4\x90\x80\x80"), 0U);       // above U+10FFFF
  EXPECT_EQ(find_unfit_xml_char("abc\xE2\x82"), 3U);            // cut short
  EXPECT_EQ(make_xml_safe("ok"), "ok");
  EXPECT_EQ(make_xml_safe("a\x01z"), "a\xEF\xBF\xBDz");
  EXPECT_EQ(make_xml_safe("\xFF\xFEx"), "\xEF\xBF\xBD\xEF\xBF\xBDx");
  EXPECT_EQ(find_unfit_xml_char(make_xml_safe("\x02\xC3(\xED\xBF\xBF\x00z")), std::string::npos);
}

TEST(XmlText, DataItemTypesAreUpperCaseNames) {
  EXPECT_TRUE(is_data_item_type("MATERIAL_LOAD"));
  EXPECT_TRUE(is_data_item_type("x:BAR_FEED_2"));
  EXPECT_FALSE(is_data_item_type(""));
  EXPECT_FALSE(is_data_item_type("material_load"));
  EXPECT_FALSE(is_data_item_type("A<B"));
  EXPECT_FALSE(is_data_item_type("1ST"));
  EXPECT_FALSE(is_data_item_type(":FOO"));
  EXPECT_FALSE(is_data_item_type("x:"));
}

// Every error a hostile URL can provoke quotes part of it; each must stay a
// valid MTConnectError document.
TEST(HostileText, UrlBytesNeverBreakAnErrorDocument) {
  auto agent = test::announced_cell(kVersion, 64);
  for (const std::string target :
       {"/%01%02%1B/current", "/mill%FF%FE/current", "/current%C3%28", "/probe/%0C",
        "/current?path=//%01%FF", "/current?path=//DataItem%5B@id=%27%01%27%5D",
        "/sample?from=%01%FF", "/sample?count=%ED%A0%80", "/sample?pretty=%7F%01",
        "/asset/%01%FF"}) {
    const Response r = test::get(*agent, target);
    EXPECT_GE(r.status, 400) << target;
    expect_valid(r, "MTConnectError", target);
  }
  const Routed method = agent->route("G\x01\xFF", "/current");
  ASSERT_TRUE(method.response);
  expect_valid(*method.response, "MTConnectError", "method");
}

core::ObservedDevice hostile_robot() {
  core::ObservedDevice d = test::robot();
  d.device_uuid = "robot\x01-\xFF-0001";
  d.name = "ro\x1B[31mbot\xC3";
  d.interfaces[0].name = "mh\x02";
  d.interfaces[0].data_items[1].name = "load\xED\xA0\x80";
  d.interfaces[0].data_items.push_back(test::item("robot.bad_type", "BAD<TYPE>"));
  d.interfaces[0].data_items.push_back(test::item("robot.bad_sub", "MATERIAL_LOAD", "re\x01q"));
  d.interfaces[0].data_items[2].category = "NOISE\x01";  // printed as EVENT
  return d;
}

TEST(HostileText, ADeviceAnnouncedWithControlCharactersKeepsDocumentsValid) {
  auto agent = make_agent(test::cell_options(kVersion, 64));
  agent->add_device(hostile_robot());
  agent->add_device(test::mill());
  // Values and losses name the device as DDS does, with the raw bytes.
  const std::string uuid = hostile_robot().device_uuid;
  agent->add_value(value(uuid, "robot.material_load.rsp", core::InteractionState::Active, kT0));
  agent->add_value(value(uuid, "robot.mh.state", core::InterfaceState::Enabled, kT0));
  agent->items_lost(uuid, {"robot.open_door.req"});

  expect_valid(test::get(*agent, "/probe"), "MTConnectDevices", "probe");
  const Response current = test::get(*agent, "/current");
  expect_valid(current, "MTConnectStreams", "current");
  expect_valid(test::get(*agent, "/sample"), "MTConnectStreams", "sample");
  test::Doc d(current.body);
  ASSERT_TRUE(d.ok);
  // The values reached the device, under its name made fit for XML.
  EXPECT_EQ(d.text("//DeviceStream[@uuid='robot\xEF\xBF\xBD-\xEF\xBF\xBD-0001']//MaterialLoad"),
            "ACTIVE");
  EXPECT_EQ(d.count("//*[@dataItemId='robot.bad_type']"), 0U);  // left out, not printed broken
  EXPECT_EQ(agent->stats().unknown_values, 0U);

  // Lost for good and back: documents stay valid through the device's loss.
  agent->device_lost(uuid);
  const Response lost = test::get(*agent, "/current");
  expect_valid(lost, "MTConnectStreams", "after loss");
  test::Doc after(lost.body);
  EXPECT_EQ(after.text("//DeviceStream[starts-with(@uuid,'robot')]//Availability"), "UNAVAILABLE");
}

// A peer's state number outside the Part 5 vocabulary (7, 200) is neither
// printed as it came ("INVALID(200)" would break the schemas' enumerations)
// nor taken for a state: the item reads UNAVAILABLE until a valid value
// comes, and every document stays valid.
TEST(HostileText, StatesOutsideTheVocabularyReadUnavailable) {
  auto agent = test::announced_cell(kVersion, 64);
  const std::string item = "robot.material_load.rsp";
  agent->add_value(value("robot-0001", item, core::InteractionState::Ready, kT0));
  for (const std::int32_t raw : {7, 200}) {
    agent->add_value(value(
        "robot-0001", item,
        core::ObservedState::outside_vocabulary(core::ItemKind::Interaction, raw), kT0 + raw));
    const Response current = test::get(*agent, "/current");
    expect_valid(current, "MTConnectStreams", "current after state " + std::to_string(raw));
    test::Doc d(current.body);
    ASSERT_TRUE(d.ok);
    EXPECT_EQ(d.text("//DeviceStream[@uuid='robot-0001']//MaterialLoad"), "UNAVAILABLE")
        << "state " << raw;
  }
  agent->add_value(value("robot-0001", "robot.mh.state",
                         core::ObservedState::outside_vocabulary(core::ItemKind::InterfaceState, 9),
                         kT0 + 300));
  expect_valid(test::get(*agent, "/sample"), "MTConnectStreams", "sample");
  agent->add_value(value("robot-0001", item, core::InteractionState::Active, kT0 + 400));
  test::Doc back(test::get(*agent, "/current").body);
  EXPECT_EQ(back.text("//DeviceStream[@uuid='robot-0001']//MaterialLoad"), "ACTIVE");
}

// Found by tests/fuzz (fuzz_bridge_config): a Sender that is not UTF-8 was
// accepted, and the 1.8 probe printed it raw in its Agent's uuid. The config
// refuses one now; a program that sets AgentOptions itself still gets valid
// documents.
TEST(HostileText, ASenderThatIsNotUtf8KeepsTheProbeValid) {
  AgentOptions options = test::cell_options(SchemaVersion::V1_8, 64);
  options.sender = "cell\xA6";
  auto agent = make_agent(options);
  agent->add_device(test::robot());
  const Response probe = test::get(*agent, "/probe");
  EXPECT_EQ(find_unfit_xml_char(probe.body), std::string::npos) << probe.body.substr(0, 2000);
  // (Not xmllint: only 1.6's schemas accept every interface type.)
  test::Doc d(probe.body);
  ASSERT_TRUE(d.ok);
  EXPECT_EQ(d.count("//*[local-name()='Agent' and @uuid='cell\xEF\xBF\xBD-agent']"), 1U);
}

}  // namespace
}  // namespace mtc::bridge
