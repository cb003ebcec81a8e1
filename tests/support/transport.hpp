// The transport of every test (issue 10): the runtime and the tools default
// to the network (Fast DDS's builtin UDPv4 + SHM, default discovery); tests
// run on loopback (the hard network rule) unless they mean the network
// (tests/multihost, inside namespaces of their own). Build options through
// loopback<T>() and tool command lines through with_loopback_transport();
// tests/scripts/check_transport_chosen.py (ctest scripts.transport_chosen)
// fails on a test that leaves the choice to the default.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include "mtc/qos/participant.hpp"

namespace mtc::test {

inline constexpr qos::Transport kTestTransport = qos::Transport::Loopback;
inline constexpr const char* kTestTransportName = "loopback";

// dds::EquipmentOptions, dds::DomainObserverOptions or qos::ParticipantConfig
// with the loopback transport chosen, everything else at its default.
template <typename Options>
Options loopback() {
  Options options;
  options.transport = kTestTransport;
  return options;
}

// The arguments of `mtc`, `mtc-bridge` or `mtc-cell` with `--transport
// loopback` added, unless they choose a transport already.
inline std::vector<std::string> with_loopback_transport(std::vector<std::string> args) {
  if (std::find(args.begin(), args.end(), "--transport") == args.end()) {
    args.insert(args.end(), {"--transport", kTestTransportName});
  }
  return args;
}

}  // namespace mtc::test
