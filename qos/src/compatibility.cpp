#include "mtc/qos/compatibility.hpp"

#include <fnmatch.h>

#include <sstream>

#include "mtc/qos/fastdds_qos.hpp"

namespace mtc::qos {

namespace fdds = eprosima::fastdds::dds;

namespace {

std::string describe(const eprosima::fastrtps::Duration_t& d) {
  if (d == eprosima::fastrtps::c_TimeInfinite) {
    return "infinite";
  }
  std::ostringstream out;
  const auto us = std::chrono::duration_cast<std::chrono::microseconds>(to_chrono(d)).count();
  out << static_cast<double>(us) / 1000.0 << " ms";
  return out.str();
}

const char* name(fdds::ReliabilityQosPolicyKind k) {
  return k == fdds::RELIABLE_RELIABILITY_QOS ? "RELIABLE" : "BEST_EFFORT";
}

const char* name(fdds::DurabilityQosPolicyKind k) {
  switch (k) {
    case fdds::VOLATILE_DURABILITY_QOS:
      return "VOLATILE";
    case fdds::TRANSIENT_LOCAL_DURABILITY_QOS:
      return "TRANSIENT_LOCAL";
    case fdds::TRANSIENT_DURABILITY_QOS:
      return "TRANSIENT";
    case fdds::PERSISTENT_DURABILITY_QOS:
      return "PERSISTENT";
  }
  return "?";
}

const char* name(fdds::LivelinessQosPolicyKind k) {
  switch (k) {
    case fdds::AUTOMATIC_LIVELINESS_QOS:
      return "AUTOMATIC";
    case fdds::MANUAL_BY_PARTICIPANT_LIVELINESS_QOS:
      return "MANUAL_BY_PARTICIPANT";
    case fdds::MANUAL_BY_TOPIC_LIVELINESS_QOS:
      return "MANUAL_BY_TOPIC";
  }
  return "?";
}

const char* name(fdds::OwnershipQosPolicyKind k) {
  return k == fdds::EXCLUSIVE_OWNERSHIP_QOS ? "EXCLUSIVE" : "SHARED";
}

// Orders the liveliness kinds by strength (the enum values are not ordered).
int strength(fdds::LivelinessQosPolicyKind k) {
  switch (k) {
    case fdds::AUTOMATIC_LIVELINESS_QOS:
      return 0;
    case fdds::MANUAL_BY_PARTICIPANT_LIVELINESS_QOS:
      return 1;
    case fdds::MANUAL_BY_TOPIC_LIVELINESS_QOS:
      return 2;
  }
  return 0;
}

bool partition_pair_matches(const std::string& a, const std::string& b) {
  return a == b || fnmatch(a.c_str(), b.c_str(), 0) == 0 || fnmatch(b.c_str(), a.c_str(), 0) == 0;
}

std::string join(const std::vector<std::string>& v) {
  if (v.empty()) {
    return "[\"\" (default)]";
  }
  std::string out = "[";
  for (std::size_t i = 0; i < v.size(); ++i) {
    out += (i > 0 ? ", \"" : "\"") + v[i] + "\"";
  }
  return out + "]";
}

void check_policies(const fdds::DataWriterQos& w, const fdds::DataReaderQos& r,
                    std::vector<std::string>& reasons) {
  if (w.reliability().kind == fdds::BEST_EFFORT_RELIABILITY_QOS &&
      r.reliability().kind == fdds::RELIABLE_RELIABILITY_QOS) {
    reasons.push_back(std::string("reliability: reader requests RELIABLE but writer offers ") +
                      name(w.reliability().kind));
  }
  if (w.durability().kind < r.durability().kind) {
    reasons.push_back(std::string("durability: reader requests ") + name(r.durability().kind) +
                      " but writer offers only " + name(w.durability().kind));
  }
  if (w.deadline().period > r.deadline().period) {
    reasons.push_back("deadline: writer offers a period of " + describe(w.deadline().period) +
                      ", longer than the " + describe(r.deadline().period) +
                      " the reader requests");
  }
  if (w.latency_budget().duration > r.latency_budget().duration) {
    reasons.push_back("latency budget: writer's " + describe(w.latency_budget().duration) +
                      " exceeds the reader's " + describe(r.latency_budget().duration));
  }
  if (strength(w.liveliness().kind) < strength(r.liveliness().kind)) {
    reasons.push_back(std::string("liveliness: reader requests ") + name(r.liveliness().kind) +
                      " but writer offers the weaker " + name(w.liveliness().kind));
  }
  if (w.liveliness().lease_duration > r.liveliness().lease_duration) {
    reasons.push_back("liveliness: writer's lease of " + describe(w.liveliness().lease_duration) +
                      " is longer than the " + describe(r.liveliness().lease_duration) +
                      " the reader requests");
  }
  if (w.ownership().kind != r.ownership().kind) {
    reasons.push_back(std::string("ownership: writer is ") + name(w.ownership().kind) +
                      ", reader is " + name(r.ownership().kind));
  }
  if (w.destination_order().kind < r.destination_order().kind) {
    reasons.emplace_back(
        "destination order: reader requests BY_SOURCE_TIMESTAMP but writer offers "
        "BY_RECEPTION_TIMESTAMP");
  }
}

}  // namespace

bool partitions_match(const std::vector<std::string>& a, const std::vector<std::string>& b) {
  const std::vector<std::string> def{""};
  const auto& aa = a.empty() ? def : a;
  const auto& bb = b.empty() ? def : b;
  for (const auto& x : aa) {
    for (const auto& y : bb) {
      if (partition_pair_matches(x, y)) {
        return true;
      }
    }
  }
  return false;
}

Compatibility check_compatibility(const WriterEndpoint& writer, const ReaderEndpoint& reader) {
  Compatibility result;
  auto& reasons = result.reasons;
  if (writer.topic_name != reader.topic_name) {
    reasons.push_back("topic: writer publishes \"" + writer.topic_name +
                      "\" but reader subscribes to \"" + reader.topic_name + "\"");
  }
  if (writer.type_name != reader.type_name) {
    reasons.push_back("type: writer's type \"" + writer.type_name + "\" differs from reader's \"" +
                      reader.type_name + "\"");
  }
  check_policies(writer.qos, reader.qos, reasons);
  if (!partitions_match(writer.partitions, reader.partitions)) {
    reasons.push_back("partition: writer's partitions " + join(writer.partitions) +
                      " share none with reader's " + join(reader.partitions));
  }
  result.compatible = reasons.empty();
  return result;
}

}  // namespace mtc::qos
