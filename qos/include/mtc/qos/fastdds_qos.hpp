// The Fast DDS reading of endpoint_qos.hpp: an EndpointQos as Fast DDS 2.9
// DataWriterQos, DataReaderQos and TopicQos. Everything the EndpointQos does
// not set keeps the Fast DDS default. For qos/ and dds/ sources, tests and raw
// peers; no header of the runtime's public API includes it (cyclone_qos.hpp is
// the same reading for Cyclone DDS).
#pragma once

#include <chrono>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/dds/topic/qos/TopicQos.hpp>

#include "mtc/qos/endpoint_qos.hpp"

namespace mtc::qos {

// The writer side: the common policies, ownership strength, the RTPS
// HEARTBEAT period (reliable_heartbeat) and data-sharing off.
eprosima::fastdds::dds::DataWriterQos fastdds_writer_qos(const EndpointQos& endpoint);
// The reader side: the common policies with reader_depth() and
// reader_max_instances() in place of depth() and max_instances().
eprosima::fastdds::dds::DataReaderQos fastdds_reader_qos(const EndpointQos& endpoint);
eprosima::fastdds::dds::TopicQos fastdds_topic_qos(const EndpointQos& endpoint);

// Converts a std::chrono duration to a DDS Duration_t (infinite stays out:
// callers pass only finite periods).
eprosima::fastrtps::Duration_t to_duration(std::chrono::nanoseconds d) noexcept;
std::chrono::nanoseconds to_chrono(const eprosima::fastrtps::Duration_t& d) noexcept;

}  // namespace mtc::qos
