// Part 5 section 5.1 failure scenarios 1-3 driven across two processes with
// the failure injection of `mtc respond` / `mtc request`. In each case the
// first handshake fails as the scenario describes, both sides report it, both
// recover to READY, and the second handshake completes: nothing is lost.
// Scenarios 4 and 5 need a peer that breaks the protocol: test_mtc_misbehaving_peer.cpp.
// Scenario 6, loss of communication, is in test_mtc_comms_loss.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <ostream>
#include <string>
#include <vector>

#include "mtc_fixture.hpp"

namespace mtc::test {
namespace {

struct Scenario {
  const char* name;
  int domain;
  std::vector<std::string> responder_injection;
  std::vector<std::string> requester_injection;
  // Transitions of the failed handshake, as the requester printed them, that
  // must appear in this order (others may be interleaved).
  std::vector<std::string> ordered;
  // Transitions that must not appear in the failed handshake.
  std::vector<std::string> absent;
};

// What gtest lists for the parameter: a stable name, not a byte dump.
void PrintTo(const Scenario& s, std::ostream* os) {
  *os << s.name;
}

bool contains(const std::vector<std::string>& v, const std::string& item) {
  return std::find(v.begin(), v.end(), item) != v.end();
}

bool is_subsequence(const std::vector<std::string>& wanted, const std::vector<std::string>& seen) {
  auto it = seen.begin();
  for (const auto& w : wanted) {
    it = std::find(it, seen.end(), w);
    if (it == seen.end()) {
      return false;
    }
    ++it;
  }
  return true;
}

class FailureScenario : public ::testing::TestWithParam<Scenario> {};

TEST_P(FailureScenario, BothSidesFailRecoverAndTheNextHandshakeCompletes) {
  const Scenario& s = GetParam();
  std::vector<std::string> responder_args = {
      "--device",      "machine-1", "--interface", "mh",  "--service", "MATERIAL_LOAD",
      "--counterpart", "robot-1",   "--action-ms", "200", "--fail-on", "1"};
  responder_args.insert(responder_args.end(), s.responder_injection.begin(),
                        s.responder_injection.end());
  auto responder = start_responder(s.domain, responder_args);
  std::vector<std::string> requester_args = {
      "--device",      "robot-1",       "--interface", "mh",        "--service",
      "MATERIAL_LOAD", "--counterpart", "machine-1",   "--count",   "2",
      "--keep-going",  "--timeout",     "30s",         "--fail-on", "1"};
  requester_args.insert(requester_args.end(), s.requester_injection.begin(),
                        s.requester_injection.end());
  auto requester = start_mtc("request", s.domain, requester_args);

  // A FAIL among the handshakes: exit code 3, every outcome still reported.
  ASSERT_EQ(requester->wait_exit(kHandshakeTimeout), 3) << requester->transcript();
  const auto req = outcomes(*requester);
  ASSERT_EQ(req.size(), 2u) << requester->transcript();
  EXPECT_EQ(req[0].result, "FAIL") << req[0].line;
  EXPECT_EQ(req[1].result, "COMPLETE") << req[1].line;

  const auto steps = transitions(*requester, 1);
  EXPECT_TRUE(is_subsequence(s.ordered, steps)) << requester->transcript();
  for (const auto& a : s.absent) {
    EXPECT_FALSE(contains(steps, a)) << a << "\n" << requester->transcript();
  }
  // Recovery: both sides back to READY before the outcome is reported.
  ASSERT_FALSE(steps.empty());
  EXPECT_TRUE(contains(steps, "request:READY")) << requester->transcript();
  EXPECT_TRUE(contains(steps, "response:READY")) << requester->transcript();

  const auto first_resp = wait_outcome(*responder, 1);
  ASSERT_TRUE(first_resp) << responder->transcript();
  EXPECT_EQ(json_field(*first_resp, "result"), "FAIL");
  const auto second_resp = wait_outcome(*responder, 2);
  ASSERT_TRUE(second_resp) << responder->transcript();
  EXPECT_EQ(json_field(*second_resp, "result"), "COMPLETE");
}

INSTANTIATE_TEST_SUITE_P(
    Part5Section5_1, FailureScenario,
    ::testing::Values(
        // 1: the responder fails immediately, before going ACTIVE.
        Scenario{"S1_ResponderFailsImmediately",
                 62,
                 {"--fail-at", "accept"},
                 {},
                 {"request:ACTIVE", "response:FAIL", "request:FAIL"},
                 {"response:ACTIVE"}},
        // 2: the responder fails while providing the service.
        Scenario{"S2_ResponderFailsWhileActive",
                 63,
                 {"--fail-at", "active"},
                 {},
                 {"request:ACTIVE", "response:ACTIVE", "response:FAIL", "request:FAIL"},
                 {"response:COMPLETE"}},
        // 2, late: at the moment the action would have completed.
        Scenario{"S2_ResponderFailsAtCompletion",
                 64,
                 {"--fail-at", "complete"},
                 {},
                 {"request:ACTIVE", "response:ACTIVE", "response:FAIL", "request:FAIL"},
                 {"response:COMPLETE"}},
        // 3: the requester fails while the responder is ACTIVE.
        Scenario{"S3_RequesterFailsDuringService",
                 65,
                 {},
                 {"--fail-at", "active"},
                 {"request:ACTIVE", "response:ACTIVE", "request:FAIL", "response:FAIL"},
                 {"response:COMPLETE"}}),
    [](const ::testing::TestParamInfo<Scenario>& param) { return std::string(param.param.name); });

}  // namespace
}  // namespace mtc::test
