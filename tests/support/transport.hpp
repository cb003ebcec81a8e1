// The transport of every test (issue 10): the runtime and the tools default
// to the network (Fast DDS's builtin UDPv4 + SHM, default discovery); tests
// run on loopback (the hard network rule) unless they mean the network
// (tests/multihost, inside namespaces of their own). Build options through
// loopback<T>() and tool command lines through with_loopback_transport();
// tests/scripts/check_transport_chosen.py (ctest scripts.transport_chosen)
// fails on a test that leaves the choice to the default.
#pragma once

#include <algorithm>
#include <cstdlib>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "mtc/qos/participant.hpp"

namespace mtc::test {

inline constexpr qos::Transport kTestTransport = qos::Transport::Loopback;
inline constexpr const char* kTestTransportName = "loopback";

// The middleware the runtime's tests run over: MTC_TEST_MIDDLEWARE=cyclone
// runs the same cases with every Equipment and DomainObserver on Cyclone DDS
// (issue 9 section 3: the DDS-level suite over both backends); unset or
// "fastdds": Fast DDS. Anything else fails the test that asks.
inline bool test_middleware_is_cyclone() {
  const char* chosen = std::getenv("MTC_TEST_MIDDLEWARE");  // NOLINT(concurrency-mt-unsafe)
  if (chosen == nullptr || std::string(chosen).empty() || std::string(chosen) == "fastdds") {
    return false;
  }
  if (std::string(chosen) == "cyclone") return true;
  throw std::invalid_argument("MTC_TEST_MIDDLEWARE='" + std::string(chosen) +
                              "': expected fastdds or cyclone");
}

namespace detail {
// Options with a `middleware` member (the runtime's) get the test middleware;
// the others (qos::ParticipantConfig: raw Fast DDS peers) are left as they are.
template <typename Options>
auto choose_test_middleware(Options& options, int) -> decltype(options.middleware, void()) {
  if (test_middleware_is_cyclone()) options.middleware = decltype(options.middleware)::Cyclone;
}
template <typename Options>
void choose_test_middleware(Options&, long) {}
}  // namespace detail

// dds::EquipmentOptions, dds::DomainObserverOptions or qos::ParticipantConfig
// with the loopback transport chosen and the test middleware, everything
// else at its default.
template <typename Options>
Options loopback() {
  Options options;
  options.transport = kTestTransport;
  detail::choose_test_middleware(options, 0);
  return options;
}

// The arguments of `mtc`, `mtc-bridge` or `mtc-cell` with `--transport
// loopback` added, unless they choose a transport already; and, under
// MTC_TEST_MIDDLEWARE=cyclone, `--middleware cyclone` unless they choose one
// or inject faults (`--transport test`, `--drop-percent`: Fast DDS's
// fault-injecting transport, which Cyclone has no counterpart of; those
// cases run on Fast DDS either way).
inline std::vector<std::string> with_loopback_transport(std::vector<std::string> args) {
  const auto transport = std::find(args.begin(), args.end(), "--transport");
  const bool fault_injection = (transport != args.end() && std::next(transport) != args.end() &&
                                *std::next(transport) == "test") ||
                               std::find(args.begin(), args.end(), "--drop-percent") != args.end();
  if (transport == args.end()) {
    args.insert(args.end(), {"--transport", kTestTransportName});
  }
  if (test_middleware_is_cyclone() && !fault_injection &&
      std::find(args.begin(), args.end(), "--middleware") == args.end()) {
    args.insert(args.end(), {"--middleware", "cyclone"});
  }
  return args;
}

}  // namespace mtc::test
