// The Fast DDS side of participant.hpp: a ParticipantConfig as Fast DDS
// DomainParticipantQos. For qos/ and dds/ sources, tests and raw peers; no
// header of the runtime's public API includes it.
#pragma once

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

// The security directory a participant QoS was built with, or "" when it
// has none: for the error when Fast DDS refuses such a participant.
std::string security_dir_of(const eprosima::fastdds::dds::DomainParticipantQos& qos);

}  // namespace mtc::qos
