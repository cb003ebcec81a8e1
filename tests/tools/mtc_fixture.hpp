// Helpers shared by the cross-process tests: start `mtc` subcommands as
// child processes (always with --json, so lines can be matched exactly) and
// read the events they print.
//
// Domain ids (registry, tools tests own 60-79; each test case its own id so
// ctest -j never lets two cases meet):
//   60 every service          61 count in order         62 scenario 1
//   63 scenario 2 (active)    64 scenario 2 (complete)  65 scenario 3
//   66 scenario 4             67 scenario 5             68 responder NOT_READY
//   69 SIGKILL responder      70 responder restarted    71 SIGSTOP requester
//   72 packet loss            73 watch                  74 list
//   75 signals                76 fail rate + seed       77 request timeout
//   78 respond --count        79 watch --duration, responder without --counterpart
// Second range 130-139 (test_mtc_profiles.cpp): 130 profile 1.3, 131-132
// INTERFACE_STATE DISABLED, 133 --peer pinning, 134 --peer usage errors.
// Fourth: 140 watch of a graceful end; 143-144 (test_mtc_middleware.cpp) a
// cell of processes on Cyclone DDS and on Fast DDS.
// Third range 190-194 (test_mtc_hostile_peer.cpp): hostile peers.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "json_field.hpp"
#include "transport.hpp"

namespace mtc::test {

// Generous bounds: they only catch hangs, timing figures live in benchmarks.
inline constexpr milliseconds kStartTimeout{20000};
inline constexpr milliseconds kHandshakeTimeout{30000};

// Lease of the tests that are not about detection time: 10 x 100 ms. On a
// 2-core CI machine shared with other suites a 300 ms lease can expire on
// scheduling delays alone; detection tests set their own (shorter) lease.
inline constexpr const char* kDefaultMissedHeartbeats = "10";

// Argument list for `mtc <command> --domain <domain> --json <args...>`, with
// the default lease unless args set --missed-heartbeats, on loopback unless
// args choose a transport (the tool's default is the network).
inline std::vector<std::string> mtc_argv(const std::string& command, int domain,
                                         std::vector<std::string> args) {
  std::vector<std::string> argv = {MTC_CLI_PATH, command, "--domain", std::to_string(domain),
                                   "--json"};
  if (std::find(args.begin(), args.end(), "--missed-heartbeats") == args.end()) {
    argv.insert(argv.end(), {"--missed-heartbeats", kDefaultMissedHeartbeats});
  }
  args = with_loopback_transport(std::move(args));
  argv.insert(argv.end(), args.begin(), args.end());
  return argv;
}

inline std::unique_ptr<ChildProcess> start_mtc(const std::string& command, int domain,
                                               std::vector<std::string> args) {
  return std::make_unique<ChildProcess>(mtc_argv(command, domain, std::move(args)));
}

// Starts `mtc respond` and waits until it announces itself READY.
inline std::unique_ptr<ChildProcess> start_responder(int domain, std::vector<std::string> args) {
  auto p = start_mtc("respond", domain, std::move(args));
  const auto ready = p->wait_for_line({"\"event\":\"ready\""}, kStartTimeout);
  EXPECT_TRUE(ready.has_value()) << p->transcript();
  return p;
}

// One outcome line of `mtc request` or `mtc respond`.
struct Outcome {
  int handshake = 0;
  std::string result;  // COMPLETE, FAIL, TIMEOUT, COMMS_LOST, NOT_READY
  std::string reason;
  std::string line;
};

inline std::vector<Outcome> outcomes(const ChildProcess& p) {
  std::vector<Outcome> out;
  for (const auto& line : p.lines()) {
    if (json_field(line, "event") != std::optional<std::string>("outcome")) continue;
    Outcome o;
    o.handshake = std::stoi(json_field(line, "handshake").value_or("0"));
    o.result = json_field(line, "result").value_or("");
    o.reason = json_field(line, "reason").value_or("");
    o.line = line;
    out.push_back(o);
  }
  return out;
}

// "request:ACTIVE", "response:COMPLETE", ... of one handshake, in print order.
inline std::vector<std::string> transitions(const ChildProcess& p, int handshake) {
  std::vector<std::string> out;
  for (const auto& line : p.lines()) {
    if (json_field(line, "event") != std::optional<std::string>("transition")) continue;
    if (json_field(line, "handshake") != std::optional<std::string>(std::to_string(handshake))) {
      continue;
    }
    out.push_back(json_field(line, "side").value_or("?") + ":" +
                  json_field(line, "state").value_or("?"));
  }
  return out;
}

// The transitions of handshake n from the request going ACTIVE on (drops
// what was seen while waiting for the responder to be READY).
inline std::vector<std::string> steps_from_request(const ChildProcess& p, int handshake) {
  auto all = transitions(p, handshake);
  auto first = std::find(all.begin(), all.end(), "request:ACTIVE");
  return {first, all.end()};
}

// Waits for the outcome line of handshake n.
inline std::optional<std::string> wait_outcome(ChildProcess& p, int n,
                                               milliseconds timeout = kHandshakeTimeout) {
  return p.wait_for_line({"\"event\":\"outcome\"", "\"handshake\":" + std::to_string(n) + ","},
                         timeout);
}

}  // namespace mtc::test
