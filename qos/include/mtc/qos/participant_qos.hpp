// The Fast DDS side of participant.hpp: a ParticipantConfig as Fast DDS
// DomainParticipantQos. For qos/ and dds/ sources, tests and raw peers; no
// header of the runtime's public API includes it.
#pragma once

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <string>
#include <utility>
#include <vector>

#include "mtc/qos/participant.hpp"

namespace mtc::qos {

// Builds the participant QoS; throws std::invalid_argument for a bad timing
// or a security directory that check_security_dir() refuses.
eprosima::fastdds::dds::DomainParticipantQos participant_qos(const ParticipantConfig& config);

// The Fast DDS properties that enable the builtin security plugins with the
// files of an (absolute) security directory.
std::vector<std::pair<std::string, std::string>> security_properties(const std::string& dir);

// Binds the loopback transports' discovery to the domain's lowest free
// well-known port instead of the one of the participant id Fast DDS gives
// it. Fast DDS numbers a process's participants 0, 1, 2, ... and never
// reuses a number, and the port follows the number; a loopback participant
// announces itself only to the ports of the first 32 ids, so in a process
// that had created 32 participants (an equipment restarted in-process, a
// benchmark's start-ups) two new ones never found each other. With the
// domain's first port as the start, Fast DDS moves up to the next port
// while one is taken (by a live participant of any process), so ports stay
// low as long as fewer than 32 participants of the domain live on the host.
// Touches only a UDPv4 discovery locator left at port 0 (the loopback
// transports); participant_qos() cannot do it: the domain is not known yet.
void anchor_discovery_port(eprosima::fastdds::dds::DomainParticipantQos& qos, int domain_id);

// Creates a participant as every participant of this project must be
// created with Fast DDS 2.9 (nullptr when Fast DDS refuses it):
// - one at a time per process: Fast DDS reads the user name with getpwuid(),
//   which is not thread-safe, while it creates one;
// - after Fast DDS's type-object registry exists. TypeObjectFactory makes
//   the process's registry on its first use, without a lock, and that first
//   use is the first reader or writer a participant gets (endpoint discovery
//   fills in type information) on the thread that creates it: endpoints
//   created on two threads at once made two registries, and one leaked
//   (seen by LeakSanitizer, 434 KB, in the one-process raw benchmark).
// `listener` and `mask` as Fast DDS's own create_participant takes them.
eprosima::fastdds::dds::DomainParticipant* create_participant(
    int domain_id, const eprosima::fastdds::dds::DomainParticipantQos& qos,
    eprosima::fastdds::dds::DomainParticipantListener* listener = nullptr,
    const eprosima::fastdds::dds::StatusMask& mask = eprosima::fastdds::dds::StatusMask::all());

// The security directory a participant QoS was built with, or "" when it
// has none: for the error when Fast DDS refuses such a participant.
std::string security_dir_of(const eprosima::fastdds::dds::DomainParticipantQos& qos);

}  // namespace mtc::qos
