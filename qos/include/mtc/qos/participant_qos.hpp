// The Fast DDS side of participant.hpp: a ParticipantConfig as Fast DDS
// DomainParticipantQos. For qos/ and dds/ sources, tests and raw peers; no
// header of the runtime's public API includes it.
#pragma once

#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>

#include "mtc/qos/participant.hpp"

namespace mtc::qos {

// Builds the participant QoS; throws std::invalid_argument for a bad timing.
eprosima::fastdds::dds::DomainParticipantQos participant_qos(const ParticipantConfig& config);

}  // namespace mtc::qos
