// What each middleware does with a peer whose @final InteractionSample lacks
// the member issue 10 appended (`paired_participant`, 12 octets at the end):
// a device built before that change, on the other vendor. Neither side sends
// XTypes type information, so they match by type name and the payload alone
// decides. Found (docs/design/middleware-layer.md, "Appended members"):
// - Fast DDS writer with the member -> Cyclone reader without it: the sample
//   arrives, the known members intact; Cyclone ignores the trailing bytes.
// - Cyclone writer without the member -> Fast DDS reader with it: the sample
//   reaches the reader's history, but deserialising runs out of bytes and
//   the runtime's type support refuses it: the reader never sees it.
// Domains 198 and 199 (registry: interop tests 195-199).
#include <gtest/gtest.h>

#include <array>
#include <string>

#include "interaction_before_paired_participant.h"
#include "interop_sides.hpp"

namespace mtc::test::interop {
namespace {

constexpr int kWithToWithoutDomain = 198;
constexpr int kWithoutToWithDomain = 199;

// The fixture's InteractionSample (no paired_participant), filled as the
// runtime fills an answer to a paired requester.
mtc_idl_InteractionSample sample_without_member() {
  mtc_idl_InteractionSample s{};
  cyclone::copy_bounded(s.device_uuid, kDevice);
  cyclone::copy_bounded(s.data_item_id, "mh1_material_load_response");
  cyclone::copy_bounded(s.interface_id, "mh1");
  s.service = mtc_idl_services_MATERIAL_LOAD;
  s.sub_type = mtc_idl_sub_types_RESPONSE;
  s.state = mtc_idl_interaction_state_READY;
  s.sequence_number = 3;
  s.heartbeat_group = 1;
  s.source_time_ns = 42;
  cyclone::copy_bounded(s.paired_device_uuid, "cnc-1");
  cyclone::copy_bounded(s.paired_interface_id, "mh1");
  return s;
}

TEST(AppendedMember, FastDdsWithMemberToCycloneWithout) {
  CycloneReader cyclone(kWithToWithoutDomain, mtc_idl_InteractionSample_desc, interaction_spec());
  FastWriter<idl::InteractionSamplePubSubType> fast(kWithToWithoutDomain, interaction_spec());
  ASSERT_TRUE(wait_until([&] { return fast.matched() == 1 && cyclone.matched() == 1; }));

  const auto expected = sample_without_member();
  idl::InteractionSample sample;
  sample.device_uuid(expected.device_uuid);
  sample.data_item_id(expected.data_item_id);
  sample.interface_id(expected.interface_id);
  sample.service(idl::services::MATERIAL_LOAD);
  sample.sub_type(idl::sub_types::RESPONSE);
  sample.state(idl::interaction_state::READY);
  sample.sequence_number(expected.sequence_number);
  sample.heartbeat_group(expected.heartbeat_group);
  sample.source_time_ns(expected.source_time_ns);
  sample.paired_device_uuid(expected.paired_device_uuid);
  sample.paired_interface_id(expected.paired_interface_id);
  sample.paired_participant().fill(0xEE);
  fast.writer().write(sample);

  mtc_idl_InteractionSample got{};
  void* pointer = &got;
  dds_sample_info_t info{};
  ASSERT_TRUE(wait_until([&] {
    return cyclone::check(dds_take(cyclone.get(), &pointer, &info, 1, 1), "dds_take") == 1;
  })) << "Cyclone dropped the sample with the appended member";
  ASSERT_TRUE(info.valid_data);
  EXPECT_STREQ(got.data_item_id, expected.data_item_id);
  EXPECT_STREQ(got.paired_device_uuid, expected.paired_device_uuid);
  EXPECT_STREQ(got.paired_interface_id, expected.paired_interface_id);
  EXPECT_EQ(got.state, expected.state);
  EXPECT_EQ(got.sequence_number, expected.sequence_number);
  EXPECT_EQ(got.source_time_ns, expected.source_time_ns);
}

TEST(AppendedMember, CycloneWithoutMemberToFastDdsWith) {
  FastReader<idl::InteractionSamplePubSubType> fast(kWithoutToWithDomain, interaction_spec());
  CycloneWriter cyclone(kWithoutToWithDomain, mtc_idl_InteractionSample_desc, interaction_spec());
  ASSERT_TRUE(wait_until([&] { return fast.matched() == 1 && cyclone.matched() == 1; }));

  const auto sample = sample_without_member();
  cyclone::check(dds_write(cyclone.get(), &sample), "dds_write");
  // Arrival in the reader's history is proof that the wire delivered it; the
  // payload is deserialised only when taken.
  ASSERT_TRUE(wait_until([&] { return fast.reader().get_unread_count() >= 1; }));
  idl::InteractionSample got;
  fdds::SampleInfo info;
  // Taken and thrown away: NO_DATA, and nothing left unread.
  const auto rc = fast.reader().take_next_sample(&got, &info);
  EXPECT_EQ(rc, eprosima::fastrtps::types::ReturnCode_t::RETCODE_NO_DATA)
      << "Fast DDS now reads a payload one member short: update the design";
  EXPECT_EQ(fast.reader().get_unread_count(), 0U);
}

}  // namespace
}  // namespace mtc::test::interop
