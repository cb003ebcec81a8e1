#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>
#include <fastdds/rtps/transport/test_UDPv4TransportDescriptor.h>
#include <fastrtps/types/TypeObjectFactory.h>
#include <fastrtps/utils/IPLocator.h>
#include <fastrtps/xmlparser/XMLProfileManager.h>

#include <climits>
#include <cstdlib>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <mutex>
#include <random>
#include <stdexcept>

#include "mtc/qos/fastdds_qos.hpp"
#include "mtc/qos/participant_qos.hpp"
#include "mtc/qos/presets.hpp"

namespace mtc::qos {

namespace fdds = eprosima::fastdds::dds;
namespace frtps = eprosima::fastdds::rtps;

namespace {

// The only address any project participant may bind or send to.
constexpr const char* kLoopback = "127.0.0.1";

// Discovery reaches the participants of this many participant ids per host
// and domain (Fast DDS gives each participant of a host the next free id and
// the unicast discovery port of that id; the default range is 4). A
// participant whose id lies beyond it still finds every participant below
// it, which then answer, but two beyond it would not find each other.
constexpr std::uint32_t kLoopbackPeerIds = 32;

std::shared_ptr<frtps::TransportDescriptorInterface> loopback_udp() {
  auto udp = std::make_shared<frtps::UDPv4TransportDescriptor>();
  udp->interfaceWhiteList.emplace_back(kLoopback);
  udp->maxInitialPeersRange = kLoopbackPeerIds;
  return udp;
}

// The network: what Fast DDS's builtin transports are (shared memory and
// UDPv4 on every interface, default discovery) with one change: a UDP send
// never blocks. A blocking send waits for room in the socket's buffer, and
// with a cable pulled the datagrams already queued for the dead link hold
// that room: the robot's state machine thread stalled 2.0-2.1 s in the
// kernel (sock_alloc_send_pskb) on the FAIL it was publishing, so it told
// the loss a lease late (multihost.cable_pull, step 7, 3,097 ms). A
// datagram the buffer cannot take now is dropped instead; the reliable
// protocol repairs it, as it would a datagram lost on the wire.
std::shared_ptr<frtps::TransportDescriptorInterface> network_udp() {
  auto udp = std::make_shared<frtps::UDPv4TransportDescriptor>();
  udp->non_blocking_send = true;
  return udp;
}

// Discovery without multicast: listening on 127.0.0.1 at the participant's
// well-known unicast port (port 0 lets Fast DDS compute it from domain and
// participant id) and announcing to the unicast discovery ports of the
// first kLoopbackPeerIds participant ids on 127.0.0.1. Setting a metatraffic
// unicast locator also keeps Fast DDS from opening its default SPDP
// multicast socket, which it binds to 0.0.0.0 (every interface), so every
// socket of a loopback participant is bound to 127.0.0.1 (or is SHM).
void loopback_discovery(fdds::DomainParticipantQos& q) {
  using eprosima::fastrtps::rtps::IPLocator;
  using eprosima::fastrtps::rtps::Locator_t;
  Locator_t loopback;
  loopback.kind = LOCATOR_KIND_UDPv4;
  loopback.port = 0;
  IPLocator::setIPv4(loopback, kLoopback);
  auto& builtin = q.wire_protocol().builtin;
  builtin.metatrafficUnicastLocatorList.clear();
  builtin.metatrafficMulticastLocatorList.clear();
  builtin.metatrafficUnicastLocatorList.push_back(loopback);
  builtin.initialPeersList.clear();
  builtin.initialPeersList.push_back(loopback);
  // User data only to 127.0.0.1 (and SHM) as well, never to a multicast group.
  q.wire_protocol().default_multicast_locator_list.clear();
}

// An ACKNACK submessage (`m.pos` at its body: readerId, writerId, then the
// 64-bit bitmap base) from the publications or subscriptions reader of
// endpoint discovery (entity ids 0x000003c7, 0x000004c7) with base 0. A zero
// base reads the same in either byte order.
bool preemptive_discovery_acknack(const eprosima::fastrtps::rtps::CDRMessage_t& m) {
  constexpr std::uint32_t kBodyBytes = 16;  // two entity ids and the base
  if (m.pos + kBodyBytes > m.length) return false;
  const auto* body = m.buffer + m.pos;
  const bool discovery_reader =
      body[0] == 0 && body[1] == 0 && (body[2] == 0x03 || body[2] == 0x04) && body[3] == 0xc7;
  if (!discovery_reader) return false;
  for (std::uint32_t i = 8; i < kBodyBytes; ++i) {
    if (body[i] != 0) return false;
  }
  return true;
}

std::shared_ptr<frtps::TransportDescriptorInterface> test_udp(const FaultInjection& faults) {
  auto udp = std::make_shared<frtps::test_UDPv4TransportDescriptor>();
  udp->interfaceWhiteList.emplace_back(kLoopback);
  udp->dropDataMessagesPercentage = faults.drop_data_percent;
  udp->dropHeartbeatMessagesPercentage = faults.drop_heartbeat_percent;
  udp->dropAckNackMessagesPercentage = faults.drop_acknack_percent;
  if (faults.random_drop_data_percent > 0) {
    // Called on the sending threads of the participant: one generator, locked.
    struct Random {
      std::mutex mutex;
      std::mt19937 engine{std::random_device{}()};
      std::uniform_int_distribution<int> percent{0, 99};
    };
    auto random = std::make_shared<Random>();
    const int p = faults.random_drop_data_percent;
    udp->drop_data_messages_filter_ = [random, p](eprosima::fastrtps::rtps::CDRMessage_t&) {
      std::lock_guard<std::mutex> lock(random->mutex);
      return random->percent(random->engine) < p;
    };
  }
  if (auto flag = faults.drop_discovery_preemptive_acknacks) {
    udp->drop_ack_nack_messages_filter_ = [flag](eprosima::fastrtps::rtps::CDRMessage_t& m) {
      return flag->load(std::memory_order_relaxed) && preemptive_discovery_acknack(m);
    };
  }
  // Per-participant outage switch, checked for every datagram sent.
  auto outage = faults.outage;
  udp->messages_filter_ = [outage](eprosima::fastrtps::rtps::CDRMessage_t&) {
    return outage && outage->load(std::memory_order_relaxed);
  };
  return udp;
}

constexpr const char* kIdentityCertificateProperty =
    "dds.sec.auth.builtin.PKI-DH.identity_certificate";

// Fast DDS takes file URIs; a relative directory would depend on the working
// directory of whoever reads the error.
std::string absolute_dir(const std::string& dir) {
  char resolved[PATH_MAX];
  return ::realpath(dir.c_str(), resolved) != nullptr ? std::string(resolved) : dir;
}

void enable_security(fdds::DomainParticipantQos& q, const std::string& dir) {
  if (auto problem = check_security_dir(dir)) throw std::invalid_argument(*problem);
  for (auto& [name, value] : security_properties(absolute_dir(dir))) {
    q.properties().properties().emplace_back(name, value);
  }
}

}  // namespace

std::string security_dir_of(const fdds::DomainParticipantQos& qos) {
  const std::string* certificate = eprosima::fastrtps::rtps::PropertyPolicyHelper::find_property(
      qos.properties(), kIdentityCertificateProperty);
  if (certificate == nullptr) return "";
  const std::string& uri = *certificate;
  const std::size_t begin = uri.rfind("file://", 0) == 0 ? 7 : 0;
  const auto end = uri.rfind('/');
  return end == std::string::npos || end < begin ? uri : uri.substr(begin, end - begin);
}

fdds::DomainParticipantQos participant_qos(const ParticipantConfig& config) {
  validate(config.timing);
  fdds::DomainParticipantQos q = fdds::PARTICIPANT_QOS_DEFAULT;
  q.name(config.name);
  if (!config.security_dir.empty()) enable_security(q, config.security_dir);
  auto& discovery = q.wire_protocol().builtin.discovery_config;
  discovery.leaseDuration = to_duration(config.timing.participant_lease);
  discovery.leaseDuration_announcementperiod = to_duration(config.timing.participant_announcement);

  auto& transport = q.transport();
  switch (config.transport) {
    case Transport::Network:
      transport.use_builtin_transports = false;
      transport.user_transports.push_back(std::make_shared<frtps::SharedMemTransportDescriptor>());
      transport.user_transports.push_back(network_udp());
      break;
    case Transport::Loopback:
      transport.use_builtin_transports = false;
      transport.user_transports.push_back(std::make_shared<frtps::SharedMemTransportDescriptor>());
      transport.user_transports.push_back(loopback_udp());
      loopback_discovery(q);
      break;
    case Transport::LoopbackUdp:
      transport.use_builtin_transports = false;
      transport.user_transports.push_back(loopback_udp());
      loopback_discovery(q);
      break;
    case Transport::LoopbackTest:
      // Fault injection, only ever inside scripts/netns-run.sh: discovery
      // stays on the SPDP multicast group (routed over lo there). Fast DDS's
      // test_UDPv4 transport did not discover its peers by unicast initial
      // peers (tests/qos TestTransport.* timed out, seen with 2.9.1).
      transport.use_builtin_transports = false;
      transport.user_transports.push_back(test_udp(config.faults));
      break;
  }
  return q;
}

void anchor_discovery_port(fdds::DomainParticipantQos& qos, int domain_id) {
  auto& wire = qos.wire_protocol();
  const auto first_port = wire.port.getUnicastPort(static_cast<std::uint32_t>(domain_id), 0);
  for (auto& locator : wire.builtin.metatrafficUnicastLocatorList) {
    if (locator.kind == LOCATOR_KIND_UDPv4 && locator.port == 0) locator.port = first_port;
  }
}

ParticipantConfig participant_config(std::string_view profile_name, const Timing& timing) {
  ParticipantConfig config;
  config.timing = timing;
  if (profile_name == kLoopbackParticipantProfile) {
    config.transport = Transport::Loopback;
  } else if (profile_name == kLoopbackUdpParticipantProfile) {
    config.transport = Transport::LoopbackUdp;
  } else {
    throw std::invalid_argument("unknown participant profile '" + std::string(profile_name) +
                                "' (known: " + std::string(kLoopbackParticipantProfile) + ", " +
                                std::string(kLoopbackUdpParticipantProfile) + ")");
  }
  return config;
}

fdds::DomainParticipant* create_participant(int domain_id, const fdds::DomainParticipantQos& qos,
                                            fdds::DomainParticipantListener* listener,
                                            const fdds::StatusMask& mask) {
  static std::mutex creating;
  const std::lock_guard<std::mutex> lock(creating);
  eprosima::fastrtps::types::TypeObjectFactory::get_instance();
  return fdds::DomainParticipantFactory::get_instance()->create_participant(domain_id, qos,
                                                                            listener, mask);
}

std::optional<Transport> parse_transport(std::string_view text) noexcept {
  if (text == "loopback") return Transport::Loopback;
  if (text == "loopback-udp") return Transport::LoopbackUdp;
  if (text == "test") return Transport::LoopbackTest;
  if (text == "network") return Transport::Network;
  return std::nullopt;
}

std::string_view to_string(Transport t) noexcept {
  switch (t) {
    case Transport::Loopback:
      return "loopback";
    case Transport::LoopbackUdp:
      return "loopback-udp";
    case Transport::LoopbackTest:
      return "test";
    case Transport::Network:
      return "network";
  }
  return "?";
}

void set_intraprocess_delivery(bool enabled) {
  eprosima::fastrtps::LibrarySettingsAttributes settings;
  settings.intraprocess_delivery =
      enabled ? eprosima::fastrtps::INTRAPROCESS_FULL : eprosima::fastrtps::INTRAPROCESS_OFF;
  eprosima::fastrtps::xmlparser::XMLProfileManager::library_settings(settings);
}

}  // namespace mtc::qos
