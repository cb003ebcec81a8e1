#include "mtc/qos/cyclone_qos.hpp"

#include <algorithm>
#include <chrono>
#include <iterator>
#include <new>
#include <stdexcept>
#include <string>

namespace mtc::qos {

namespace {

CycloneQos make_qos() {
  CycloneQos qos(dds_create_qos());
  if (!qos) throw std::bad_alloc();
  return qos;
}

dds_duration_t to_cyclone(std::chrono::nanoseconds d) noexcept {
  return static_cast<dds_duration_t>(d.count());
}

// The policies fastdds_writer_qos(), fastdds_reader_qos() and
// fastdds_topic_qos() share, the same values as apply_common() in
// fastdds_qos.cpp gives Fast DDS.
void apply_common(const EndpointQos& e, dds_qos_t* q) {
  // 100 ms: Fast DDS's default max_blocking_time, set so both block alike.
  dds_qset_reliability(q,
                       e.reliability() == Reliability::Reliable ? DDS_RELIABILITY_RELIABLE
                                                                : DDS_RELIABILITY_BEST_EFFORT,
                       DDS_MSECS(100));
  dds_qset_durability(q, e.durability() == Durability::TransientLocal
                             ? DDS_DURABILITY_TRANSIENT_LOCAL
                             : DDS_DURABILITY_VOLATILE);
  if (e.is_keep_all()) {
    dds_qset_history(q, DDS_HISTORY_KEEP_ALL, 1);
  } else {
    dds_qset_history(q, DDS_HISTORY_KEEP_LAST, e.depth());
  }
  const std::int32_t per_instance = e.is_keep_all() ? 64 : e.depth();
  dds_qset_resource_limits(q, e.max_instances() * per_instance, e.max_instances(), per_instance);
  if (e.deadline()) dds_qset_deadline(q, to_cyclone(*e.deadline()));
  dds_liveliness_kind_t kind = DDS_LIVELINESS_AUTOMATIC;
  switch (e.liveliness_kind()) {
    case Liveliness::Automatic:
      break;
    case Liveliness::ManualByParticipant:
      kind = DDS_LIVELINESS_MANUAL_BY_PARTICIPANT;
      break;
    case Liveliness::ManualByTopic:
      kind = DDS_LIVELINESS_MANUAL_BY_TOPIC;
      break;
  }
  dds_qset_liveliness(q, kind,
                      e.liveliness_lease() ? to_cyclone(*e.liveliness_lease()) : DDS_INFINITY);
  dds_qset_ownership(
      q, e.ownership() == Ownership::Exclusive ? DDS_OWNERSHIP_EXCLUSIVE : DDS_OWNERSHIP_SHARED);
}

}  // namespace

CycloneQos cyclone_topic_qos(const EndpointQos& endpoint) {
  auto qos = make_qos();
  apply_common(endpoint, qos.get());
  return qos;
}

CycloneQos cyclone_writer_qos(const EndpointQos& endpoint) {
  auto qos = make_qos();
  apply_common(endpoint, qos.get());
  dds_qset_ownership_strength(qos.get(), endpoint.ownership_strength());
  // No disposal but an explicit one. With the default (true), a Cyclone
  // reader turns a Cyclone writer's loss of liveliness (a process stopped
  // for a lease) into NOT_ALIVE_DISPOSED, which the runtime takes for the
  // graceful leave of that incarnation and stops listening to it: a SIGSTOPped
  // peer, resumed, was never heard again. The graceful leave disposes
  // explicitly, so it still reads as one.
  dds_qset_writer_data_lifecycle(qos.get(), false);
  // Cyclone would pick XCDR2 for some types; Fast DDS 2.9 reads XCDR1 only.
  const dds_data_representation_id_t xcdr1 = DDS_DATA_REPRESENTATION_XCDR1;
  dds_qset_data_representation(qos.get(), 1, &xcdr1);
  return qos;
}

CycloneQos cyclone_reader_qos(const EndpointQos& endpoint) {
  // Readers keep reader_depth() per instance and room for every device's
  // items, as EndpointQos::reader_qos() does for Fast DDS.
  auto reader = endpoint;
  if (!reader.is_keep_all()) reader.keep_last(reader.reader_depth());
  reader.max_instances(reader.reader_max_instances());
  auto qos = make_qos();
  apply_common(reader, qos.get());
  return qos;
}

CycloneQos cyclone_partition_qos(const std::vector<std::string>& partitions) {
  auto qos = make_qos();
  std::vector<const char*> names;
  names.reserve(partitions.size());
  std::transform(partitions.begin(), partitions.end(), std::back_inserter(names),
                 [](const std::string& p) { return p.c_str(); });
  dds_qset_partition(qos.get(), static_cast<uint32_t>(names.size()), names.data());
  return qos;
}

namespace {

std::string ms(std::chrono::milliseconds d) {
  return std::to_string(d.count()) + "ms";
}

// Discovery and RTPS timing from `timing`, and key hashes (below), shared by
// both configurations. GenerateKeyhash: Fast DDS 2.9 takes a deleted
// endpoint's SEDP disposal by its key hash alone; without one, a Fast DDS
// reader never unmatches a Cyclone writer deleted while its participant lives
// (Mw/Backends.ADeletedWriterIsReportedUnmatched/CycloneToFastDds).
std::string lease_and_heartbeat(const Timing& timing) {
  return "<LeaseDuration>" + ms(timing.participant_lease) + "</LeaseDuration><SPDPInterval>" +
         ms(timing.participant_announcement) + "</SPDPInterval></Discovery>" +
         "<Internal><GenerateKeyhash>true</GenerateKeyhash><HeartbeatInterval>" +
         ms(timing.reliable_heartbeat) + "</HeartbeatInterval></Internal>";
}

}  // namespace

std::string cyclone_loopback_config(const Timing& timing) {
  validate(timing);
  // Peers 127.0.0.1 with participant index auto: Cyclone announces itself to
  // the well-known unicast discovery ports of the first 32 participant
  // indices on 127.0.0.1 and listens on one of them, which is what Fast DDS's
  // loopback transports do too, so the two find each other without multicast.
  return "<CycloneDDS><Domain Id=\"any\">"
         "<General><Interfaces><NetworkInterface name=\"lo\"/></Interfaces>"
         "<AllowMulticast>false</AllowMulticast></General>"
         "<Discovery><Peers><Peer address=\"127.0.0.1\"/></Peers>"
         "<ParticipantIndex>auto</ParticipantIndex>"
         "<MaxAutoParticipantIndex>31</MaxAutoParticipantIndex>" +
         lease_and_heartbeat(timing) + "</Domain></CycloneDDS>";
}

std::string cyclone_network_config(const Timing& timing,
                                   const std::vector<std::string>& interfaces) {
  validate(timing);
  // Discovery is the standard's: SPDP multicast to 239.255.0.1 on the
  // domain's port, as Fast DDS's built-in UDP transport does, so either finds
  // the other across hosts with no configuration shared between them.
  std::string config = "<CycloneDDS><Domain Id=\"any\"><General><Interfaces>";
  if (interfaces.empty()) {
    config += "<NetworkInterface autodetermine=\"true\"/>";
  }
  for (const auto& name : interfaces) {
    if (name.empty() || name.find_first_of("<>&\"'") != std::string::npos) {
      throw std::invalid_argument("network interface name '" + name +
                                  "' cannot go into a Cyclone configuration");
    }
    config += "<NetworkInterface name=\"" + name + "\"/>";
  }
  return config + "</Interfaces></General><Discovery>" + lease_and_heartbeat(timing) +
         "</Domain></CycloneDDS>";
}

}  // namespace mtc::qos
