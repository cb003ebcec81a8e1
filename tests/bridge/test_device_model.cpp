// DeviceModel: Devices files (good and malformed), announcements, XPath.
#include <gtest/gtest.h>

#include <set>

#include "../support/param_name.hpp"
#include "bridge_test_util.hpp"
#include "mtc/bridge/device_model.hpp"

namespace mtc::bridge {
namespace {

using test::devices_file;

TEST(DeviceModel, LoadsTheSampleCellFiles) {
  for (const char* name : {"cell_1.3.xml", "cell_1.6.xml", "cell_2.0.xml"}) {
    SCOPED_TRACE(name);
    SlotRegistry slots;
    DeviceModel m = DeviceModel::from_file(devices_file(name), slots);
    ASSERT_EQ(m.devices().size(), 3u);
    EXPECT_EQ(m.devices()[0].name, "machine");
    EXPECT_EQ(m.devices()[0].uuid, "cell-machine");
    EXPECT_TRUE(m.devices()[0].availability_slot.has_value());
    // File ids are "<device id>_<DDS id>": not found as such, resolved.
    EXPECT_FALSE(m.find_item("cell-machine", "door_open_door_response").has_value());
    const auto door = m.resolve_item("cell-machine", "door_open_door_response", {});
    ASSERT_TRUE(door.has_value());
    const DataItemInfo& di = m.data_items()[*door];
    EXPECT_EQ(di.id, "machine_door_open_door_response");
    EXPECT_EQ(di.element, "OpenDoor");
    EXPECT_EQ(di.sub_type, "RESPONSE");
    EXPECT_EQ(m.components()[di.component].element, "DoorInterface");
    EXPECT_EQ(m.find_item("cell-machine", "door_open_door_response"), door);  // remembered
    EXPECT_FALSE(m.resolve_item("cell-robot", "door_open_door_response", {}).has_value());
    EXPECT_EQ(m.find_device("cell-robot"), m.find_device("robot"));
  }
  SlotRegistry slots;
  EXPECT_EQ(DeviceModel::from_file(devices_file("cell_1.3.xml"), slots).file_version(),
            SchemaVersion::V1_3);
  EXPECT_EQ(DeviceModel::from_file(devices_file("cell_2.0.xml"), slots).file_version(),
            SchemaVersion::V2_0);
}

TEST(DeviceModel, ResolvesByTypeWhenIdsDoNotMatch) {
  SlotRegistry slots;
  DeviceModel m = DeviceModel::from_file(devices_file("cell_1.6.xml"), slots);
  // A vendor's own ids: matched by type/subType among the interface items.
  const auto load =
      m.resolve_item("cell-robot", "xyz_load_rsp", {"mh", "", "MATERIAL_LOAD", "RESPONSE"});
  ASSERT_TRUE(load.has_value());
  EXPECT_EQ(m.data_items()[*load].id, "robot_material_handler_material_load_response");
  // The robot has an INTERFACE_STATE in each of three interfaces: the
  // interface element (or id) decides.
  EXPECT_FALSE(m.resolve_item("cell-robot", "s1", {"", "", "INTERFACE_STATE", ""}).has_value());
  const auto by_element =
      m.resolve_item("cell-robot", "s2", {"", "ChuckInterface", "INTERFACE_STATE", ""});
  ASSERT_TRUE(by_element.has_value());
  EXPECT_EQ(m.data_items()[*by_element].id, "robot_chuck_interface_state");
  const auto by_id = m.resolve_item("cell-robot", "s3", {"door", "", "INTERFACE_STATE", ""});
  ASSERT_TRUE(by_id.has_value());
  EXPECT_EQ(m.data_items()[*by_id].id, "robot_door_interface_state");
  // An item is given away once; the Door component's DOOR_STATE (not an
  // interface) is never a candidate.
  EXPECT_FALSE(m.resolve_item("cell-robot", "s4", {"door", "", "INTERFACE_STATE", ""}).has_value());
  const auto ds = m.resolve_item("cell-machine", "ds", {"", "", "DOOR_STATE", ""});
  ASSERT_TRUE(ds.has_value());
  EXPECT_EQ(m.data_items()[*ds].id, "machine_door_door_state");
}

TEST(DeviceModel, ElementNamesFollowTheTypes) {
  EXPECT_EQ(element_name_for_type("MATERIAL_LOAD"), "MaterialLoad");
  EXPECT_EQ(element_name_for_type("INTERFACE_STATE"), "InterfaceState");
  EXPECT_EQ(element_name_for_type("AVAILABILITY"), "Availability");
  EXPECT_EQ(element_name_for_type("x:VENDOR_THING"), "x:VendorThing");
}

struct BadFile {
  const char* what;
  const char* xml;
  std::size_t line;       // expected line (0: do not check)
  const char* in_reason;  // expected fragment of the reason
};

// What gtest lists for the parameter (see param_name.hpp).
void PrintTo(const BadFile& p, std::ostream* os) {
  *os << mtc::test::printable(p.what);
}

class MalformedDevices : public ::testing::TestWithParam<BadFile> {};

TEST_P(MalformedDevices, FailsWithFileLineAndReason) {
  const BadFile& bad = GetParam();
  SlotRegistry slots;
  try {
    (void)DeviceModel::from_text(bad.xml, "bad.xml", slots);
    FAIL() << "accepted: " << bad.what;
  } catch (const ModelError& e) {
    EXPECT_EQ(e.file(), "bad.xml");
    if (bad.line != 0) {
      EXPECT_EQ(e.line(), bad.line) << e.what();
    }
    EXPECT_NE(e.reason().find(bad.in_reason), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("bad.xml:"), std::string::npos);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Table, MalformedDevices,
    ::testing::Values(
        BadFile{"empty", "", 0, "not well-formed"},
        BadFile{"not xml", "hello world", 0, "not well-formed"},
        BadFile{"unclosed", "<MTConnectDevices>\n<Devices>\n<Device id='a'>\n</Devices>", 4,
                "not well-formed"},
        BadFile{"wrong root", "<MTConnectStreams/>", 1, "expected <MTConnectDevices>"},
        BadFile{"no Devices", "<MTConnectDevices>\n<Header/>\n</MTConnectDevices>", 1,
                "no <Devices>"},
        BadFile{"no Device", "<MTConnectDevices><Devices/></MTConnectDevices>", 1, "no <Device>"},
        BadFile{
            "device without uuid",
            "<MTConnectDevices>\n<Devices>\n<Device id='d' name='n'/></Devices></MTConnectDevices>",
            3, "'uuid'"},
        BadFile{"item without id",
                "<MTConnectDevices><Devices><Device id='d' name='n' uuid='u'>\n<DataItems>\n"
                "<DataItem type='AVAILABILITY' category='EVENT'/></DataItems></Device></Devices>"
                "</MTConnectDevices>",
                3, "'id'"},
        BadFile{
            "item without type",
            "<MTConnectDevices><Devices><Device id='d' name='n' uuid='u'><DataItems>"
            "<DataItem id='x' category='EVENT'/></DataItems></Device></Devices></MTConnectDevices>",
            1, "'type'"},
        BadFile{"bad category",
                "<MTConnectDevices><Devices><Device id='d' name='n' uuid='u'><DataItems>"
                "<DataItem id='x' type='A' category='NOISE'/></DataItems></Device></Devices>"
                "</MTConnectDevices>",
                1, "category"},
        BadFile{"duplicate id",
                "<MTConnectDevices><Devices><Device id='d' name='n' uuid='u'><DataItems>\n"
                "<DataItem id='x' type='A' category='EVENT'/>\n"
                "<DataItem id='x' type='B' category='EVENT'/></DataItems></Device></Devices>"
                "</MTConnectDevices>",
                3, "duplicate id 'x'"},
        BadFile{"stray element in Devices",
                "<MTConnectDevices><Devices><Robot id='r'/></Devices></MTConnectDevices>", 1,
                "unexpected <Robot>"},
        BadFile{"component without id",
                "<MTConnectDevices><Devices><Device id='d' name='n' uuid='u'><Components>\n"
                "<Controller name='c'/></Components></Device></Devices></MTConnectDevices>",
                2, "'id'"}),
    [](const ::testing::TestParamInfo<BadFile>& param_info) {
      return mtc::test::param_name(param_info.index, param_info.param.what);
    });

TEST(DeviceModel, MissingFileIsAModelError) {
  SlotRegistry slots;
  EXPECT_THROW(DeviceModel::from_file("/nonexistent/devices.xml", slots), ModelError);
}

TEST(DeviceModel, PrefixedNamespaceIsAccepted) {
  SlotRegistry slots;
  const DeviceModel m = DeviceModel::from_text(
      "<m:MTConnectDevices xmlns:m='urn:mtconnect.org:MTConnectDevices:1.6'><m:Devices>"
      "<m:Device id='d' name='n' uuid='u'><m:DataItems><m:DataItem id='a' type='AVAILABILITY' "
      "category='EVENT'/></m:DataItems></m:Device></m:Devices></m:MTConnectDevices>",
      "p.xml", slots);
  EXPECT_EQ(m.file_version(), SchemaVersion::V1_6);
  ASSERT_EQ(m.data_items().size(), 3u);  // with ASSET_CHANGED and ASSET_REMOVED
  EXPECT_EQ(m.data_items()[0].element, "Availability");
}

TEST(DeviceModel, AnnouncementsBuildDevicesWithInterfaces) {
  SlotRegistry slots;
  const DeviceModel m = DeviceModel::from_announcements(
      {test::mill(), test::robot(), test::feeder()}, SchemaVersion::V1_6, slots);
  ASSERT_EQ(m.devices().size(), 3u);
  const auto load = m.find_item("robot-0001", "robot.material_load.rsp");
  ASSERT_TRUE(load.has_value());
  EXPECT_EQ(m.components()[m.data_items()[*load].component].element, "MaterialHandlerInterface");
  // Device AVAILABILITY, ASSET_CHANGED, ASSET_REMOVED + 13 mill items.
  EXPECT_EQ(m.all_items(0).size(), 16u);
}

TEST(DeviceModel, AnnouncementIdsAreMadeValidAndUnique) {
  core::ObservedDevice a = test::feeder();
  core::ObservedDevice b = test::feeder();
  b.device_uuid = "feeder-0002";
  b.name = "feeder 2";                       // space: not an NCName
  b.interfaces[0].data_items[0].id = "1st";  // leading digit
  SlotRegistry slots;
  const DeviceModel m = DeviceModel::from_announcements({a, b}, SchemaVersion::V1_6, slots);
  std::set<std::string> ids;
  for (const auto& di : m.data_items()) EXPECT_TRUE(ids.insert(di.id).second) << di.id;
  for (const auto& c : m.components()) EXPECT_TRUE(ids.insert(c.id).second) << c.id;
  // The same DDS id on two devices maps to distinct items.
  const auto i1 = m.find_item("feeder-0001", "feeder.material_feed.rsp");
  const auto i2 = m.find_item("feeder-0002", "feeder.material_feed.rsp");
  ASSERT_TRUE(i1 && i2);
  EXPECT_NE(m.data_items()[*i1].id, m.data_items()[*i2].id);
  EXPECT_NE(m.data_items()[*i1].slot, m.data_items()[*i2].slot);
  EXPECT_TRUE(m.find_item("feeder-0002", "1st").has_value());
}

TEST(DeviceModel, Version13LeavesOutInterfacesItCannotDescribe) {
  SlotRegistry slots;
  const DeviceModel m =
      DeviceModel::from_announcements({test::mill(), test::feeder()}, SchemaVersion::V1_3, slots);
  EXPECT_FALSE(m.find_item("mill-0001", "mill.material_load.req").has_value());
  EXPECT_FALSE(m.find_item("feeder-0001", "feeder.material_feed.rsp").has_value());
  EXPECT_TRUE(m.find_item("mill-0001", "mill.open_door.rsp").has_value());
}

TEST(DeviceModel, XPathSelectsItemsAndComponents) {
  SlotRegistry slots;
  const DeviceModel m = DeviceModel::from_file(devices_file("cell_1.6.xml"), slots);
  EXPECT_EQ(m.select("//DataItem[@type='DOOR_STATE']", std::nullopt).size(), 2u);
  EXPECT_EQ(m.select("//DoorInterface", std::nullopt).size(), 4u + 3u);
  EXPECT_EQ(m.select("//Device[@name='robot']//DataItem[@subType='REQUEST']", std::nullopt).size(),
            4u);
  const auto mill = m.find_device("machine");
  EXPECT_TRUE(m.select("//Device[@name='robot']", mill).empty());
  EXPECT_EQ(m.select("//DataItem/@type", std::nullopt).size(), m.data_items().size());
  EXPECT_THROW(m.select("//DataItem[", std::nullopt), std::invalid_argument);
  EXPECT_THROW(m.select("1 + 1", std::nullopt), std::invalid_argument);
  EXPECT_THROW(m.select("", std::nullopt), std::invalid_argument);
}

TEST(DeviceModel, SlotsAreStableAcrossRebuilds) {
  SlotRegistry slots;
  const DeviceModel a =
      DeviceModel::from_announcements({test::feeder()}, SchemaVersion::V1_6, slots);
  const DeviceModel b =
      DeviceModel::from_announcements({test::mill(), test::feeder()}, SchemaVersion::V1_6, slots);
  const auto ia = a.find_item("feeder-0001", "feeder.material_feed.rsp");
  const auto ib = b.find_item("feeder-0001", "feeder.material_feed.rsp");
  ASSERT_TRUE(ia && ib);
  EXPECT_EQ(a.data_items()[*ia].slot, b.data_items()[*ib].slot);
}

}  // namespace
}  // namespace mtc::bridge
