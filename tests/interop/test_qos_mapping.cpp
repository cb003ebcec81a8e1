// The same preset is the same contract on both middlewares: for every preset
// of mtc::qos, a writer and a reader are created on Fast DDS (fastdds_writer_qos(),
// fastdds_reader_qos()) and on Cyclone DDS (cyclone_writer_qos(), ...), and the
// policies each entity reports back (DataWriter::get_qos, dds_get_qos: what
// the middleware took, not what we asked for) are compared policy by policy.
// No traffic: the entities only exist. Domains 197 and 198 (a process holds
// one Cyclone domain instance per id, made here with our configuration, so
// the Cyclone writer and reader each get one), shared with the other interop
// tests under the ctest resource lock.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <ostream>
#include <stdexcept>
#include <string>
#include <tuple>

#include "interop_sides.hpp"
#include "mtc/idl_cyclone/mtconnect_interfaces.h"

namespace mtc::test::interop {
namespace {

constexpr int kDomain = 197;
constexpr int kCycloneReaderDomain = 198;
constexpr std::int64_t kInfinite = std::numeric_limits<std::int64_t>::max();

// The policies a preset sets, as neutral values (kinds as small integers in
// the order of the DDS specification, durations in ns, kInfinite for none).
struct Policies {
  int reliability = 0;  // 0 best effort, 1 reliable
  std::int64_t max_blocking_ns = 0;
  int durability = 0;  // 0 volatile, 1 transient local
  int history = 0;     // 0 keep last, 1 keep all
  std::int32_t depth = 0;
  std::int32_t max_samples = 0;
  std::int32_t max_instances = 0;
  std::int32_t max_samples_per_instance = 0;
  std::int64_t deadline_ns = 0;
  int liveliness = 0;  // 0 automatic, 1 manual by participant, 2 manual by topic
  std::int64_t lease_ns = 0;
  int ownership = 0;  // 0 shared, 1 exclusive

  auto tie() const {
    return std::tie(reliability, max_blocking_ns, durability, history, depth, max_samples,
                    max_instances, max_samples_per_instance, deadline_ns, liveliness, lease_ns,
                    ownership);
  }
  bool operator==(const Policies& o) const { return tie() == o.tie(); }
};

std::ostream& operator<<(std::ostream& os, const Policies& p) {
  return os << "{reliability " << p.reliability << " blocking " << p.max_blocking_ns
            << " durability " << p.durability << " history " << p.history << "/" << p.depth
            << " limits " << p.max_samples << "/" << p.max_instances << "/"
            << p.max_samples_per_instance << " deadline " << p.deadline_ns << " liveliness "
            << p.liveliness << "/" << p.lease_ns << " ownership " << p.ownership << "}";
}

std::int64_t ns(const eprosima::fastrtps::Duration_t& d) {
  if (d == eprosima::fastrtps::c_TimeInfinite) return kInfinite;
  return static_cast<std::int64_t>(d.seconds) * 1000000000 + d.nanosec;
}

// DataWriterQos and DataReaderQos have the same accessors, no common base.
template <typename Qos>
Policies from_fast(const Qos& q) {
  Policies p;
  p.reliability = q.reliability().kind == fdds::RELIABLE_RELIABILITY_QOS ? 1 : 0;
  p.max_blocking_ns = ns(q.reliability().max_blocking_time);
  p.durability = q.durability().kind == fdds::TRANSIENT_LOCAL_DURABILITY_QOS ? 1 : 0;
  p.history = q.history().kind == fdds::KEEP_ALL_HISTORY_QOS ? 1 : 0;
  p.depth = q.history().depth;
  p.max_samples = q.resource_limits().max_samples;
  p.max_instances = q.resource_limits().max_instances;
  p.max_samples_per_instance = q.resource_limits().max_samples_per_instance;
  p.deadline_ns = ns(q.deadline().period);
  p.liveliness = static_cast<int>(q.liveliness().kind);
  p.lease_ns = ns(q.liveliness().lease_duration);
  p.ownership = q.ownership().kind == fdds::EXCLUSIVE_OWNERSHIP_QOS ? 1 : 0;
  return p;
}

Policies from_cyclone(dds_entity_t entity) {
  qos::CycloneQos q(dds_create_qos());
  cyclone::check(dds_get_qos(entity, q.get()), "dds_get_qos");
  Policies p;
  dds_reliability_kind_t reliability{};
  dds_durability_kind_t durability{};
  dds_history_kind_t history{};
  dds_liveliness_kind_t liveliness{};
  dds_ownership_kind_t ownership{};
  const bool all = dds_qget_reliability(q.get(), &reliability, &p.max_blocking_ns) &&
                   dds_qget_durability(q.get(), &durability) &&
                   dds_qget_history(q.get(), &history, &p.depth) &&
                   dds_qget_resource_limits(q.get(), &p.max_samples, &p.max_instances,
                                            &p.max_samples_per_instance) &&
                   dds_qget_deadline(q.get(), &p.deadline_ns) &&
                   dds_qget_liveliness(q.get(), &liveliness, &p.lease_ns) &&
                   dds_qget_ownership(q.get(), &ownership);
  EXPECT_TRUE(all) << "a policy is missing from the Cyclone entity's QoS";
  p.reliability = reliability == DDS_RELIABILITY_RELIABLE ? 1 : 0;
  p.durability = durability == DDS_DURABILITY_TRANSIENT_LOCAL ? 1 : 0;
  p.history = history == DDS_HISTORY_KEEP_ALL ? 1 : 0;
  p.liveliness = static_cast<int>(liveliness);
  p.ownership = ownership == DDS_OWNERSHIP_EXCLUSIVE ? 1 : 0;
  return p;
}

// Topic names allow [A-Za-z0-9_/] on Cyclone: "mtc.state" -> "mtc/QosCheck/mtc_state".
std::string topic_for(const std::string& preset) {
  std::string name = preset;
  std::replace(name.begin(), name.end(), '.', '_');
  return "mtc/QosCheck/" + name;
}

class QosMapping : public ::testing::TestWithParam<std::string> {};

TEST_P(QosMapping, EffectivePoliciesAgree) {
  const auto endpoint = qos::preset(GetParam());
  const TopicSpec spec{topic_for(GetParam()), "mtc::idl::InteractionSample", endpoint};
  FastWriter<idl::InteractionSamplePubSubType> fast_writer(kDomain, spec);
  FastReader<idl::InteractionSamplePubSubType> fast_reader(kDomain, spec);
  CycloneWriter cyclone_writer(kDomain, mtc_idl_InteractionSample_desc, spec);
  CycloneReader cyclone_reader(kCycloneReaderDomain, mtc_idl_InteractionSample_desc, spec);

  const auto fast_w = from_fast(fast_writer.writer().get().get_qos());
  const auto fast_r = from_fast(fast_reader.reader().get_qos());
  EXPECT_EQ(from_cyclone(cyclone_writer.get()), fast_w) << "writer, preset " << GetParam();
  EXPECT_EQ(from_cyclone(cyclone_reader.get()), fast_r) << "reader, preset " << GetParam();
  // The presets' own promises, so that agreeing on a wrong value fails too.
  EXPECT_EQ(fast_w.reliability, 1);
  EXPECT_EQ(fast_w.durability, 1);
  EXPECT_EQ(fast_w.depth, endpoint.depth());
  EXPECT_EQ(fast_r.depth, endpoint.reader_depth());
  EXPECT_EQ(fast_r.max_instances, endpoint.reader_max_instances());
}

INSTANTIATE_TEST_SUITE_P(Presets, QosMapping, ::testing::ValuesIn(qos::preset_names()),
                         [](const auto& preset) {
                           std::string name = preset.param;
                           std::replace(name.begin(), name.end(), '.', '_');
                           return name;
                         });

// The network transport's configuration (the cell's hosts) is one Cyclone
// takes: a domain made from it exists, on the interfaces named or on the one
// Cyclone picks itself; an interface the host lacks is refused by Cyclone,
// and a name that would break the XML is refused before it. Domain 199.
TEST(CycloneNetworkConfig, CycloneTakesItAndItNamesEveryInterface) {
  const auto domain_from = [](const std::string& config) {
    const dds_entity_t domain = dds_create_domain(199, config.c_str());
    if (domain > 0) {
      EXPECT_EQ(dds_delete(domain), DDS_RETCODE_OK);
    }
    return domain;
  };
  const auto picked = qos::cyclone_network_config({}, {});
  EXPECT_NE(picked.find("autodetermine=\"true\""), std::string::npos) << picked;
  EXPECT_GT(domain_from(picked), 0) << picked;
  const auto named = qos::cyclone_network_config({}, {"lo"});
  EXPECT_NE(named.find("<NetworkInterface name=\"lo\"/>"), std::string::npos) << named;
  EXPECT_EQ(named.find("AllowMulticast"), std::string::npos) << "standard discovery: " << named;
  EXPECT_GT(domain_from(named), 0) << named;
  EXPECT_LT(domain_from(qos::cyclone_network_config({}, {"mtc-absent0"})), 0);
  EXPECT_THROW(qos::cyclone_network_config({}, {"eth0\"/><x"}), std::invalid_argument);
}

}  // namespace
}  // namespace mtc::test::interop
