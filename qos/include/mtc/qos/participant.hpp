// Participant configuration: transport, fault injection and timing, as
// plain values (no Fast DDS type: the runtime's public headers include this
// one). participant_qos.hpp turns a ParticipantConfig into Fast DDS QoS
// inside qos/ and dds/.
//
// Network (the default) is Fast DDS's builtin transports with its default
// discovery (SPDP multicast, every interface), UDP sends made non-blocking:
// what a cell that spans machines needs. Tests, benchmarks and the main job choose a loopback
// transport explicitly.
//
// The loopback transports Loopback and LoopbackUdp confine DDS
// to the host by configuration, not by a network namespace: the builtin
// transports are switched off, UDPv4 is restricted to 127.0.0.1
// (interfaceWhiteList) and discovery uses no multicast: each
// participant listens for discovery on 127.0.0.1 at the domain's lowest free
// well-known unicast port (anchor_discovery_port in participant_qos.hpp) and
// announces itself to the first 32 of those ports on 127.0.0.1 (initial
// peers). Every socket such a
// participant opens is bound to 127.0.0.1, or is shared memory; this is what
// lets ./scripts/start.sh run the cell and the bridge on the host
// (tests/scripts/check_loopback_confinement.sh proves it). LoopbackTest, the
// fault-injection transport of tests, is UDPv4 on 127.0.0.1 too but
// discovers through the SPDP multicast group, which only the test namespace
// (scripts/netns-run.sh) routes over lo.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "mtc/qos/timing.hpp"

namespace mtc::qos {

enum class Transport : std::uint8_t {
  Loopback,      // UDPv4 on 127.0.0.1 + shared memory (same host, fastest)
  LoopbackUdp,   // UDPv4 on 127.0.0.1 only
  LoopbackTest,  // Fast DDS test_UDPv4 transport on 127.0.0.1: fault injection
  Network,       // Fast DDS builtin transports (UDPv4 on every interface, sends
                 // that never block, + SHM),
                 // default discovery: the default, for a real cell network;
                 // tests use it only inside their own network namespaces
};

inline constexpr std::array<Transport, 4> kAllTransports = {
    Transport::Loopback, Transport::LoopbackUdp, Transport::LoopbackTest, Transport::Network};

// Faults the LoopbackTest transport injects into what this participant
// sends (ignored by the other transports).
struct FaultInjection {
  // Fast DDS's test transport drops every n-th DATA submessage (a counter,
  // never two in a row); random_drop_data_percent drops each one with that
  // probability, independently, so losses also come in bursts.
  std::uint8_t drop_data_percent = 0;         // DATA submessages
  std::uint8_t random_drop_data_percent = 0;  // DATA submessages, at random
  std::uint8_t drop_heartbeat_percent = 0;    // RTPS HEARTBEAT submessages
  std::uint8_t drop_acknack_percent = 0;      // ACKNACK submessages
  // While *outage is true every datagram this participant sends is dropped:
  // a cable pull that affects only this participant (the process-wide
  // test_UDPv4Transport_ShutdownAllNetwork would cut every participant).
  std::shared_ptr<std::atomic<bool>> outage;
  // While *drop_discovery_preemptive_acknacks is true, the ACKNACKs with
  // sequence number base 0 of this participant's endpoint-discovery readers
  // are dropped: the request for every endpoint announcement a newly
  // (re)discovered participant makes before its first discovery heartbeat
  // arrives. Losing it is what a cable pull occasionally does by a race
  // (docs/multihost.md, "Cable pull"); this makes it certain.
  std::shared_ptr<std::atomic<bool>> drop_discovery_preemptive_acknacks;
};

struct ParticipantConfig {
  std::string name = "mtc";
  Transport transport = Transport::Network;
  FaultInjection faults;
  Timing timing;
  // DDS-Security: a directory made by scripts/security/make-pki.sh for one
  // identity (kSecurityFiles). Empty: no security (any participant of the
  // domain may read and write). Set: authentication (PKI-DH), access control
  // with the signed governance and permissions, and AES-GCM encryption.
  std::string security_dir;
};

// The files of a security directory: the CA that signed the identities, the
// governance and the permissions; the identity's certificate and key.
inline constexpr std::array<const char*, 5> kSecurityFiles = {"ca.pem", "cert.pem", "key.pem",
                                                              "governance.p7s", "permissions.p7s"};

// Checks a security directory before Fast DDS sees it, so that a bad one is
// told by file: missing or unreadable files, a certificate not signed by
// ca.pem or outside its validity, a key that is not the certificate's, a
// governance or permissions document whose signature does not verify
// against ca.pem (tampered, or signed by another CA). Returns the problem
// in words, naming the file, or nullopt. participant_qos() throws
// std::invalid_argument with the same text.
std::optional<std::string> check_security_dir(const std::string& dir);

// Named participant profiles, as in the XML file: "mtc.participant.loopback"
// (UDPv4 127.0.0.1 + SHM) and "mtc.participant.loopback_udp"; throws
// std::invalid_argument naming the known profiles otherwise.
ParticipantConfig participant_config(std::string_view profile_name, const Timing& timing = {});

// The one spelling of each transport, in command lines and configuration
// files alike: "loopback", "loopback-udp", "test", "network".
std::optional<Transport> parse_transport(std::string_view text) noexcept;
std::string_view to_string(Transport t) noexcept;

// Intra-process delivery lets two participants of one process bypass every
// transport. Fault-injection tests with two participants in one process must
// turn it off (process-wide, before creating participants).
void set_intraprocess_delivery(bool enabled);

// Largest domain id Fast DDS accepts with the default port mapping.
inline constexpr int kMaxDomainId = 232;

}  // namespace mtc::qos
