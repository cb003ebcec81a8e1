// The transport of every benchmark (issue 10): the runtime defaults to the
// network (Fast DDS's builtin UDPv4 + SHM); benchmarks measure on loopback
// inside scripts/netns-run.sh unless they choose otherwise on purpose.
// tests/scripts/check_transport_chosen.py (ctest scripts.transport_chosen)
// fails on a benchmark that leaves the choice to the default.
#pragma once

#include "mtc/qos/participant.hpp"

namespace mtc::bench {

inline constexpr qos::Transport kBenchTransport = qos::Transport::Loopback;

// dds::EquipmentOptions, dds::DomainObserverOptions or qos::ParticipantConfig
// with the loopback transport chosen, everything else at its default.
template <typename Options>
Options loopback() {
  Options options;
  options.transport = kBenchTransport;
  return options;
}

}  // namespace mtc::bench
