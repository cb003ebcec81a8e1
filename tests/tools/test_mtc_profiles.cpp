// `mtc request` / `mtc respond` across processes with the options that pick
// the edition of Part 5 (--profile 1.3) and disable an interface
// (--disabled, INTERFACE_STATE DISABLED), and pin the counterpart (--peer).
// Domain ids 130-139 (tools tests,
// second range; see mtc_fixture.hpp for 60-79).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "mtc_fixture.hpp"

namespace mtc::test {
namespace {

bool contains(const std::vector<std::string>& v, const std::string& item) {
  return std::find(v.begin(), v.end(), item) != v.end();
}

// The start line `mtc respond` printed (start_responder waited for it).
std::string ready_line(const ChildProcess& p) {
  for (const auto& line : p.lines()) {
    if (line.find("\"event\":\"ready\"") != std::string::npos) return line;
  }
  return "";
}

std::vector<std::string> responder_args(std::vector<std::string> extra) {
  std::vector<std::string> args = {
      "--device",      "machine-1",     "--interface", "mh",          "--service",
      "MATERIAL_LOAD", "--counterpart", "robot-1",     "--action-ms", "200"};
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

std::vector<std::string> requester_args(std::vector<std::string> extra) {
  std::vector<std::string> args = {"--device",  "robot-1",       "--interface",   "mh",
                                   "--service", "MATERIAL_LOAD", "--counterpart", "machine-1"};
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

// 1.3: "the requester returns to READY (not FAIL) when the responder fails";
// under 1.6 the same handshake shows request:FAIL (test_mtc_failure_scenarios).
TEST(Profile13, RequesterReturnsToReadyAfterResponderFail) {
  constexpr int kDomain = 130;
  auto responder = start_responder(
      kDomain, responder_args({"--profile", "1.3", "--fail-at", "active", "--fail-on", "1"}));
  const auto ready = ready_line(*responder);
  EXPECT_EQ(json_field(ready, "profile"), "1.3") << responder->transcript();
  auto requester = start_mtc(
      "request", kDomain,
      requester_args({"--profile", "1.3", "--count", "2", "--keep-going", "--timeout", "30s"}));
  ASSERT_EQ(requester->wait_exit(kHandshakeTimeout), 3) << requester->transcript();
  const auto out = outcomes(*requester);
  ASSERT_EQ(out.size(), 2u) << requester->transcript();
  EXPECT_EQ(out[0].result, "FAIL") << out[0].line;
  EXPECT_EQ(out[1].result, "COMPLETE") << out[1].line;
  const auto steps = steps_from_request(*requester, 1);
  EXPECT_TRUE(contains(steps, "response:FAIL")) << requester->transcript();
  EXPECT_FALSE(contains(steps, "request:FAIL")) << requester->transcript();
  auto fail = std::find(steps.begin(), steps.end(), "response:FAIL");
  EXPECT_NE(std::find(fail, steps.end(), "request:READY"), steps.end()) << requester->transcript();
}

// A responder whose interface is DISABLED publishes NOT_READY for every
// service (Part 5: "MUST be set to NOT_READY"): the requester never goes
// ACTIVE, ends NOT_READY (exit 6) and says why.
TEST(InterfaceDisabled, RequesterRefusesToStartAgainstDisabledResponder) {
  constexpr int kDomain = 131;
  auto responder = start_responder(kDomain, responder_args({"--disabled"}));
  const auto ready = ready_line(*responder);
  EXPECT_EQ(json_field(ready, "interface_state"), "DISABLED") << responder->transcript();
  auto requester = start_mtc("request", kDomain, requester_args({"--timeout", "4s"}));
  ASSERT_EQ(requester->wait_exit(kHandshakeTimeout), 6) << requester->transcript();
  const auto out = outcomes(*requester);
  ASSERT_EQ(out.size(), 1u) << requester->transcript();
  EXPECT_EQ(out[0].result, "NOT_READY") << out[0].line;
  const auto steps = transitions(*requester, 1);
  EXPECT_FALSE(contains(steps, "request:ACTIVE")) << requester->transcript();
  EXPECT_NE(requester->stderr_text().find("machine-1 interface mh is DISABLED"), std::string::npos)
      << requester->transcript();
}

// A requester whose own interface is DISABLED does not request at all.
TEST(InterfaceDisabled, DisabledRequesterDoesNotRequest) {
  constexpr int kDomain = 132;
  auto responder = start_responder(kDomain, responder_args({}));
  auto requester = start_mtc("request", kDomain, requester_args({"--disabled", "--timeout", "4s"}));
  ASSERT_EQ(requester->wait_exit(kHandshakeTimeout), 6) << requester->transcript();
  const auto out = outcomes(*requester);
  ASSERT_EQ(out.size(), 1u) << requester->transcript();
  EXPECT_EQ(out[0].result, "NOT_READY") << out[0].line;
  EXPECT_NE(out[0].reason.find("DISABLED"), std::string::npos) << out[0].line;
  EXPECT_FALSE(contains(transitions(*requester, 1), "request:ACTIVE")) << requester->transcript();
  // The responder saw no request.
  EXPECT_FALSE(responder->wait_for_line({"\"event\":\"outcome\""}, milliseconds(0)))
      << responder->transcript();
}

// --peer UUID/INTERFACE pins the pairing: a responder told to serve
// robot-2/mh-b names it in its samples, so robot-1 is told at once that it
// is left out (EXCLUDED, exit 7, the pairing named; never ACTIVE), and
// robot-2 is served.
TEST(Pairing, PeerOptionPinsTheCounterpartInterface) {
  constexpr int kDomain = 133;
  auto responder =
      start_responder(kDomain, {"--device", "machine-1", "--interface", "mh", "--service",
                                "MATERIAL_LOAD", "--peer", "robot-2/mh-b", "--action-ms", "100"});
  auto intruder = start_mtc("request", kDomain,
                            {"--device", "robot-1", "--interface", "mh", "--service",
                             "MATERIAL_LOAD", "--counterpart", "machine-1", "--timeout", "30s"});
  ASSERT_EQ(intruder->wait_exit(kHandshakeTimeout), 7) << intruder->transcript();
  EXPECT_NE(intruder->stderr_text().find("robot-1/mh: machine-1/mh is paired with robot-2/mh-b"),
            std::string::npos)
      << intruder->transcript();
  EXPECT_FALSE(contains(transitions(*intruder, 1), "request:ACTIVE")) << intruder->transcript();
  auto paired = start_mtc("request", kDomain,
                          {"--device", "robot-2", "--interface", "mh-b", "--service",
                           "MATERIAL_LOAD", "--peer", "machine-1/mh", "--timeout", "30s"});
  ASSERT_EQ(paired->wait_exit(kHandshakeTimeout), 0) << paired->transcript();
  const auto served = wait_outcome(*responder, 1);
  ASSERT_TRUE(served) << responder->transcript();
  EXPECT_EQ(json_field(*served, "result"), "COMPLETE");
}

// Bad --peer values are usage errors (exit 2), before anything starts.
TEST(Pairing, MalformedPeerIsAUsageError) {
  for (const char* bad : {"machine-1", "machine-1/", "/mh", "a/b/c"}) {
    auto p = start_mtc(
        "request", 134,
        {"--device", "robot-1", "--interface", "mh", "--service", "MATERIAL_LOAD", "--peer", bad});
    EXPECT_EQ(p->wait_exit(kStartTimeout), 2) << bad << "\n" << p->transcript();
  }
}

}  // namespace
}  // namespace mtc::test
