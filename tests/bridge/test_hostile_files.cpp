// Devices files an attacker or an accident could hand the bridge: nested far
// too deep, huge, endless (/dev/zero), an entity-expansion bomb, not text,
// duplicate devices, control characters. Each is a ModelError naming the file
// and the line, raised quickly, never a crash or a hang.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>

#include "bridge_test_util.hpp"
#include "mtc/bridge/device_model.hpp"

namespace mtc::bridge {
namespace {

constexpr const char* kOpen =
    "<MTConnectDevices xmlns=\"urn:mtconnect.org:MTConnectDevices:1.6\"><Devices>\n";
constexpr const char* kClose = "</Devices></MTConnectDevices>\n";

std::string device(const std::string& id, const std::string& name, const std::string& uuid) {
  return "<Device id='" + id + "' name='" + name + "' uuid='" + uuid + "'><DataItems>" +
         "<DataItem id='" + id + "_avail' type='AVAILABILITY' category='EVENT'/>" +
         "</DataItems></Device>\n";
}

ModelError error_of(const std::string& xml, const ModelLimits& limits = {}) {
  SlotRegistry slots;
  try {
    (void)DeviceModel::from_text(xml, "hostile.xml", slots, limits);
  } catch (const ModelError& e) {
    return e;
  }
  ADD_FAILURE() << "accepted";
  return ModelError("", 0, "");
}

std::string nested_components(std::size_t depth) {
  std::string xml = kOpen;
  xml += "<Device id='d' name='n' uuid='u'>\n";
  for (std::size_t i = 0; i < depth; ++i) {
    xml += "<Components><Axes id='c" + std::to_string(i) + "'>\n";
  }
  for (std::size_t i = 0; i < depth; ++i) xml += "</Axes></Components>";
  xml += "</Device>";
  xml += kClose;
  return xml;
}

TEST(HostileDevicesFile, NestedTwentyThousandDeepIsRefusedWithoutRecursion) {
  const std::string xml = nested_components(20000);
  const auto start = std::chrono::steady_clock::now();
  const ModelError e = error_of(xml);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
  EXPECT_EQ(e.file(), "hostile.xml");
  EXPECT_NE(e.reason().find("nested deeper than"), std::string::npos) << e.what();
  // The first element past the limit: three elements down to the Device,
  // two per component level, each level on a line of its own from line 3.
  const ModelLimits limits;
  EXPECT_EQ(e.line(), 3 + (limits.max_depth - 3) / 2) << e.what();
}

TEST(HostileDevicesFile, DepthWithinTheLimitLoads) {
  SlotRegistry slots;
  const DeviceModel m = DeviceModel::from_text(nested_components(20), "deep.xml", slots);
  EXPECT_EQ(m.components().size(), 21u);
}

TEST(HostileDevicesFile, DuplicateDeviceUuidsAndNamesAreRefused) {
  const ModelError uuid = error_of(std::string(kOpen) + device("a", "mill", "u-1") +
                                   device("b", "lathe", "u-1") + kClose);
  EXPECT_EQ(uuid.line(), 3u) << uuid.what();
  EXPECT_NE(uuid.reason().find("duplicate device uuid 'u-1' (first on line 2)"), std::string::npos)
      << uuid.what();
  const ModelError name = error_of(std::string(kOpen) + device("a", "mill", "u-1") +
                                   device("b", "mill", "u-2") + kClose);
  EXPECT_EQ(name.line(), 3u) << name.what();
  EXPECT_NE(name.reason().find("duplicate device name 'mill' (first on line 2)"), std::string::npos)
      << name.what();
  // A name that is another device's uuid would make /{device} ambiguous.
  const ModelError cross = error_of(std::string(kOpen) + device("a", "mill", "u-1") +
                                    device("b", "u-1", "u-2") + kClose);
  EXPECT_NE(cross.reason().find("'u-1'"), std::string::npos) << cross.what();
}

TEST(HostileDevicesFile, EntityExpansionBombIsRefusedAtItsDoctype) {
  std::string xml =
      "<?xml version='1.0'?>\n<!DOCTYPE MTConnectDevices [\n<!ENTITY a 'aaaaaaaaaa'>\n";
  std::string previous = "a";
  for (int level = 0; level < 9; ++level) {
    const std::string name = "e" + std::to_string(level);
    xml += "<!ENTITY " + name + " '";
    for (int i = 0; i < 10; ++i) xml += "&" + previous + ";";
    xml += "'>\n";
    previous = name;
  }
  xml +=
      "]>\n" + std::string(kOpen) + "<Device id='d' name='&" + previous + ";' uuid='u'/>" + kClose;
  const ModelError e = error_of(xml);
  EXPECT_EQ(e.line(), 2u) << e.what();
  EXPECT_NE(e.reason().find("DOCTYPE"), std::string::npos) << e.what();
}

TEST(HostileDevicesFile, ControlCharactersAndInvalidUtf8AreRefusedWithTheirLine) {
  const ModelError control =
      error_of(std::string(kOpen) + "\n" + device("a", "mi\x01ll", "u-1") + kClose);
  EXPECT_EQ(control.line(), 3u) << control.what();
  EXPECT_NE(control.reason().find("not allowed in XML"), std::string::npos) << control.what();
  const ModelError reference =
      error_of(std::string(kOpen) + device("a", "mi&#27;ll", "u-1") + kClose);
  EXPECT_EQ(reference.line(), 2u) << reference.what();
  const ModelError utf8 = error_of(std::string(kOpen) + device("a", "mi\xC3ll", "u-1") + kClose);
  EXPECT_EQ(utf8.line(), 2u) << utf8.what();
  EXPECT_NE(utf8.reason().find("UTF-8"), std::string::npos) << utf8.what();
}

TEST(HostileDevicesFile, ATypeThatCannotNameAnElementIsRefused) {
  const ModelError e =
      error_of(std::string(kOpen) +
               "<Device id='d' name='n' uuid='u'><DataItems>\n"
               "<DataItem id='x' type='A&lt;B' category='EVENT'/></DataItems></Device>" +
               kClose);
  EXPECT_EQ(e.line(), 3u) << e.what();
  EXPECT_NE(e.reason().find("type 'A<B'"), std::string::npos) << e.what();
}

TEST(HostileDevicesFile, HugeAndEndlessFilesAreRefusedBeforeParsing) {
  ModelLimits small;
  small.max_file_bytes = 4096;
  const std::string path = ::testing::TempDir() + "hostile_huge_devices.xml";
  {
    std::ofstream out(path);
    out << kOpen << device("a", "mill", "u-1") << std::string(8192, ' ') << kClose;
  }
  SlotRegistry slots;
  for (const std::string& file : {path, std::string("/dev/zero")}) {
    try {
      (void)DeviceModel::from_file(file, slots, small);
      ADD_FAILURE() << file << " accepted";
    } catch (const ModelError& e) {
      EXPECT_EQ(e.file(), file);
      EXPECT_NE(e.reason().find("larger than 4096 bytes"), std::string::npos) << e.what();
    }
  }
  try {
    (void)DeviceModel::from_file(::testing::TempDir(), slots);
    ADD_FAILURE() << "a directory accepted";
  } catch (const ModelError& e) {
    EXPECT_NE(e.reason().find("directory"), std::string::npos) << e.what();
  }
  std::remove(path.c_str());
}

TEST(HostileDevicesFile, BinaryJunkIsNotXml) {
  std::string junk(4096, '\0');
  for (std::size_t i = 0; i < junk.size(); ++i) junk[i] = static_cast<char>((i * 7919) % 251);
  const ModelError e = error_of(junk);
  EXPECT_EQ(e.file(), "hostile.xml");
  EXPECT_NE(e.reason().find("not well-formed"), std::string::npos) << e.what();
}

}  // namespace
}  // namespace mtc::bridge
