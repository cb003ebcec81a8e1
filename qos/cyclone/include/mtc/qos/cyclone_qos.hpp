// The Cyclone DDS reading of endpoint_qos.hpp: the project's QoS presets as
// Cyclone DDS 0.10 (C API) dds_qos_t, policy for policy what
// fastdds_writer_qos() etc. (fastdds_qos.hpp) give Fast DDS, so that one
// preset means the same contract whichever middleware an equipment runs on.
// The interop tests (tests/interop) read the effective policies back from
// both and compare. Includes no Fast DDS header.
//
// What has no per-endpoint counterpart in Cyclone:
// - reliable_heartbeat: Cyclone's writer HEARTBEAT period is a domain setting
//   (Internal/HeartbeatInterval, 100 ms by default and adaptive), not a QoS;
//   cyclone_domain_config() sets it from the Timing instead.
// - Fast DDS's liveliness announcement_period, data-sharing and NACK
//   suppression window (nack_suppression()): Fast DDS only, never on the
//   wire.
#pragma once

#include <dds/dds.h>

#include <memory>
#include <string>
#include <vector>

#include "mtc/qos/endpoint_qos.hpp"
#include "mtc/qos/timing.hpp"

namespace mtc::qos {

struct CycloneQosDeleter {
  void operator()(dds_qos_t* qos) const noexcept { dds_delete_qos(qos); }
};
// An owned dds_qos_t (dds_create_qos / dds_delete_qos).
using CycloneQos = std::unique_ptr<dds_qos_t, CycloneQosDeleter>;

// The policies of `endpoint` for a Cyclone topic, writer or reader. Writers
// are pinned to XCDR1 (PLAIN_CDR): Fast DDS 2.9 with Fast CDR 1.0 reads no
// other encoding. Throws std::bad_alloc when Cyclone cannot allocate.
CycloneQos cyclone_topic_qos(const EndpointQos& endpoint);
CycloneQos cyclone_writer_qos(const EndpointQos& endpoint);
CycloneQos cyclone_reader_qos(const EndpointQos& endpoint);

// A publisher's or subscriber's PARTITION ("mtc/dev/<uuid>", "mtc/dev/*").
CycloneQos cyclone_partition_qos(const std::vector<std::string>& partitions);

// A Cyclone domain configuration (the XML that CYCLONEDDS_URI or
// dds_create_domain() take) confined to the loopback interface: unicast
// discovery to 127.0.0.1 (Peers, participant index auto) as Fast DDS's
// loopback transports do, no multicast, the writer HEARTBEAT period and the
// participant lease from `timing`, and key hashes in every message that
// names an instance (Fast DDS 2.9 needs them to unmatch a deleted writer).
std::string cyclone_loopback_config(const Timing& timing = {});

// A Cyclone domain configuration for the cell's hosts (Transport::Network):
// the named network interfaces (every one the host has up, as Fast DDS's
// built-in UDP transport takes; none named: the one Cyclone determines
// itself), standard multicast discovery, and the same timing and key hashes
// as above. Throws std::invalid_argument for a name XML cannot carry.
std::string cyclone_network_config(const Timing& timing,
                                   const std::vector<std::string>& interfaces);

// DDS-Security on Cyclone: the participant QoS that loads Cyclone's builtin
// plugins (authentication PKI-DH, access control, AES-GCM-GMAC
// cryptography) with the files of an absolute security directory
// (kSecurityFiles), the same PKI, governance and permissions Fast DDS takes
// through security_properties(). `plugin_dir` holds Cyclone's
// libdds_security_*.so (Debian: <libdir>/libddsc0debian, found by CMake);
// empty: Cyclone looks them up by name. The directory is not checked here:
// check_security_dir() does that first, naming the file.
CycloneQos cyclone_security_qos(const std::string& dir, const std::string& plugin_dir);

// The directory of Cyclone's security plugins this build found, or empty.
std::string cyclone_security_plugin_dir();

}  // namespace mtc::qos
