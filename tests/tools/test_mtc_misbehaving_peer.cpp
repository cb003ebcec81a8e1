// Failure scenarios 4 and 5 across processes. They need a peer that breaks
// Tables 5/6, which neither the runtime nor `mtc` will do, so the test
// process plays that peer (RoguePeer) against a real `mtc` process and checks
// that the well-behaved side detects the unexpected state, fails, recovers
// and completes the next handshake.
#include <gtest/gtest.h>

#include <algorithm>

#include "mtc_fixture.hpp"
#include "rogue_peer.hpp"

namespace mtc::test {
namespace {

using core::InteractionState;
constexpr milliseconds kStep{20000};

bool has(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

TEST(MisbehavingPeer, S4_RequesterBackToReadyWhileActiveFailsTheResponder) {
  constexpr int kDomain = 66;
  auto responder = start_responder(
      kDomain, {"--device", "machine-1", "--interface", "mh", "--service", "MATERIAL_LOAD",
                "--counterpart", "robot-1", "--action-ms", "60000,10"});
  RoguePeer robot(kDomain, "robot-1", "mh", core::Service::MaterialLoad, core::SubType::Request,
                  "machine-1");
  robot.set_state(InteractionState::Ready);
  ASSERT_TRUE(robot.wait_counterpart(InteractionState::Ready, kStep)) << responder->transcript();
  robot.set_state(InteractionState::Active);
  ASSERT_TRUE(robot.wait_counterpart(InteractionState::Active, kStep)) << responder->transcript();
  robot.set_state(InteractionState::Ready);  // the unexpected change (scenario 4)
  ASSERT_TRUE(robot.wait_counterpart(InteractionState::Fail, kStep)) << responder->transcript();
  const auto first = wait_outcome(*responder, 1);
  ASSERT_TRUE(first) << responder->transcript();
  EXPECT_EQ(json_field(*first, "result"), "FAIL");
  // A requester that sees the responder FAIL follows it (Table 5, FAIL
  // condition 2), which acknowledges it; then both return to READY.
  robot.set_state(InteractionState::Fail);
  ASSERT_TRUE(robot.wait_counterpart(InteractionState::Ready, kStep)) << responder->transcript();
  robot.set_state(InteractionState::Ready);

  robot.set_state(InteractionState::Active);
  ASSERT_TRUE(robot.wait_counterpart(InteractionState::Complete, kStep)) << responder->transcript();
  robot.set_state(InteractionState::Ready);
  const auto second = wait_outcome(*responder, 2);
  ASSERT_TRUE(second) << responder->transcript();
  EXPECT_EQ(json_field(*second, "result"), "COMPLETE");
  ASSERT_TRUE(robot.wait_counterpart(InteractionState::Ready, kStep)) << responder->transcript();

  const auto steps = transitions(*responder, 1);
  EXPECT_TRUE(has(steps, "response:ACTIVE") && has(steps, "response:FAIL"))
      << responder->transcript();
  EXPECT_FALSE(has(steps, "response:COMPLETE")) << responder->transcript();
}

TEST(MisbehavingPeer, S5_ResponderNotReadyWhileActiveFailsTheRequester) {
  constexpr int kDomain = 67;
  RoguePeer machine(kDomain, "machine-1", "mh", core::Service::MaterialLoad,
                    core::SubType::Response, "robot-1");
  machine.set_state(InteractionState::Ready);
  auto requester =
      start_mtc("request", kDomain,
                {"--device", "robot-1", "--interface", "mh", "--service", "MATERIAL_LOAD",
                 "--counterpart", "machine-1", "--count", "2", "--keep-going", "--timeout", "30s"});
  ASSERT_TRUE(machine.wait_counterpart(InteractionState::Active, kStep)) << requester->transcript();
  machine.set_state(InteractionState::Active);
  ASSERT_TRUE(requester->wait_for_line({"\"side\":\"response\"", "\"state\":\"ACTIVE\""}, kStep))
      << requester->transcript();
  machine.set_state(InteractionState::NotReady);  // the unexpected change (scenario 5)
  ASSERT_TRUE(machine.wait_counterpart(InteractionState::Fail, kStep)) << requester->transcript();
  // The responder clears the cause and is READY again.
  machine.set_state(InteractionState::Ready);

  ASSERT_TRUE(machine.wait_counterpart(InteractionState::Active, kStep)) << requester->transcript();
  machine.set_state(InteractionState::Active);
  machine.set_state(InteractionState::Complete);
  ASSERT_TRUE(machine.wait_counterpart(InteractionState::Ready, kStep)) << requester->transcript();
  machine.set_state(InteractionState::Ready);

  ASSERT_EQ(requester->wait_exit(kHandshakeTimeout), 3) << requester->transcript();
  const auto out = outcomes(*requester);
  ASSERT_EQ(out.size(), 2u) << requester->transcript();
  EXPECT_EQ(out[0].result, "FAIL");
  EXPECT_EQ(out[1].result, "COMPLETE");
  const auto steps = steps_from_request(*requester, 1);
  EXPECT_TRUE(has(steps, "response:NOT_READY") && has(steps, "request:FAIL"))
      << requester->transcript();
}

}  // namespace
}  // namespace mtc::test
