// check_compatibility names every reason two endpoints would not match.
#include <gtest/gtest.h>

#include <algorithm>

#include "mtc/qos/compatibility.hpp"
#include "mtc/qos/fastdds_qos.hpp"
#include "mtc/qos/presets.hpp"

namespace {

using namespace std::chrono_literals;
namespace fdds = eprosima::fastdds::dds;
using mtc::qos::check_compatibility;
using mtc::qos::ReaderEndpoint;
using mtc::qos::WriterEndpoint;

WriterEndpoint writer() {
  return {"mtc/InterfaceState",
          "mtc::idl::InterfaceStateSample",
          mtc::qos::fastdds_writer_qos(mtc::qos::state_topic()),
          {"mtc/dev/robot"}};
}
ReaderEndpoint reader() {
  return {"mtc/InterfaceState",
          "mtc::idl::InterfaceStateSample",
          mtc::qos::fastdds_reader_qos(mtc::qos::state_topic()),
          {"mtc/dev/*"}};
}

WriterEndpoint heartbeat_writer() {
  return {"mtc/Heartbeat",
          "mtc::idl::Heartbeat",
          mtc::qos::fastdds_writer_qos(mtc::qos::heartbeat_topic()),
          {"mtc/dev/robot"}};
}
ReaderEndpoint heartbeat_reader() {
  return {"mtc/Heartbeat",
          "mtc::idl::Heartbeat",
          mtc::qos::fastdds_reader_qos(mtc::qos::heartbeat_topic()),
          {"mtc/dev/*"}};
}

bool mentions(const mtc::qos::Compatibility& c, const std::string& word) {
  return std::any_of(c.reasons.begin(), c.reasons.end(),
                     [&](const std::string& r) { return r.find(word) != std::string::npos; });
}

TEST(Compatibility, PresetEndpointsMatch) {
  const auto c = check_compatibility(writer(), reader());
  EXPECT_TRUE(c.compatible);
  EXPECT_TRUE(c.reasons.empty());
  EXPECT_TRUE(check_compatibility(heartbeat_writer(), heartbeat_reader()).compatible);
}

TEST(Compatibility, ObserverAcceptsLeasesUpToItsOwn) {
  mtc::qos::Timing observer_timing;
  observer_timing.missed_heartbeats = 5;  // lease 500 ms
  ReaderEndpoint observer = heartbeat_reader();
  observer.qos = mtc::qos::fastdds_reader_qos(mtc::qos::heartbeat_observer_topic(observer_timing));
  mtc::qos::Timing device;  // 100 ms x 3: lease and deadline 300 ms
  WriterEndpoint w = heartbeat_writer();
  w.qos = mtc::qos::fastdds_writer_qos(mtc::qos::heartbeat_topic(device));
  EXPECT_TRUE(check_compatibility(w, observer).compatible);
  device.missed_heartbeats = 6;  // lease 600 ms: longer than the observer's
  w.qos = mtc::qos::fastdds_writer_qos(mtc::qos::heartbeat_topic(device));
  const auto c = check_compatibility(w, observer);
  EXPECT_FALSE(c.compatible);
  EXPECT_TRUE(mentions(c, "liveliness"));
}

TEST(Compatibility, BestEffortWriterCannotServeReliableReader) {
  auto w = writer();
  w.qos.reliability().kind = fdds::BEST_EFFORT_RELIABILITY_QOS;
  const auto c = check_compatibility(w, reader());
  EXPECT_FALSE(c.compatible);
  ASSERT_EQ(c.reasons.size(), 1u);
  EXPECT_TRUE(mentions(c, "reliability")) << c.reasons[0];
}

TEST(Compatibility, VolatileWriterCannotServeTransientLocalReader) {
  auto w = writer();
  w.qos.durability().kind = fdds::VOLATILE_DURABILITY_QOS;
  const auto c = check_compatibility(w, reader());
  EXPECT_FALSE(c.compatible);
  EXPECT_TRUE(mentions(c, "durability: reader requests TRANSIENT_LOCAL"));
}

TEST(Compatibility, OfferedDeadlineLongerThanRequested) {
  auto w = heartbeat_writer();
  w.qos.deadline().period = mtc::qos::to_duration(500ms);
  const auto c = check_compatibility(w, heartbeat_reader());
  EXPECT_FALSE(c.compatible);
  EXPECT_TRUE(mentions(c, "deadline: writer offers a period of 500 ms")) << c.reasons.at(0);
}

TEST(Compatibility, LivelinessKindAndLease) {
  auto w = heartbeat_writer();
  w.qos.liveliness().kind = fdds::AUTOMATIC_LIVELINESS_QOS;
  w.qos.liveliness().lease_duration = mtc::qos::to_duration(1s);
  const auto c = check_compatibility(w, heartbeat_reader());
  EXPECT_FALSE(c.compatible);
  EXPECT_EQ(c.reasons.size(), 2u);
  EXPECT_TRUE(mentions(c, "MANUAL_BY_TOPIC but writer offers the weaker AUTOMATIC"));
  EXPECT_TRUE(mentions(c, "lease of 1000 ms is longer than the 300 ms"));
}

TEST(Compatibility, OwnershipMustAgree) {
  auto w = writer();
  w.qos.ownership().kind = fdds::EXCLUSIVE_OWNERSHIP_QOS;
  const auto c = check_compatibility(w, reader());
  EXPECT_FALSE(c.compatible);
  EXPECT_TRUE(mentions(c, "ownership: writer is EXCLUSIVE, reader is SHARED"));
}

TEST(Compatibility, PartitionsTopicAndTypeAreExplained) {
  auto w = writer();
  auto r = reader();
  r.partitions = {"mtc/dev/cnc"};
  r.topic_name = "mtc/DoorState";
  r.type_name = "mtc::idl::DoorStateSample";
  const auto c = check_compatibility(w, r);
  EXPECT_FALSE(c.compatible);
  EXPECT_EQ(c.reasons.size(), 3u);
  EXPECT_TRUE(mentions(c, "partition"));
  EXPECT_TRUE(mentions(c, "topic"));
  EXPECT_TRUE(mentions(c, "type"));
}

TEST(Compatibility, StrongerOfferIsFine) {
  // A writer may offer more than requested: reliable to best-effort reader,
  // shorter deadline, shorter lease.
  auto r = heartbeat_reader();
  r.qos.reliability().kind = fdds::BEST_EFFORT_RELIABILITY_QOS;
  r.qos.deadline().period = mtc::qos::to_duration(10s);
  r.qos.liveliness().lease_duration = mtc::qos::to_duration(10s);
  EXPECT_TRUE(check_compatibility(heartbeat_writer(), r).compatible);
  auto state = reader();
  state.qos.reliability().kind = fdds::BEST_EFFORT_RELIABILITY_QOS;
  state.qos.durability().kind = fdds::VOLATILE_DURABILITY_QOS;
  EXPECT_TRUE(check_compatibility(writer(), state).compatible);
}

TEST(Partitions, WildcardsAndDefault) {
  using mtc::qos::partitions_match;
  EXPECT_TRUE(partitions_match({}, {}));
  EXPECT_TRUE(partitions_match({"mtc/dev/a"}, {"mtc/dev/*"}));
  EXPECT_TRUE(partitions_match({"*"}, {"x"}));
  EXPECT_FALSE(partitions_match({"mtc/dev/a"}, {"mtc/dev/b"}));
  EXPECT_FALSE(partitions_match({}, {"mtc/dev/a"}));
}

}  // namespace
