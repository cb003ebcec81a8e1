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
// HEARTBEAT period (reliable_heartbeat) with its NACK suppression window
// (nack_suppression()) and data-sharing off.
eprosima::fastdds::dds::DataWriterQos fastdds_writer_qos(const EndpointQos& endpoint);

// The RTPS nackSuppressionDuration of a reliable writer whose HEARTBEAT
// period is `heartbeat_period`: a quarter of it, at most 5 ms. Why not Fast
// DDS's 0: in 2.9 every DATA sent restarts a per-reader suppression timer,
// and a timer that is not running wakes the participant's event thread,
// which at 0 fires at once and takes the writer's mutex while the writing
// thread still holds it: two to four futex wake-ups in the middle of every
// write (docs/benchmarks.md, "NACK suppression"). With a window, only the
// first write of a burst starts the timer. Why at most 5 ms: a NACK of a lost
// sample answers a HEARTBEAT sent after it, and a Fast DDS reader answers a
// HEARTBEAT after its heartbeatResponseDelay, 5 ms, so no NACK from such a
// reader ever falls in the window; one from a quicker reader (Cyclone) that
// does is answered at the next HEARTBEAT period.
std::chrono::nanoseconds nack_suppression(std::chrono::nanoseconds heartbeat_period) noexcept;
// The reader side: the common policies with reader_depth() and
// reader_max_instances() in place of depth() and max_instances().
eprosima::fastdds::dds::DataReaderQos fastdds_reader_qos(const EndpointQos& endpoint);
eprosima::fastdds::dds::TopicQos fastdds_topic_qos(const EndpointQos& endpoint);

// For the device announcement, whose samples hold far less than their type's
// bound (1.7 MB for 128 interfaces; a few KB written): Fast DDS reserves the
// bound for each of allocated_samples history slots up front (100 by
// default: hundreds of MB per process). The writer, which holds one sample,
// sizes each to what it holds (a dynamic memory policy); the reader reserves
// one slot and adds one per device it hears from. A dynamic policy on the
// reader side too made a Fast DDS reader miss a Cyclone device's return
// (docs/fastdds-notes.md, "The announcement's memory").
void announcement_memory(eprosima::fastdds::dds::DataWriterQos& q) noexcept;
void announcement_memory(eprosima::fastdds::dds::DataReaderQos& q) noexcept;

// Converts a std::chrono duration to a DDS Duration_t (infinite stays out:
// callers pass only finite periods).
eprosima::fastrtps::Duration_t to_duration(std::chrono::nanoseconds d) noexcept;
std::chrono::nanoseconds to_chrono(const eprosima::fastrtps::Duration_t& d) noexcept;

}  // namespace mtc::qos
