// Internal, Cyclone DDS backend (MTC_CYCLONE builds; issue 9 section 3,
// step 4): mw::Participant over Cyclone DDS 0.10's C API and the C types idlc
// generates from the same IDL, with the same QoS presets
// (mtc/qos/cyclone_qos.hpp). Samples are the Fast DDS backend's on the wire
// (XCDR1, the same keys), so a Cyclone participant and a Fast DDS one read
// each other (tests/dds/test_mw_backends.cpp).
#pragma once

#include <memory>
#include <string>

#include "middleware.hpp"

namespace mtc::dds::mw {

// A Cyclone DDS participant in `domain_id`, its domain confined to loopback
// (Transport::Loopback and LoopbackUdp: UDP on 127.0.0.1; Cyclone 0.10 in
// Debian has no shared memory). A transport or security setting the backend
// cannot honour yet is a ConfigError that says so; so is a second timing for
// a domain id already in use in this process (cyclone_entities.hpp).
std::unique_ptr<Participant> make_cyclone_participant(int domain_id,
                                                      const qos::ParticipantConfig& config);

// Topics of one Cyclone participant, made on first use with the presets of
// the participant's timing; shared by its publishers and taps.
class CycloneTopics {
 public:
  virtual ~CycloneTopics() = default;
  // A topic other than the interaction ones (ConfigError for those).
  virtual int topic(TopicKind kind) = 0;
  // The interaction topic of interaction_index `index`.
  virtual int interaction_topic(std::size_t index) = 0;
};

// The tap of a Cyclone participant (cyclone_tap.cpp).
std::unique_ptr<Tap> make_cyclone_tap(int participant, CycloneTopics& topics,
                                      const TapConfig& config, TapSink sink);

}  // namespace mtc::dds::mw
