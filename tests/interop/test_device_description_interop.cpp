// The deepest type of the IDL across vendors: a DeviceDescription (nested
// sequences of structs of bounded strings, an enum, 8-byte members after
// them) written by one middleware and read by the other, every field intact,
// with the device_description preset. A bridge or peer builds its whole view
// of a device from this announcement.
// Domains 195 and 196, shared with the other interop tests under the ctest
// resource lock.
#include <gtest/gtest.h>

#include <cstdint>
#include <ostream>
#include <string>
#include <tuple>
#include <vector>

#include "interop_sides.hpp"
#include "mtc/idl_cyclone/mtconnect_interfaces.h"

namespace mtc::test::interop {
namespace {

constexpr int kFastToCycloneDomain = 195;
constexpr int kCycloneToFastDomain = 196;

struct DataItem {
  std::string id, name, type, sub_type, category;
  auto tie() const { return std::tie(id, name, type, sub_type, category); }
  bool operator==(const DataItem& o) const { return tie() == o.tie(); }
};
struct Interface {
  std::string id, name;
  int type = 0;
  std::vector<DataItem> items;
  auto tie() const { return std::tie(id, name, type, items); }
  bool operator==(const Interface& o) const { return tie() == o.tie(); }
};
struct Device {
  std::string uuid, name;
  std::vector<Interface> interfaces;
  std::uint64_t sequence_number = 0;
  std::int64_t source_time_ns = 0;
  auto tie() const { return std::tie(uuid, name, interfaces, sequence_number, source_time_ns); }
  bool operator==(const Device& o) const { return tie() == o.tie(); }
};

std::ostream& operator<<(std::ostream& os, const Device& d) {
  os << d.uuid << " '" << d.name << "' seq " << d.sequence_number << " t " << d.source_time_ns;
  for (const auto& i : d.interfaces) {
    os << " [" << i.id << " '" << i.name << "' type " << i.type;
    for (const auto& item : i.items) {
      os << " (" << item.id << ", " << item.name << ", " << item.type << ", " << item.sub_type
         << ", " << item.category << ")";
    }
    os << "]";
  }
  return os;
}

// A robot with a material handler (two items) and a door (one item); a
// name at its 128-character bound, a uint64 above 2^63, a negative time.
Device test_device() {
  return {kDevice,
          std::string(128, 'n'),
          {{"mh1",
            "material handler",
            1,
            {{"mh1_material_load_request", "load", "MATERIAL_LOAD", "REQUEST", "EVENT"},
             {"mh1_material_load_response", "load", "MATERIAL_LOAD", "RESPONSE", "EVENT"}}},
           {"door1", "door", 2, {{"door1_door_state", "door", "DOOR_STATE", "", "EVENT"}}}},
          (1ULL << 63) + 11,
          -42};
}

idl::DeviceDescription to_fast(const Device& d) {
  idl::DeviceDescription out;
  out.device_uuid(d.uuid);
  out.name(d.name);
  out.sequence_number(d.sequence_number);
  out.source_time_ns(d.source_time_ns);
  for (const auto& i : d.interfaces) {
    idl::InterfaceDescription fi;
    fi.id(i.id);
    fi.name(i.name);
    fi.interface_type(static_cast<idl::interface_types::InterfaceType>(i.type));
    for (const auto& item : i.items) {
      idl::DataItemDescription fd;
      fd.id(item.id);
      fd.name(item.name);
      fd.type(item.type);
      fd.sub_type(item.sub_type);
      fd.category(item.category);
      fi.data_items().push_back(fd);
    }
    out.interfaces().push_back(fi);
  }
  return out;
}

Device from_fast(const idl::DeviceDescription& d) {
  Device out{d.device_uuid().to_string(),
             d.name().to_string(),
             {},
             d.sequence_number(),
             d.source_time_ns()};
  for (const auto& i : d.interfaces()) {
    Interface oi{
        i.id().to_string(), i.name().to_string(), static_cast<int>(i.interface_type()), {}};
    for (const auto& item : i.data_items()) {
      oi.items.push_back({item.id().to_string(), item.name().to_string(), item.type().to_string(),
                          item.sub_type().to_string(), item.category().to_string()});
    }
    out.interfaces.push_back(oi);
  }
  return out;
}

// Cyclone's C struct and the buffers its sequences point into.
struct CycloneDevice {
  std::vector<std::vector<mtc_idl_DataItemDescription>> items;
  std::vector<mtc_idl_InterfaceDescription> interfaces;
  mtc_idl_DeviceDescription sample{};
};

void to_cyclone(const Device& d, CycloneDevice& out) {
  out.items.assign(d.interfaces.size(), {});
  out.interfaces.assign(d.interfaces.size(), mtc_idl_InterfaceDescription{});
  for (std::size_t i = 0; i < d.interfaces.size(); ++i) {
    const auto& src = d.interfaces[i];
    auto& ci = out.interfaces[i];
    cyclone::copy_bounded(ci.id, src.id);
    cyclone::copy_bounded(ci.name, src.name);
    ci.interface_type = static_cast<mtc_idl_interface_types_InterfaceType>(src.type);
    for (const auto& item : src.items) {
      mtc_idl_DataItemDescription cd{};
      cyclone::copy_bounded(cd.id, item.id);
      cyclone::copy_bounded(cd.name, item.name);
      cyclone::copy_bounded(cd.type, item.type);
      cyclone::copy_bounded(cd.sub_type, item.sub_type);
      cyclone::copy_bounded(cd.category, item.category);
      out.items[i].push_back(cd);
    }
    const auto n = static_cast<std::uint32_t>(out.items[i].size());
    ci.data_items = {n, n, out.items[i].data(), false};
  }
  auto& s = out.sample;
  cyclone::copy_bounded(s.device_uuid, d.uuid);
  cyclone::copy_bounded(s.name, d.name);
  const auto n = static_cast<std::uint32_t>(out.interfaces.size());
  s.interfaces = {n, n, out.interfaces.data(), false};
  s.sequence_number = d.sequence_number;
  s.source_time_ns = d.source_time_ns;
}

Device from_cyclone(const mtc_idl_DeviceDescription& d) {
  Device out{d.device_uuid, d.name, {}, d.sequence_number, d.source_time_ns};
  for (std::uint32_t i = 0; i < d.interfaces._length; ++i) {
    const auto& ci = d.interfaces._buffer[i];
    Interface oi{ci.id, ci.name, static_cast<int>(ci.interface_type), {}};
    for (std::uint32_t j = 0; j < ci.data_items._length; ++j) {
      const auto& cd = ci.data_items._buffer[j];
      oi.items.push_back({cd.id, cd.name, cd.type, cd.sub_type, cd.category});
    }
    out.interfaces.push_back(oi);
  }
  return out;
}

TopicSpec device_spec() {
  return {detail::topics::kDeviceDescription, "mtc::idl::DeviceDescription",
          qos::device_description_topic()};
}

TEST(DeviceDescriptionInterop, FastDdsToCyclone) {
  CycloneReader cyclone(kFastToCycloneDomain, mtc_idl_DeviceDescription_desc, device_spec());
  FastWriter<idl::DeviceDescriptionPubSubType> fast(kFastToCycloneDomain, device_spec());
  ASSERT_TRUE(wait_until([&] { return fast.matched() == 1 && cyclone.matched() == 1; }));
  const auto device = test_device();
  fast.writer().write(to_fast(device));

  void* loaned = nullptr;
  dds_sample_info_t info{};
  ASSERT_TRUE(wait_until([&] {
    return cyclone::check(dds_take(cyclone.get(), &loaned, &info, 1, 1), "dds_take") == 1;
  })) << "Cyclone never received the announcement";
  ASSERT_TRUE(info.valid_data);
  EXPECT_EQ(from_cyclone(*static_cast<const mtc_idl_DeviceDescription*>(loaned)), device);
  cyclone::check(dds_return_loan(cyclone.get(), &loaned, 1), "dds_return_loan");
}

TEST(DeviceDescriptionInterop, CycloneToFastDds) {
  FastReader<idl::DeviceDescriptionPubSubType> fast(kCycloneToFastDomain, device_spec());
  CycloneWriter cyclone(kCycloneToFastDomain, mtc_idl_DeviceDescription_desc, device_spec());
  ASSERT_TRUE(wait_until([&] { return fast.matched() == 1 && cyclone.matched() == 1; }));
  const auto device = test_device();
  CycloneDevice sample;
  to_cyclone(device, sample);
  cyclone::check(dds_write(cyclone.get(), &sample.sample), "dds_write");

  idl::DeviceDescription got;
  fdds::SampleInfo info;
  ASSERT_TRUE(wait_until([&] {
    return fast.reader().take_next_sample(&got, &info) ==
           eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK;
  })) << "Fast DDS never received the announcement";
  ASSERT_TRUE(info.valid_data);
  EXPECT_EQ(from_fast(got), device);
}

}  // namespace
}  // namespace mtc::test::interop
