// The heartbeat contract across vendors: a device's heartbeat topic
// (mtc/Heartbeat, the equipment preset: DEADLINE and MANUAL_BY_TOPIC
// liveliness of Timing::lease(), 300 ms by default) written by one
// middleware and read by the other. While the writer beats, its reader sees
// it alive and misses no deadline, and the values (the sequence of
// interaction changes included) arrive intact; when it stops, the reader
// reports both the lost liveliness and the missed deadline within a bound;
// when it beats again, it is alive again. This is what comms-loss detection
// in a mixed cell rests on (docs/design/middleware-layer.md).
// Domains 195 and 196, shared with test_cyclone_interop.cpp under the ctest
// resource lock of every interop test.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <thread>

#include "interop_sides.hpp"
#include "mtc/idl_cyclone/mtconnect_interfaces.h"

namespace mtc::test::interop {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

constexpr int kFastBeatsDomain = 195;
constexpr int kCycloneBeatsDomain = 196;
constexpr int kBeats = 10;
// Loss must be told within the lease; the bound adds room for a loaded
// 2-core machine (scheduling, the other test processes).
constexpr auto kLossBound = 3 * qos::Timing{}.lease();

idl::Heartbeat fast_beat(std::uint64_t beat) {
  idl::Heartbeat h;
  h.device_uuid(kDevice);
  h.group(0);
  h.period_ms(100);
  h.lease_ms(300);
  h.beat(beat);
  idl::InteractionChanges changes;
  changes.service(idl::services::OPEN_DOOR);
  changes.sub_type(idl::sub_types::RESPONSE);
  changes.changes(beat * 2);
  h.interaction_changes().push_back(changes);
  return h;
}

// Cyclone's heartbeat; `changes` holds the one element of its sequence.
mtc_idl_Heartbeat cyclone_beat(std::uint64_t beat, mtc_idl_InteractionChanges& changes) {
  mtc_idl_Heartbeat h{};
  cyclone::copy_bounded(h.device_uuid, kDevice);
  h.period_ms = 100;
  h.lease_ms = 300;
  h.beat = beat;
  changes = {mtc_idl_services_OPEN_DOOR, mtc_idl_sub_types_RESPONSE, beat * 2};
  h.interaction_changes = {1, 1, &changes, false};
  return h;
}

struct Liveness {
  int alive = 0;
  int deadline_misses = 0;
};

Liveness liveness_of(dds_entity_t reader) {
  dds_liveliness_changed_status_t live{};
  dds_requested_deadline_missed_status_t deadline{};
  cyclone::check(dds_get_liveliness_changed_status(reader, &live), "liveliness status");
  cyclone::check(dds_get_requested_deadline_missed_status(reader, &deadline), "deadline status");
  return {static_cast<int>(live.alive_count), static_cast<int>(deadline.total_count)};
}

Liveness liveness_of(fdds::DataReader& reader) {
  fdds::LivelinessChangedStatus live;
  fdds::RequestedDeadlineMissedStatus deadline;
  reader.get_liveliness_changed_status(live);
  reader.get_requested_deadline_missed_status(deadline);
  return {live.alive_count, static_cast<int>(deadline.total_count)};
}

// The newest beat a Cyclone reader holds, checking the sequence on the way.
std::uint64_t take_beats(dds_entity_t reader) {
  std::array<void*, 8> samples{};
  std::array<dds_sample_info_t, 8> infos{};
  const auto n = cyclone::check(dds_take(reader, samples.data(), infos.data(), 8, 8), "dds_take");
  std::uint64_t newest = 0;
  for (dds_return_t i = 0; i < n; ++i) {
    if (!infos[static_cast<std::size_t>(i)].valid_data) continue;
    const auto& h = *static_cast<const mtc_idl_Heartbeat*>(samples[static_cast<std::size_t>(i)]);
    EXPECT_EQ(h.interaction_changes._length, 1U);
    if (h.interaction_changes._length == 1) {
      EXPECT_EQ(h.interaction_changes._buffer[0].changes, h.beat * 2);
    }
    newest = std::max(newest, h.beat);
  }
  if (n > 0) cyclone::check(dds_return_loan(reader, samples.data(), n), "dds_return_loan");
  return newest;
}

std::uint64_t take_beats(fdds::DataReader& reader) {
  idl::Heartbeat h;
  fdds::SampleInfo info;
  std::uint64_t newest = 0;
  while (reader.take_next_sample(&h, &info) ==
         eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK) {
    if (!info.valid_data) continue;
    EXPECT_EQ(h.interaction_changes().size(), 1U);
    if (h.interaction_changes().size() == 1) {
      EXPECT_EQ(h.interaction_changes()[0].changes(), h.beat() * 2);
    }
    newest = std::max(newest, h.beat());
  }
  return newest;
}

// Beats `kBeats` times through `beat(n)`, checking the reader all along;
// then stops, waits for the reader to see the writer lost and a deadline
// missed (printing how long each took); then beats once more and checks
// that the writer is alive again.
template <typename Beat, typename Reader>
void check_heartbeat_contract(Beat beat, Reader& reader) {
  std::uint64_t newest = 0;
  for (std::uint64_t n = 1; n <= kBeats; ++n) {
    beat(n);
    std::this_thread::sleep_for(100ms);  // the heartbeat period (a timer)
    newest = std::max(newest, take_beats(reader));
  }
  EXPECT_EQ(newest, static_cast<std::uint64_t>(kBeats));
  EXPECT_EQ(liveness_of(reader).alive, 1);
  EXPECT_EQ(liveness_of(reader).deadline_misses, 0);

  const auto stopped = Clock::now();
  ASSERT_TRUE(wait_until([&] { return liveness_of(reader).alive == 0; }, kLossBound))
      << "the writer never became not alive";
  const auto lost = Clock::now() - stopped;
  ASSERT_TRUE(wait_until([&] { return liveness_of(reader).deadline_misses > 0; }, kLossBound))
      << "no deadline missed";
  const auto missed = Clock::now() - stopped;
  std::printf(
      "lease 300 ms: not alive after %lld ms, deadline missed after %lld ms\n",
      static_cast<long long>(std::chrono::duration_cast<std::chrono::milliseconds>(lost).count()),
      static_cast<long long>(
          std::chrono::duration_cast<std::chrono::milliseconds>(missed).count()));

  beat(kBeats + 1);
  EXPECT_TRUE(wait_until([&] { return liveness_of(reader).alive == 1; }, kLossBound))
      << "the writer never came back";
}

TEST(HeartbeatInterop, FastDdsBeatsCycloneWatches) {
  CycloneReader cyclone(kFastBeatsDomain, mtc_idl_Heartbeat_desc, heartbeat_spec());
  FastWriter<idl::HeartbeatPubSubType> fast(kFastBeatsDomain, heartbeat_spec());
  ASSERT_TRUE(wait_until([&] { return fast.matched() == 1 && cyclone.matched() == 1; }));
  dds_entity_t reader = cyclone.get();
  check_heartbeat_contract([&](std::uint64_t n) { fast.writer().write(fast_beat(n)); }, reader);
}

TEST(HeartbeatInterop, CycloneBeatsFastDdsWatches) {
  FastReader<idl::HeartbeatPubSubType> fast(kCycloneBeatsDomain, heartbeat_spec());
  CycloneWriter cyclone(kCycloneBeatsDomain, mtc_idl_Heartbeat_desc, heartbeat_spec());
  ASSERT_TRUE(wait_until([&] { return fast.matched() == 1 && cyclone.matched() == 1; }));
  check_heartbeat_contract(
      [&](std::uint64_t n) {
        mtc_idl_InteractionChanges changes{};
        const auto h = cyclone_beat(n, changes);
        cyclone::check(dds_write(cyclone.get(), &h), "dds_write");
      },
      fast.reader());
}

}  // namespace
}  // namespace mtc::test::interop
