// The instance handle of a sample depends on its key fields only. The
// handle fastddsgen 2.3's getKey() computes also depends on the key hashed
// before it (stale alignment padding in a shared buffer); that made the
// writers of a running cell collect stray instances and the cost of every
// RTPS heartbeat grow with the age of the run (docs/endurance.md).
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "mtc/idl/mtconnect_interfacesPubSubTypes.h"
#include "mtc/idl/type_support.hpp"

namespace {

using eprosima::fastrtps::rtps::InstanceHandle_t;
using mtc::idl::InteractionSample;

InteractionSample sample(const std::string& device, const std::string& item) {
  InteractionSample s;
  s.device_uuid(device);
  s.data_item_id(item);
  return s;
}

InstanceHandle_t key_of(eprosima::fastdds::dds::TypeSupport& type, InteractionSample s) {
  InstanceHandle_t h;
  EXPECT_TRUE(type.get_key(&s, &h));
  return h;
}

// Big-endian CDR of one string: length (with the NUL), characters, NUL.
void append_cdr_string(std::vector<unsigned char>& out, const std::string& text) {
  while (out.size() % 4 != 0) out.push_back(0);  // alignment padding is zero
  const auto n = static_cast<std::uint32_t>(text.size() + 1);
  for (int shift = 24; shift >= 0; shift -= 8) {
    out.push_back(static_cast<unsigned char>(n >> shift));
  }
  out.insert(out.end(), text.begin(), text.end());
  out.push_back(0);
}

// The key hash as the RTPS specification (9.6.3.8) defines it, computed here
// independently of any type object.
InstanceHandle_t spec_key_hash(const std::string& device, const std::string& item) {
  std::vector<unsigned char> cdr;
  append_cdr_string(cdr, device);
  append_cdr_string(cdr, item);
  MD5 md5;
  md5.update(cdr.data(), static_cast<MD5::size_type>(cdr.size()));
  md5.finalize();
  InstanceHandle_t h;
  std::memcpy(h.value, md5.digest, 16);
  return h;
}

TEST(TypeSupport, SameKeySameHandleWhateverWasHashedBefore) {
  auto type = mtc::idl::type_support<mtc::idl::InteractionSamplePubSubType>();
  const auto first = key_of(type, sample("cell-robot", "door_open_door_request"));
  // Keys whose strings end at other offsets leave other bytes where the
  // padding of the first key's device uuid goes.
  key_of(type, sample("a-much-longer-device-uuid-xyz", "something_else_entirely"));
  key_of(type, sample("m", "x"));
  const auto again = key_of(type, sample("cell-robot", "door_open_door_request"));
  EXPECT_EQ(first, again);
}

TEST(TypeSupport, HandleIsTheRtpsKeyHash) {
  auto type = mtc::idl::type_support<mtc::idl::InteractionSamplePubSubType>();
  key_of(type, sample("a-much-longer-device-uuid-xyz", "something_else_entirely"));
  for (const auto& [device, item] :
       std::vector<std::pair<std::string, std::string>>{{"cell-robot", "door_open_door_request"},
                                                        {"cell-machine", "mh_interface_state"},
                                                        {"d", "i"},
                                                        {"abc", "defg"}}) {
    EXPECT_EQ(key_of(type, sample(device, item)), spec_key_hash(device, item))
        << device << "/" << item;
  }
}

TEST(TypeSupport, DistinctKeysDistinctHandles) {
  auto type = mtc::idl::type_support<mtc::idl::InteractionSamplePubSubType>();
  EXPECT_NE(key_of(type, sample("robot-1", "mh_material_load_request")),
            key_of(type, sample("robot-1", "mh_material_load_response")));
  EXPECT_NE(key_of(type, sample("robot-1", "x")), key_of(type, sample("robot-2", "x")));
}

TEST(TypeSupport, EveryTopicTypeHashesItsKeyOnly) {
  auto state = mtc::idl::type_support<mtc::idl::InterfaceStateSamplePubSubType>();
  mtc::idl::InterfaceStateSample a;
  a.device_uuid("cell-machine");
  a.data_item_id("door_interface_state");
  mtc::idl::InterfaceStateSample other;
  other.device_uuid("x");
  other.data_item_id("a-long-item-id-that-ends-elsewhere");
  InstanceHandle_t h1;
  InstanceHandle_t h2;
  InstanceHandle_t h3;
  ASSERT_TRUE(state.get_key(&a, &h1));
  ASSERT_TRUE(state.get_key(&other, &h2));
  a.state(mtc::idl::interface_state::ENABLED);  // not a key field
  ASSERT_TRUE(state.get_key(&a, &h3));
  EXPECT_EQ(h1, h3);
  EXPECT_EQ(h1, spec_key_hash("cell-machine", "door_interface_state"));

  auto description = mtc::idl::type_support<mtc::idl::DeviceDescriptionPubSubType>();
  mtc::idl::DeviceDescription d;
  d.device_uuid("cell-feeder");
  InstanceHandle_t hd1;
  InstanceHandle_t hd2;
  ASSERT_TRUE(description.get_key(&d, &hd1));
  d.name("renamed");
  ASSERT_TRUE(description.get_key(&d, &hd2));
  EXPECT_EQ(hd1, hd2);
}

// The heartbeat's key is (device_uuid, group): a string then an unsigned
// long, whose alignment padding must be zero too.
TEST(TypeSupport, HeartbeatKeyIsDeviceAndGroup) {
  auto type = mtc::idl::type_support<mtc::idl::HeartbeatPubSubType>();
  auto heartbeat = [](const std::string& device, std::uint32_t group) {
    mtc::idl::Heartbeat h;
    h.device_uuid(device);
    h.group(group);
    return h;
  };
  auto key = [&type](mtc::idl::Heartbeat h) {
    InstanceHandle_t out;
    EXPECT_TRUE(type.get_key(&h, &out));
    return out;
  };
  const auto first = key(heartbeat("cell-robot", 1));
  key(heartbeat("a-much-longer-device-uuid-xyz", 7));
  auto beating = heartbeat("cell-robot", 1);
  beating.beat(42);  // not a key field
  beating.request_changes(3);
  EXPECT_EQ(key(beating), first);
  EXPECT_NE(key(heartbeat("cell-robot", 0)), first);
  // Big-endian CDR: "cell-robot" (4 + 11 bytes), 1 byte of zero padding, group.
  std::vector<unsigned char> cdr;
  append_cdr_string(cdr, "cell-robot");
  while (cdr.size() % 4 != 0) cdr.push_back(0);
  for (int shift = 24; shift >= 0; shift -= 8) {
    cdr.push_back(static_cast<unsigned char>(1 >> shift));
  }
  MD5 md5;
  md5.update(cdr.data(), static_cast<MD5::size_type>(cdr.size()));
  md5.finalize();
  InstanceHandle_t expected;
  std::memcpy(expected.value, md5.digest, 16);
  EXPECT_EQ(first, expected);
}

}  // namespace
