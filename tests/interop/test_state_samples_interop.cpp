// The three state samples across vendors (design page, section 6): an
// InterfaceStateSample, a DoorStateSample and a ChuckStateSample written by
// one middleware and read by the other on their own topics with the state
// preset, every field intact and each data item its own instance (the key).
// The three share one shape (two key strings, an interface id, a state enum
// of its own, then the 8-, 4- and 8-byte members), so one template per direction
// covers them; a type whose members drift from that shape no longer compiles
// here.
// Domains 195 and 196, shared with the other interop tests under the ctest
// resource lock.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <map>
#include <ostream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "interop_sides.hpp"
#include "mtc/idl_cyclone/mtconnect_interfaces.h"

namespace mtc::test::interop {
namespace {

constexpr int kFastToCycloneDomain = 195;
constexpr int kCycloneToFastDomain = 196;

// One state sample as plain values, whichever of the three types it is.
struct StateItem {
  std::string device_uuid;
  std::string data_item_id;
  std::string interface_id;
  int state = 0;
  std::uint64_t sequence_number = 0;
  std::uint32_t heartbeat_group = 0;
  std::int64_t source_time_ns = 0;

  auto tie() const {
    return std::tie(device_uuid, data_item_id, interface_id, state, sequence_number,
                    heartbeat_group, source_time_ns);
  }
  bool operator==(const StateItem& other) const { return tie() == other.tie(); }
};

std::ostream& operator<<(std::ostream& os, const StateItem& i) {
  return os << "{" << i.device_uuid << ", " << i.data_item_id << ", " << i.interface_id
            << ", state " << i.state << ", seq " << i.sequence_number << ", group "
            << i.heartbeat_group << ", t " << i.source_time_ns << "}";
}

// What differs between the three: the generated types, the topic and the
// state enum (its last value, so that every test value is a non-zero one).
struct InterfaceState {
  using PubSub = idl::InterfaceStateSamplePubSubType;
  using Fast = idl::InterfaceStateSample;
  using FastState = idl::interface_state::Value;
  using Cyclone = mtc_idl_InterfaceStateSample;
  using CycloneState = mtc_idl_interface_state_Value;
  static const dds_topic_descriptor_t& descriptor() { return mtc_idl_InterfaceStateSample_desc; }
  static constexpr const char* kTopic = detail::topics::kInterfaceState;
  static constexpr const char* kTypeName = "mtc::idl::InterfaceStateSample";
  static constexpr int kLastState = 2;  // DISABLED
};

struct DoorState {
  using PubSub = idl::DoorStateSamplePubSubType;
  using Fast = idl::DoorStateSample;
  using FastState = idl::door_state::Value;
  using Cyclone = mtc_idl_DoorStateSample;
  using CycloneState = mtc_idl_door_state_Value;
  static const dds_topic_descriptor_t& descriptor() { return mtc_idl_DoorStateSample_desc; }
  static constexpr const char* kTopic = detail::topics::kDoorState;
  static constexpr const char* kTypeName = "mtc::idl::DoorStateSample";
  static constexpr int kLastState = 3;  // CLOSED
};

struct ChuckState {
  using PubSub = idl::ChuckStateSamplePubSubType;
  using Fast = idl::ChuckStateSample;
  using FastState = idl::chuck_state::Value;
  using Cyclone = mtc_idl_ChuckStateSample;
  using CycloneState = mtc_idl_chuck_state_Value;
  static const dds_topic_descriptor_t& descriptor() { return mtc_idl_ChuckStateSample_desc; }
  static constexpr const char* kTopic = detail::topics::kChuckState;
  static constexpr const char* kTypeName = "mtc::idl::ChuckStateSample";
  static constexpr int kLastState = 3;  // CLOSED
};

template <typename T>
typename T::Fast to_fast(const StateItem& i) {
  typename T::Fast s;
  s.device_uuid(i.device_uuid);
  s.data_item_id(i.data_item_id);
  s.interface_id(i.interface_id);
  s.state(static_cast<typename T::FastState>(i.state));
  s.sequence_number(i.sequence_number);
  s.heartbeat_group(i.heartbeat_group);
  s.source_time_ns(i.source_time_ns);
  return s;
}

template <typename Fast>
StateItem from_fast(const Fast& s) {
  return {s.device_uuid().to_string(), s.data_item_id().to_string(), s.interface_id().to_string(),
          static_cast<int>(s.state()), s.sequence_number(),          s.heartbeat_group(),
          s.source_time_ns()};
}

template <typename T>
typename T::Cyclone to_cyclone(const StateItem& i) {
  typename T::Cyclone s{};
  cyclone::copy_bounded(s.device_uuid, i.device_uuid);
  cyclone::copy_bounded(s.data_item_id, i.data_item_id);
  cyclone::copy_bounded(s.interface_id, i.interface_id);
  s.state = static_cast<typename T::CycloneState>(i.state);
  s.sequence_number = i.sequence_number;
  s.heartbeat_group = i.heartbeat_group;
  s.source_time_ns = i.source_time_ns;
  return s;
}

template <typename Cyclone>
StateItem from_cyclone(const Cyclone& s) {
  return {s.device_uuid,     s.data_item_id,    s.interface_id,  static_cast<int>(s.state),
          s.sequence_number, s.heartbeat_group, s.source_time_ns};
}

// Two items of one device with the values that catch encoding faults (as
// test_items() for the interaction topic): a uint64 above 2^63 right after
// an enum, a negative int64 after a uint32, a key and an interface id at
// their 64-character bound, and every state non-zero.
template <typename T>
std::array<StateItem, 2> state_items() {
  StateItem a{kDevice, "unit1_state", "unit1", T::kLastState, (1ULL << 63) + 9, 3, -9876543210LL};
  StateItem b = a;
  b.data_item_id = std::string(64, 's');
  b.interface_id = std::string(64, 'i');
  b.state = 1;
  b.sequence_number = 2;
  return {a, b};
}

template <typename T>
TopicSpec state_spec() {
  return {T::kTopic, T::kTypeName, qos::state_topic()};
}

// A Fast DDS writer to a Cyclone reader (void: gtest's ASSERT_* return).
template <typename T>
void fast_dds_to_cyclone() {
  CycloneReader cyclone(kFastToCycloneDomain, T::descriptor(), state_spec<T>());
  FastWriter<typename T::PubSub> fast(kFastToCycloneDomain, state_spec<T>());
  ASSERT_TRUE(wait_until([&] { return fast.matched() == 1 && cyclone.matched() == 1; }));
  const auto items = state_items<T>();
  for (const auto& item : items) fast.writer().write(to_fast<T>(item));

  // Cyclone lends its samples; each is copied out with its instance handle.
  std::vector<std::pair<dds_instance_handle_t, StateItem>> got;
  ASSERT_TRUE(wait_until([&] {
    void* loaned = nullptr;
    dds_sample_info_t info{};
    if (cyclone::check(dds_take(cyclone.get(), &loaned, &info, 1, 1), "dds_take") == 1) {
      EXPECT_TRUE(info.valid_data);
      got.emplace_back(info.instance_handle,
                       from_cyclone(*static_cast<const typename T::Cyclone*>(loaned)));
      cyclone::check(dds_return_loan(cyclone.get(), &loaned, 1), "dds_return_loan");
    }
    return got.size() >= items.size();
  })) << "Cyclone received "
      << got.size() << " of " << items.size() << " samples";

  ASSERT_EQ(got.size(), items.size());
  std::map<std::string, std::pair<dds_instance_handle_t, StateItem>> by_item;
  for (const auto& [handle, item] : got) by_item[item.data_item_id] = {handle, item};
  for (const auto& item : items) {
    SCOPED_TRACE(item.data_item_id);
    ASSERT_EQ(by_item.count(item.data_item_id), 1U);
    EXPECT_EQ(by_item[item.data_item_id].second, item);
    // The key: Cyclone filed the sample under the instance of its key fields.
    const auto key = to_cyclone<T>(item);
    EXPECT_EQ(dds_lookup_instance(cyclone.get(), &key), by_item[item.data_item_id].first);
  }
  EXPECT_NE(by_item[items[0].data_item_id].first, by_item[items[1].data_item_id].first);
}

// A Cyclone writer to a Fast DDS reader.
template <typename T>
void cyclone_to_fast_dds() {
  FastReader<typename T::PubSub> fast(kCycloneToFastDomain, state_spec<T>());
  CycloneWriter cyclone(kCycloneToFastDomain, T::descriptor(), state_spec<T>());
  ASSERT_TRUE(wait_until([&] { return fast.matched() == 1 && cyclone.matched() == 1; }));
  const auto items = state_items<T>();
  for (const auto& item : items) {
    const auto sample = to_cyclone<T>(item);
    cyclone::check(dds_write(cyclone.get(), &sample), "dds_write");
  }

  using Handle = eprosima::fastrtps::rtps::InstanceHandle_t;
  std::map<std::string, std::pair<Handle, StateItem>> by_item;
  std::size_t taken = 0;
  ASSERT_TRUE(wait_until([&] {
    typename T::Fast sample;
    fdds::SampleInfo info;
    while (fast.reader().take_next_sample(&sample, &info) ==
           eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK) {
      EXPECT_TRUE(info.valid_data);
      const auto item = from_fast(sample);
      by_item[item.data_item_id] = {info.instance_handle, item};
      ++taken;
    }
    return taken >= items.size();
  })) << "Fast DDS received "
      << taken << " of " << items.size() << " samples";

  EXPECT_EQ(taken, items.size());
  for (const auto& item : items) {
    SCOPED_TRACE(item.data_item_id);
    ASSERT_EQ(by_item.count(item.data_item_id), 1U);
    EXPECT_EQ(by_item[item.data_item_id].second, item);
    // The key: Fast DDS filed the sample under the specification's key hash.
    Handle expected;
    idl::compute_key_hash(to_fast<T>(item), expected, false);
    EXPECT_EQ(by_item[item.data_item_id].first, expected);
  }
}

// One case per type and direction, named for ctest -R.
TEST(StateSampleInterop, InterfaceStateFastDdsToCyclone) {
  fast_dds_to_cyclone<InterfaceState>();
}
TEST(StateSampleInterop, InterfaceStateCycloneToFastDds) {
  cyclone_to_fast_dds<InterfaceState>();
}
TEST(StateSampleInterop, DoorStateFastDdsToCyclone) {
  fast_dds_to_cyclone<DoorState>();
}
TEST(StateSampleInterop, DoorStateCycloneToFastDds) {
  cyclone_to_fast_dds<DoorState>();
}
TEST(StateSampleInterop, ChuckStateFastDdsToCyclone) {
  fast_dds_to_cyclone<ChuckState>();
}
TEST(StateSampleInterop, ChuckStateCycloneToFastDds) {
  cyclone_to_fast_dds<ChuckState>();
}

}  // namespace
}  // namespace mtc::test::interop
