// The code presets hold the documented values, and the XML profiles file
// (parsed by Fast DDS's own XMLProfileManager) carries the same presets.
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>
#include <fastrtps/attributes/ParticipantAttributes.h>
#include <fastrtps/attributes/PublisherAttributes.h>
#include <fastrtps/attributes/SubscriberAttributes.h>
#include <fastrtps/utils/IPLocator.h>
#include <fastrtps/xmlparser/XMLProfileManager.h>
#include <gtest/gtest.h>

#include <stdexcept>

#include "mtc/qos/fastdds_qos.hpp"
#include "mtc/qos/participant_qos.hpp"
#include "mtc/qos/presets.hpp"

namespace {

using namespace std::chrono_literals;
namespace fdds = eprosima::fastdds::dds;
namespace xml = eprosima::fastrtps::xmlparser;
using mtc::qos::to_duration;

TEST(Presets, StateTopicHoldsDocumentedPolicies) {
  const auto w = mtc::qos::fastdds_writer_qos(mtc::qos::state_topic());
  EXPECT_EQ(w.reliability().kind, fdds::RELIABLE_RELIABILITY_QOS);
  EXPECT_EQ(w.durability().kind, fdds::TRANSIENT_LOCAL_DURABILITY_QOS);
  EXPECT_EQ(w.history().kind, fdds::KEEP_LAST_HISTORY_QOS);
  EXPECT_EQ(w.history().depth, 1);
  // Changes only: an unchanged item is silent, liveness is the heartbeat's.
  EXPECT_EQ(w.deadline().period, eprosima::fastrtps::c_TimeInfinite);
  EXPECT_EQ(w.liveliness().kind, fdds::AUTOMATIC_LIVELINESS_QOS);
  EXPECT_EQ(w.liveliness().lease_duration, eprosima::fastrtps::c_TimeInfinite);
  EXPECT_EQ(w.reliable_writer_qos().times.heartbeatPeriod, to_duration(20ms));
  // Not Fast DDS's 0, which wakes its event thread on every write.
  EXPECT_EQ(w.reliable_writer_qos().times.nackSupressionDuration, to_duration(5ms));
  EXPECT_GE(w.resource_limits().max_instances, 1024);
  const auto r = mtc::qos::fastdds_reader_qos(mtc::qos::state_topic());
  EXPECT_EQ(r.reliability().kind, fdds::RELIABLE_RELIABILITY_QOS);
  EXPECT_EQ(r.deadline().period, eprosima::fastrtps::c_TimeInfinite);
  EXPECT_EQ(r.liveliness().kind, fdds::AUTOMATIC_LIVELINESS_QOS);
  EXPECT_EQ(r.history().depth, 8);  // bursts are handed over, not collapsed
  EXPECT_EQ(r.resource_limits().max_samples_per_instance, 8);
}

TEST(Presets, NackSuppressionIsAQuarterOfTheHeartbeatPeriodAtMostFiveMilliseconds) {
  // At most the Fast DDS reader's 5 ms HEARTBEAT response delay, so that no
  // NACK of a lost sample from such a reader is ever suppressed.
  EXPECT_EQ(mtc::qos::nack_suppression(20ms), 5ms);
  EXPECT_EQ(mtc::qos::nack_suppression(8ms), 2ms);
  EXPECT_EQ(mtc::qos::nack_suppression(100ms), 5ms);
  EXPECT_EQ(mtc::qos::nack_suppression(1ms), 250us);
  mtc::qos::Timing fast;
  fast.reliable_heartbeat = 8ms;
  const auto w = mtc::qos::fastdds_writer_qos(mtc::qos::state_topic(fast));
  EXPECT_EQ(w.reliable_writer_qos().times.nackSupressionDuration, to_duration(2ms));
}

TEST(Presets, HeartbeatTopicCarriesDeadlineAndLiveliness) {
  const auto w = mtc::qos::fastdds_writer_qos(mtc::qos::heartbeat_topic());
  EXPECT_EQ(w.reliability().kind, fdds::RELIABLE_RELIABILITY_QOS);
  EXPECT_EQ(w.durability().kind, fdds::TRANSIENT_LOCAL_DURABILITY_QOS);
  EXPECT_EQ(w.history().depth, 1);
  EXPECT_EQ(w.deadline().period, to_duration(300ms));
  EXPECT_EQ(w.liveliness().kind, fdds::MANUAL_BY_TOPIC_LIVELINESS_QOS);
  EXPECT_EQ(w.liveliness().lease_duration, to_duration(300ms));
  EXPECT_EQ(w.reliable_writer_qos().times.heartbeatPeriod, to_duration(20ms));
  const auto r = mtc::qos::fastdds_reader_qos(mtc::qos::heartbeat_topic());
  EXPECT_EQ(r.deadline().period, to_duration(300ms));
  EXPECT_EQ(r.liveliness().kind, fdds::MANUAL_BY_TOPIC_LIVELINESS_QOS);
  EXPECT_EQ(r.liveliness().lease_duration, to_duration(300ms));
  EXPECT_EQ(r.history().depth, 1);
}

TEST(Presets, ObserverReadsHeartbeatsByLivelinessWithoutDeadline) {
  const auto r = mtc::qos::fastdds_reader_qos(mtc::qos::heartbeat_observer_topic());
  EXPECT_EQ(r.reliability().kind, fdds::RELIABLE_RELIABILITY_QOS);
  EXPECT_EQ(r.durability().kind, fdds::TRANSIENT_LOCAL_DURABILITY_QOS);
  EXPECT_EQ(r.deadline().period, eprosima::fastrtps::c_TimeInfinite);
  EXPECT_EQ(r.liveliness().kind, fdds::MANUAL_BY_TOPIC_LIVELINESS_QOS);
  EXPECT_EQ(r.liveliness().lease_duration, to_duration(300ms));
  EXPECT_EQ(r.resource_limits().max_instances, 16384);
  // The observer's state reader is the equipment's.
  const auto state = mtc::qos::fastdds_reader_qos(mtc::qos::state_observer_topic());
  const auto equipment = mtc::qos::fastdds_reader_qos(mtc::qos::state_topic());
  EXPECT_EQ(state.durability().kind, fdds::TRANSIENT_LOCAL_DURABILITY_QOS);
  EXPECT_EQ(state.history().depth, equipment.history().depth);
  EXPECT_EQ(state.resource_limits().max_instances, 16384);
  EXPECT_EQ(state.resource_limits().max_samples, equipment.resource_limits().max_samples);
  EXPECT_EQ(state.ownership().kind, equipment.ownership().kind);
  EXPECT_EQ(state.liveliness().kind, equipment.liveliness().kind);
}

TEST(Presets, ReadersHoldEveryDevicesInstancesWritersTheirOwn) {
  for (const auto& preset : {mtc::qos::state_topic(), mtc::qos::device_description_topic(),
                             mtc::qos::heartbeat_topic()}) {
    EXPECT_EQ(mtc::qos::fastdds_writer_qos(preset).resource_limits().max_instances, 1024);
    EXPECT_EQ(mtc::qos::fastdds_reader_qos(preset).resource_limits().max_instances, 16384);
  }
}

TEST(Presets, TimingIsConfigurablePerInterface) {
  mtc::qos::Timing t;
  t.heartbeat = 50ms;
  t.missed_heartbeats = 4;
  t.reliable_heartbeat = 10ms;
  const auto w = mtc::qos::fastdds_writer_qos(mtc::qos::heartbeat_topic(t));
  EXPECT_EQ(w.deadline().period, to_duration(200ms));
  EXPECT_EQ(w.liveliness().lease_duration, to_duration(200ms));
  EXPECT_EQ(w.reliable_writer_qos().times.heartbeatPeriod, to_duration(10ms));
  EXPECT_EQ(mtc::qos::fastdds_writer_qos(mtc::qos::state_topic(t))
                .reliable_writer_qos()
                .times.heartbeatPeriod,
            to_duration(10ms));
}

TEST(Presets, DeviceDescriptionHasNeitherDeadlineNorLease) {
  const auto w = mtc::qos::fastdds_writer_qos(mtc::qos::device_description_topic());
  EXPECT_EQ(w.durability().kind, fdds::TRANSIENT_LOCAL_DURABILITY_QOS);
  EXPECT_EQ(w.deadline().period, eprosima::fastrtps::c_TimeInfinite);
  EXPECT_EQ(w.liveliness().kind, fdds::AUTOMATIC_LIVELINESS_QOS);
  EXPECT_EQ(w.liveliness().lease_duration, eprosima::fastrtps::c_TimeInfinite);
}

TEST(Presets, BadTimingIsRejectedWithAReason) {
  mtc::qos::Timing t;
  t.missed_heartbeats = 1;
  EXPECT_THROW(mtc::qos::state_topic(t), std::invalid_argument);
  t = {};
  t.heartbeat = 0ms;
  EXPECT_THROW(mtc::qos::state_topic(t), std::invalid_argument);
  t = {};
  t.reliable_heartbeat = 1s;
  EXPECT_THROW(mtc::qos::state_topic(t), std::invalid_argument);
  EXPECT_THROW(mtc::qos::preset("no.such.preset"), std::invalid_argument);
  EXPECT_NO_THROW(mtc::qos::preset("mtc.device_description"));
  EXPECT_NO_THROW(mtc::qos::preset("mtc.heartbeat_observer"));
}

class XmlProfiles : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    ASSERT_EQ(xml::XMLProfileManager::loadXMLFile(MTC_QOS_PROFILES_SOURCE), xml::XMLP_ret::XML_OK);
  }
};

void expect_same_writer(const std::string& profile, const fdds::DataWriterQos& code) {
  eprosima::fastrtps::PublisherAttributes a;
  ASSERT_EQ(xml::XMLProfileManager::fillPublisherAttributes(profile, a), xml::XMLP_ret::XML_OK)
      << profile;
  EXPECT_EQ(a.qos.m_reliability.kind, code.reliability().kind) << profile;
  EXPECT_EQ(a.qos.m_durability.kind, code.durability().kind) << profile;
  EXPECT_EQ(a.qos.m_deadline.period, code.deadline().period) << profile;
  EXPECT_EQ(a.qos.m_liveliness.kind, code.liveliness().kind) << profile;
  EXPECT_EQ(a.qos.m_liveliness.lease_duration, code.liveliness().lease_duration) << profile;
  EXPECT_EQ(a.qos.m_liveliness.announcement_period, code.liveliness().announcement_period);
  EXPECT_EQ(a.qos.m_ownership.kind, code.ownership().kind) << profile;
  EXPECT_EQ(a.topic.historyQos.kind, code.history().kind) << profile;
  EXPECT_EQ(a.topic.historyQos.depth, code.history().depth) << profile;
  EXPECT_EQ(a.topic.resourceLimitsQos.max_instances, code.resource_limits().max_instances);
  EXPECT_EQ(a.topic.resourceLimitsQos.max_samples, code.resource_limits().max_samples);
  EXPECT_EQ(a.topic.resourceLimitsQos.max_samples_per_instance,
            code.resource_limits().max_samples_per_instance);
  EXPECT_EQ(a.topic.resourceLimitsQos.allocated_samples, code.resource_limits().allocated_samples)
      << profile;
  EXPECT_EQ(a.historyMemoryPolicy, code.endpoint().history_memory_policy) << profile;
  EXPECT_EQ(a.times.heartbeatPeriod, code.reliable_writer_qos().times.heartbeatPeriod) << profile;
  EXPECT_EQ(a.times.nackSupressionDuration, code.reliable_writer_qos().times.nackSupressionDuration)
      << profile;
}

void expect_same_reader(const std::string& profile, const fdds::DataReaderQos& code) {
  eprosima::fastrtps::SubscriberAttributes a;
  ASSERT_EQ(xml::XMLProfileManager::fillSubscriberAttributes(profile, a), xml::XMLP_ret::XML_OK)
      << profile;
  EXPECT_EQ(a.qos.m_reliability.kind, code.reliability().kind) << profile;
  EXPECT_EQ(a.qos.m_durability.kind, code.durability().kind) << profile;
  EXPECT_EQ(a.qos.m_deadline.period, code.deadline().period) << profile;
  EXPECT_EQ(a.qos.m_liveliness.kind, code.liveliness().kind) << profile;
  EXPECT_EQ(a.qos.m_liveliness.lease_duration, code.liveliness().lease_duration) << profile;
  EXPECT_EQ(a.qos.m_ownership.kind, code.ownership().kind) << profile;
  EXPECT_EQ(a.topic.historyQos.depth, code.history().depth) << profile;
  EXPECT_EQ(a.topic.resourceLimitsQos.max_instances, code.resource_limits().max_instances);
  EXPECT_EQ(a.topic.resourceLimitsQos.max_samples, code.resource_limits().max_samples);
  EXPECT_EQ(a.topic.resourceLimitsQos.max_samples_per_instance,
            code.resource_limits().max_samples_per_instance);
  EXPECT_EQ(a.topic.resourceLimitsQos.allocated_samples, code.resource_limits().allocated_samples)
      << profile;
  EXPECT_EQ(a.historyMemoryPolicy, code.endpoint().history_memory_policy) << profile;
}

TEST_F(XmlProfiles, EndpointProfilesMatchCodePresets) {
  for (const auto name : {mtc::qos::kStateProfile, mtc::qos::kHeartbeatProfile}) {
    const auto preset = mtc::qos::preset(name);
    expect_same_writer(std::string(name) + ".writer", mtc::qos::fastdds_writer_qos(preset));
    expect_same_reader(std::string(name) + ".reader", mtc::qos::fastdds_reader_qos(preset));
  }
  // The announcement's memory as the runtime sets it (announcement_memory).
  auto writer = mtc::qos::fastdds_writer_qos(mtc::qos::device_description_topic());
  auto reader = mtc::qos::fastdds_reader_qos(mtc::qos::device_description_topic());
  mtc::qos::announcement_memory(writer);
  mtc::qos::announcement_memory(reader);
  const std::string description(mtc::qos::kDeviceDescriptionProfile);
  expect_same_writer(description + ".writer", writer);
  expect_same_reader(description + ".reader", reader);
  // An observer only reads.
  expect_same_reader(std::string(mtc::qos::kStateObserverProfile) + ".reader",
                     mtc::qos::fastdds_reader_qos(mtc::qos::state_observer_topic()));
  expect_same_reader(std::string(mtc::qos::kHeartbeatObserverProfile) + ".reader",
                     mtc::qos::fastdds_reader_qos(mtc::qos::heartbeat_observer_topic()));
}

TEST_F(XmlProfiles, EveryPresetHasAReaderProfile) {
  for (const auto& name : mtc::qos::preset_names()) {
    eprosima::fastrtps::SubscriberAttributes a;
    EXPECT_EQ(xml::XMLProfileManager::fillSubscriberAttributes(name + ".reader", a),
              xml::XMLP_ret::XML_OK)
        << name;
  }
}

void expect_loopback_participant(const std::string& profile, bool with_shm) {
  eprosima::fastrtps::ParticipantAttributes a;
  ASSERT_EQ(xml::XMLProfileManager::fillParticipantAttributes(profile, a), xml::XMLP_ret::XML_OK);
  mtc::qos::ParticipantConfig config;
  config.transport = with_shm ? mtc::qos::Transport::Loopback : mtc::qos::Transport::LoopbackUdp;
  const auto code = mtc::qos::participant_qos(config);
  const auto& disc = a.rtps.builtin.discovery_config;
  EXPECT_EQ(disc.leaseDuration, code.wire_protocol().builtin.discovery_config.leaseDuration);
  EXPECT_EQ(disc.leaseDuration_announcementperiod,
            code.wire_protocol().builtin.discovery_config.leaseDuration_announcementperiod);
  // Discovery by unicast on 127.0.0.1 only, in the file as in the code.
  const auto& builtin = code.wire_protocol().builtin;
  EXPECT_EQ(a.rtps.builtin.initialPeersList, builtin.initialPeersList);
  EXPECT_EQ(a.rtps.builtin.metatrafficUnicastLocatorList, builtin.metatrafficUnicastLocatorList);
  EXPECT_TRUE(builtin.metatrafficMulticastLocatorList.empty());
  EXPECT_TRUE(a.rtps.builtin.metatrafficMulticastLocatorList.empty());
  ASSERT_EQ(builtin.initialPeersList.size(), 1u);
  EXPECT_EQ(eprosima::fastrtps::rtps::IPLocator::toIPv4string(*builtin.initialPeersList.begin()),
            "127.0.0.1");
  EXPECT_FALSE(a.rtps.useBuiltinTransports);
  EXPECT_EQ(a.rtps.useBuiltinTransports, code.transport().use_builtin_transports);
  ASSERT_EQ(a.rtps.userTransports.size(), code.transport().user_transports.size());
  int udp = 0;
  int shm = 0;
  for (const auto& t : a.rtps.userTransports) {
    if (auto u = std::dynamic_pointer_cast<eprosima::fastdds::rtps::UDPv4TransportDescriptor>(t)) {
      ++udp;
      EXPECT_EQ(u->interfaceWhiteList, std::vector<std::string>{"127.0.0.1"});
      EXPECT_EQ(u->maxInitialPeersRange, 32u);
    } else if (std::dynamic_pointer_cast<eprosima::fastdds::rtps::SharedMemTransportDescriptor>(
                   t)) {
      ++shm;
    }
  }
  EXPECT_EQ(udp, 1);
  EXPECT_EQ(shm, with_shm ? 1 : 0);
}

TEST_F(XmlProfiles, ParticipantProfilesAreLoopbackOnlyAndMatchCode) {
  expect_loopback_participant(std::string(mtc::qos::kLoopbackParticipantProfile), true);
  expect_loopback_participant(std::string(mtc::qos::kLoopbackUdpParticipantProfile), false);
}

// The default transport is the network (issue 10): what Fast DDS's builtin
// transports are (SHM + UDPv4 on every interface) and its default discovery,
// exactly as PARTICIPANT_QOS_DEFAULT has them, except that a UDP send never
// blocks (a pulled cable stalled a blocking send for 2 s).
TEST(Profiles, TheDefaultTransportIsTheNetworkWithSendsThatNeverBlock) {
  // transport-guard: the default itself is under test
  const mtc::qos::ParticipantConfig config;
  EXPECT_EQ(config.transport, mtc::qos::Transport::Network);
  const auto code = mtc::qos::participant_qos(config);
  const auto& fast_dds = eprosima::fastdds::dds::PARTICIPANT_QOS_DEFAULT;
  EXPECT_FALSE(code.transport().use_builtin_transports);
  const auto& user = code.transport().user_transports;
  ASSERT_EQ(user.size(), 2U);
  EXPECT_NE(
      std::dynamic_pointer_cast<eprosima::fastdds::rtps::SharedMemTransportDescriptor>(user[0]),
      nullptr);
  const auto udp =
      std::dynamic_pointer_cast<eprosima::fastdds::rtps::UDPv4TransportDescriptor>(user[1]);
  ASSERT_NE(udp, nullptr);
  EXPECT_TRUE(udp->non_blocking_send);
  EXPECT_TRUE(udp->interfaceWhiteList.empty()) << "every interface, as the builtin one";
  EXPECT_EQ(udp->sendBufferSize,
            eprosima::fastdds::rtps::UDPv4TransportDescriptor().sendBufferSize);
  const auto& builtin = code.wire_protocol().builtin;
  EXPECT_EQ(builtin.initialPeersList, fast_dds.wire_protocol().builtin.initialPeersList);
  EXPECT_EQ(builtin.metatrafficUnicastLocatorList,
            fast_dds.wire_protocol().builtin.metatrafficUnicastLocatorList);
  EXPECT_EQ(builtin.metatrafficMulticastLocatorList,
            fast_dds.wire_protocol().builtin.metatrafficMulticastLocatorList);
  EXPECT_EQ(code.wire_protocol().default_multicast_locator_list,
            fast_dds.wire_protocol().default_multicast_locator_list);
}

TEST(Profiles, ParticipantProfilesAndTransportNames) {
  EXPECT_EQ(mtc::qos::participant_config("mtc.participant.loopback_udp").transport,
            mtc::qos::Transport::LoopbackUdp);
  EXPECT_THROW(mtc::qos::participant_config("nope"), std::invalid_argument);
  for (auto t : mtc::qos::kAllTransports) {
    EXPECT_EQ(mtc::qos::parse_transport(mtc::qos::to_string(t)), t);
  }
  EXPECT_EQ(mtc::qos::to_string(mtc::qos::Transport::Network), "network");
  EXPECT_FALSE(mtc::qos::parse_transport("udp6").has_value());
  // One name per transport: the former spelling is gone.
  EXPECT_FALSE(mtc::qos::parse_transport("builtin").has_value());
}

TEST(Profiles, FilePathPointsAtAnExistingFile) {
  const auto path = mtc::qos::profiles_file_path();
  ASSERT_FALSE(path.empty());
  EXPECT_EQ(xml::XMLProfileManager::loadXMLFile(path), xml::XMLP_ret::XML_OK);
}

}  // namespace
