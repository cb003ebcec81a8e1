// Explains, in words, why a writer and a reader would not match.
//
// DDS silently refuses to match endpoints whose requested/offered QoS are
// incompatible: nothing arrives and no error is raised on either side.
// check_compatibility applies the same rules (DDS 1.4 section 2.2.3, "RxO")
// plus topic, type and partition matching, and returns every reason at once
// so that `mtc list` and the logs can say what to change.
#pragma once

#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <string>
#include <vector>

namespace mtc::qos {

struct WriterEndpoint {
  std::string topic_name;
  std::string type_name;
  eprosima::fastdds::dds::DataWriterQos qos;
  std::vector<std::string> partitions;  // publisher's; empty = default partition
};

struct ReaderEndpoint {
  std::string topic_name;
  std::string type_name;
  eprosima::fastdds::dds::DataReaderQos qos;
  std::vector<std::string> partitions;  // subscriber's; empty = default partition
};

struct Compatibility {
  bool compatible = true;
  std::vector<std::string> reasons;  // one sentence per incompatibility
};

// Never throws for any QoS values.
Compatibility check_compatibility(const WriterEndpoint& writer, const ReaderEndpoint& reader);

// True when the two partition lists share a partition (fnmatch-style wildcards
// on either side, as Fast DDS does; an empty list is the default partition "").
bool partitions_match(const std::vector<std::string>& a, const std::vector<std::string>& b);

}  // namespace mtc::qos
