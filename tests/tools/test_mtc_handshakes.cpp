// Successful handshakes between two `mtc` processes: every one of the ten
// services, many handshakes in order, and the requester's reactions to a
// responder that is NOT_READY or absent.
#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <string>
#include <vector>

#include "mtc_fixture.hpp"

namespace mtc::test {
namespace {

const std::vector<std::string> kServices = {
    "MATERIAL_FEED",   "MATERIAL_CHANGE", "MATERIAL_RETRACT", "PART_CHANGE", "MATERIAL_LOAD",
    "MATERIAL_UNLOAD", "OPEN_DOOR",       "CLOSE_DOOR",       "OPEN_CHUCK",  "CLOSE_CHUCK"};

const std::vector<std::string> kSuccess = {"request:ACTIVE", "response:ACTIVE", "response:COMPLETE",
                                           "request:READY", "response:READY"};

std::vector<std::string> requester_args(const std::string& service,
                                        std::vector<std::string> more = {}) {
  std::vector<std::string> args = {"--device",  "robot-1", "--interface",   "cell",
                                   "--service", service,   "--counterpart", "machine-1",
                                   "--timeout", "30s"};
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

// For door/chuck services: the responder flag and initial state, the event
// it prints when the service moved the door/chuck, and the new state.
std::vector<std::string> door_or_chuck(const std::string& service) {
  if (service == "OPEN_DOOR") {
    return {"--door-state", "CLOSED", "door_state", "OPEN"};
  }
  if (service == "CLOSE_DOOR") {
    return {"--door-state", "OPEN", "door_state", "CLOSED"};
  }
  if (service == "OPEN_CHUCK") {
    return {"--chuck-state", "CLOSED", "chuck_state", "OPEN"};
  }
  if (service == "CLOSE_CHUCK") {
    return {"--chuck-state", "OPEN", "chuck_state", "CLOSED"};
  }
  return {};
}

TEST(Handshake, EveryServiceCompletesAcrossProcesses) {
  constexpr int kDomain = 60;
  int k = 0;
  for (const auto& service : kServices) {
    SCOPED_TRACE(service);
    // A fresh pair of processes (own device uuids) per service, so that one
    // service's peer leaving cannot touch the next service's handshake.
    ++k;
    const std::string machine = "machine-" + std::to_string(k);
    const std::string robot = "robot-" + std::to_string(k);
    std::vector<std::string> args = {"--device",    machine, "--interface",   "cell",
                                     "--service",   service, "--counterpart", robot,
                                     "--action-ms", "10"};
    // Door and chuck services run against a responder that controls the
    // door/chuck, starting where the service can be performed.
    const auto moves = door_or_chuck(service);
    if (!moves.empty()) {
      args.insert(args.end(), moves.begin(), moves.begin() + 2);
    }
    auto responder = start_responder(kDomain, args);
    auto requester = start_mtc("request", kDomain,
                               {"--device", robot, "--interface", "cell", "--service", service,
                                "--counterpart", machine, "--timeout", "30s"});
    ASSERT_EQ(requester->wait_exit(kHandshakeTimeout), 0) << requester->transcript();
    const auto out = outcomes(*requester);
    ASSERT_EQ(out.size(), 1u) << requester->transcript();
    EXPECT_EQ(out[0].result, "COMPLETE");
    // A door/chuck service ends with the response NOT_READY: the door is now
    // where the service puts it, so the same service cannot run again.
    auto expected = kSuccess;
    if (!moves.empty()) {
      expected.back() = "response:NOT_READY";
    }
    EXPECT_EQ(steps_from_request(*requester, 1), expected) << requester->transcript();
    // The responder reports the same handshake, for this service.
    const auto line = wait_outcome(*responder, 1);
    ASSERT_TRUE(line) << responder->transcript();
    EXPECT_EQ(json_field(*line, "service"), service);
    EXPECT_EQ(json_field(*line, "result"), "COMPLETE");
    if (!moves.empty()) {
      const auto& lines = responder->lines();
      const auto moved = std::find_if(lines.begin(), lines.end(), [&](const std::string& l) {
        return json_field(l, "event") == moves[2];
      });
      ASSERT_NE(moved, lines.end()) << responder->transcript();
      EXPECT_EQ(json_field(*moved, "detail"), moves[3]);
    }
    responder->send_signal(SIGTERM);
    EXPECT_EQ(responder->wait_exit(kStartTimeout), 0) << responder->transcript();
  }
}

TEST(Handshake, ManyHandshakesCompleteInOrderWithLatencies) {
  constexpr int kDomain = 61;
  constexpr int kCount = 20;
  auto responder =
      start_responder(kDomain, {"--device", "machine-1", "--interface", "cell", "--service",
                                "MATERIAL_LOAD", "--counterpart", "robot-1", "--action-ms", "0"});
  auto requester = start_mtc("request", kDomain,
                             requester_args("MATERIAL_LOAD", {"--count", std::to_string(kCount)}));
  ASSERT_EQ(requester->wait_exit(kHandshakeTimeout), 0) << requester->transcript();
  const auto out = outcomes(*requester);
  ASSERT_EQ(out.size(), static_cast<std::size_t>(kCount)) << requester->transcript();
  for (int i = 0; i < kCount; ++i) {
    EXPECT_EQ(out[i].handshake, i + 1);
    EXPECT_EQ(out[i].result, "COMPLETE");
    // Each step's latency is printed and plausible (source -> reception, same host).
    const auto total = json_field(out[i].line, "total_ms");
    ASSERT_TRUE(total) << out[i].line;
    EXPECT_GT(std::stod(*total), 0.0);
    EXPECT_LT(std::stod(*total), 10000.0);
  }
  for (int i = 1; i <= kCount; ++i) {
    const auto line = wait_outcome(*responder, i);
    ASSERT_TRUE(line) << responder->transcript();
    EXPECT_EQ(json_field(*line, "result"), "COMPLETE");
  }
  const auto summary = requester->lines().back();
  EXPECT_EQ(json_field(summary, "event"), "summary") << summary;
  EXPECT_EQ(json_field(summary, "complete"), std::to_string(kCount)) << summary;
}

TEST(Handshake, NotReadyResponderIsReportedWithItsOwnExitCode) {
  constexpr int kDomain = 68;
  auto responder =
      start_responder(kDomain, {"--device", "machine-1", "--interface", "cell", "--service",
                                "MATERIAL_LOAD", "--counterpart", "robot-1", "--not-ready"});
  // Twice: the first requester leaving is a comms loss for the responder
  // (FAIL); recovering from it must bring it back to NOT_READY, not READY.
  for (int round = 1; round <= 2; ++round) {
    SCOPED_TRACE(round);
    auto requester = start_mtc("request", kDomain,
                               {"--device", "robot-1", "--interface", "cell", "--service",
                                "MATERIAL_LOAD", "--counterpart", "machine-1", "--timeout", "4s"});
    ASSERT_EQ(requester->wait_exit(kHandshakeTimeout), 6) << requester->transcript();
    const auto out = outcomes(*requester);
    ASSERT_EQ(out.size(), 1u) << requester->transcript();
    EXPECT_EQ(out[0].result, "NOT_READY");
    // The request never went ACTIVE: Part 5 forbids requesting from a NOT_READY responder.
    const auto steps = transitions(*requester, 1);
    EXPECT_EQ(std::count(steps.begin(), steps.end(), "request:ACTIVE"), 0)
        << requester->transcript();
    EXPECT_EQ(steps.back(), "response:NOT_READY") << requester->transcript();
  }
}

TEST(Handshake, ResponderWithCountExitsAfterThatManyHandshakes) {
  constexpr int kDomain = 78;
  auto responder = start_responder(
      kDomain, {"--device", "machine-1", "--interface", "cell", "--service", "PART_CHANGE",
                "--counterpart", "robot-1", "--action-ms", "0", "--count", "2"});
  auto requester = start_mtc("request", kDomain, requester_args("PART_CHANGE", {"--count", "2"}));
  ASSERT_EQ(requester->wait_exit(kHandshakeTimeout), 0) << requester->transcript();
  ASSERT_EQ(responder->wait_exit(kHandshakeTimeout), 0) << responder->transcript();
  const auto stopped = responder->wait_for_line({"\"event\":\"stopped\""}, milliseconds(0));
  ASSERT_TRUE(stopped) << responder->transcript();
  EXPECT_EQ(json_field(*stopped, "handshakes"), "2");
}

TEST(Handshake, AbsentResponderTimesOut) {
  constexpr int kDomain = 77;
  auto requester = start_mtc("request", kDomain,
                             {"--device", "robot-1", "--interface", "cell", "--service",
                              "MATERIAL_LOAD", "--counterpart", "machine-1", "--timeout", "1s"});
  ASSERT_EQ(requester->wait_exit(kHandshakeTimeout), 4) << requester->transcript();
  const auto out = outcomes(*requester);
  ASSERT_EQ(out.size(), 1u) << requester->transcript();
  EXPECT_EQ(out[0].result, "TIMEOUT");
}

}  // namespace
}  // namespace mtc::test
