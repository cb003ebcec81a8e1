// Table 1 step by step and the failure scenarios of section 5.1 (1.6/1.8),
// replayed as the text describes them, then the 1.3 variants where 1.3
// differs (section 3.4 of the 1.3 text).
#include <gtest/gtest.h>

#include "machine_fixtures.hpp"

namespace mtc::core::testing_support {
namespace {

using S = InteractionState;
using N = Notice;
using R = Reason;
using namespace std::chrono_literals;

// Plays Table 1 up to and including `last_step`, returning that step's result.
StepResult play_table1(Pair& p, int last_step) {
  StepResult r;
  for (int step = 1; step <= last_step; ++step) {
    switch (step) {
      case 1:
        r = p.requester.request(p.now);
        break;
      case 2:
        r = p.to_responder();
        break;
      case 3:
        r = p.responder.accept(p.now);
        break;
      case 4:
        r = p.responder.complete(p.now);
        break;
      case 5:  // requester detects COMPLETE ...
      case 6:  // ... and is back to READY (same step)
        r = p.to_requester();
        break;
      case 7:  // responder detects READY ...
      case 8:  // ... and is back to READY
        r = p.to_responder();
        break;
      default:
        break;
    }
    if (step == 3) p.to_requester();     // the requester sees the response ACTIVE
    if (step == 5 || step == 7) ++step;  // detection and reaction are one event
  }
  return r;
}

TEST(Table1, Step1_RequestTransitionsFromReadyToActive) {
  Pair p;
  const auto r = play_table1(p, 1);
  EXPECT_EQ(r.previous, S::Ready);
  EXPECT_EQ(r.current, S::Active);
  EXPECT_EQ(r.notice, N::RequestIssued);
}

TEST(Table1, Step2_ResponderDetectsTheRequest) {
  Pair p;
  const auto r = play_table1(p, 2);
  EXPECT_EQ(r.notice, N::RequestObserved);
  EXPECT_EQ(r.current, S::Ready) << "detection alone does not change the response";
  EXPECT_EQ(p.responder.counterpart(), S::Active);
}

TEST(Table1, Step3_ResponseTransitionsFromReadyToActive) {
  Pair p;
  const auto r = play_table1(p, 3);
  EXPECT_EQ(r.previous, S::Ready);
  EXPECT_EQ(r.current, S::Active);
  EXPECT_EQ(r.notice, N::Accepted);
}

TEST(Table1, Step4_ResponseTransitionsToComplete) {
  Pair p;
  const auto r = play_table1(p, 4);
  EXPECT_EQ(r.previous, S::Active);
  EXPECT_EQ(r.current, S::Complete);
  EXPECT_EQ(r.notice, N::Completed);
}

TEST(Table1, Step5_RequesterDetectsComplete) {
  Pair p;
  const auto r = play_table1(p, 5);
  EXPECT_EQ(r.event, Event::SeenComplete);
  EXPECT_EQ(r.notice, N::Completed);
}

TEST(Table1, Step6_RequestReturnsToReadyAcknowledging) {
  Pair p;
  const auto r = play_table1(p, 6);
  EXPECT_EQ(r.previous, S::Active);
  EXPECT_EQ(r.current, S::Ready);
  EXPECT_EQ(p.responder.state(), S::Complete) << "COMPLETE holds until the ack is seen";
}

TEST(Table1, Step7_ResponderDetectsRequestReady) {
  Pair p;
  const auto r = play_table1(p, 7);
  EXPECT_EQ(r.event, Event::SeenReady);
  EXPECT_EQ(r.notice, N::Acknowledged);
}

TEST(Table1, Step8_ResponseReturnsToReady) {
  Pair p;
  const auto r = play_table1(p, 8);
  EXPECT_EQ(r.previous, S::Complete);
  EXPECT_EQ(r.current, S::Ready);
  p.to_requester();
  EXPECT_EQ(p.requester.state(), S::Ready);
  EXPECT_EQ(p.responder.state(), S::Ready);
  EXPECT_EQ(p.requester.request(p.now).current, S::Active) << "ready for another action";
}

TEST(Table1, Step8_ResponseMayChooseNotReady) {
  Pair p;
  play_table1(p, 4);
  p.responder.set_not_ready(p.now);  // wish recorded, COMPLETE must hold
  EXPECT_EQ(p.responder.state(), S::Complete);
  p.to_requester();
  EXPECT_EQ(p.to_responder().current, S::NotReady);
}

// Both sides clear FAIL; the text lets each choose READY or NOT_READY.
void recover_both(Pair& p, S requester_to = S::Ready, S responder_to = S::Ready) {
  EXPECT_EQ(p.requester.recover(requester_to, p.now).notice, N::Recovered);
  p.to_responder();
  EXPECT_EQ(p.responder.recover(responder_to, p.now).notice, N::Recovered);
  p.to_requester();
  EXPECT_EQ(p.requester.state(), requester_to);
  EXPECT_EQ(p.responder.state(), responder_to);
}

TEST(Scenarios16, Scenario1_ResponderFailsImmediately) {
  Pair p;
  p.requester.request(p.now);
  EXPECT_EQ(p.to_responder().notice, N::RequestObserved);
  const auto fail = p.responder.fail(p.now);  // before it could go ACTIVE
  EXPECT_EQ(fail.current, S::Fail);
  const auto seen = p.to_requester();  // Requester MUST change its state to FAIL
  EXPECT_EQ(seen.current, S::Fail);
  EXPECT_EQ(seen.notice, N::CounterpartFailed);
  EXPECT_EQ(seen.reason, R::CounterpartFail);
  // The responder may not clear FAIL before the request acknowledged it.
  EXPECT_EQ(p.to_responder().notice, N::FailAcknowledged);
  recover_both(p, S::Ready, S::NotReady);
}

TEST(Scenarios16, Scenario2_ResponderFailsWhileProvidingService) {
  Pair p;
  p.requester.request(p.now);
  p.to_responder();
  p.responder.accept(p.now);
  EXPECT_EQ(p.to_requester().notice, N::Accepted);
  EXPECT_EQ(p.responder.fail(p.now).current, S::Fail);
  EXPECT_EQ(p.responder.recover(S::Ready, p.now).reason, R::FailNotAcknowledged);
  const auto seen = p.to_requester();
  EXPECT_EQ(seen.previous, S::Active);
  EXPECT_EQ(seen.current, S::Fail);
  p.to_responder();
  recover_both(p, S::NotReady, S::Ready);
}

TEST(Scenarios16, Scenario3_RequesterFailsDuringServiceRequest) {
  Pair p;
  p.requester.request(p.now);
  p.to_responder();
  p.responder.accept(p.now);
  p.to_requester();
  EXPECT_EQ(p.requester.fail(p.now).current, S::Fail);
  EXPECT_EQ(p.requester.recover(S::Ready, p.now).reason, R::FailNotAcknowledged);
  const auto seen = p.to_responder();  // responder also transitions to FAIL
  EXPECT_EQ(seen.current, S::Fail);
  EXPECT_EQ(seen.reason, R::CounterpartFail);
  EXPECT_EQ(p.to_requester().notice, N::FailAcknowledged);
  recover_both(p);
}

// The requester here is a foreign device whose values the test scripts:
// our Requester cannot make this unexpected change (it is refused).
TEST(Scenarios16, Scenario4_RequesterChangesToUnexpectedState) {
  Responder rs(Service::MaterialLoad);
  TimePoint now{};
  rs.on_counterpart(S::Ready, now);
  rs.on_counterpart(S::Active, now);
  rs.accept(now);
  const auto r = rs.on_counterpart(S::Ready, now);  // back to READY before COMPLETE
  EXPECT_EQ(r.current, S::Fail);
  EXPECT_EQ(r.notice, N::CounterpartFailed);
  EXPECT_EQ(r.reason, R::CounterpartLeftActive);
  EXPECT_EQ(rs.recover(S::Ready, now).reason, R::FailNotAcknowledged);
  // A 1.6 requester seeing the response FAIL MUST go FAIL (Table 5 condition 2).
  Requester rq(Service::MaterialLoad);
  rq.on_counterpart(S::Ready, now);
  EXPECT_EQ(rq.on_counterpart(S::Fail, now).current, S::Fail);
  EXPECT_EQ(rs.on_counterpart(rq.state(), now).notice, N::FailAcknowledged);
  EXPECT_EQ(rs.recover(S::Ready, now).current, S::Ready);

  Requester ours(Service::MaterialLoad);
  ours.on_counterpart(S::Ready, now);
  ours.request(now);
  EXPECT_EQ(ours.set_ready(now).reason, R::NotIdle) << "our requester refuses the change";
}

TEST(Scenarios16, Scenario4_NoteRequesterGoesNotReadyViaDisabledInterface) {
  Pair p;
  p.requester.request(p.now);
  p.to_responder();
  p.responder.accept(p.now);
  p.to_requester();
  EXPECT_EQ(p.requester.disable(p.now).current, S::NotReady);  // INTERFACE_STATE DISABLED
  EXPECT_EQ(p.to_responder().reason, R::CounterpartLeftActive);
  EXPECT_EQ(p.responder.state(), S::Fail);
  p.to_requester();  // seen while disabled: remembered
  EXPECT_EQ(p.requester.state(), S::NotReady);
  const auto enabled = p.requester.enable(p.now);
  EXPECT_EQ(enabled.current, S::Fail) << "re-enabled requester acknowledges the pending FAIL";
  EXPECT_EQ(p.to_responder().notice, N::FailAcknowledged);
  recover_both(p);
}

TEST(Scenarios16, Scenario5_ResponderChangesToUnexpectedState) {
  MachineOptions o;
  o.limits.fail_ack = 5s;
  Requester rq(Service::MaterialLoad, o);
  TimePoint now{};
  rq.on_counterpart(S::Ready, now);
  rq.request(now);
  rq.on_counterpart(S::Active, now);
  const auto r = rq.on_counterpart(S::NotReady, now);  // responder to NOT_READY mid-service
  EXPECT_EQ(r.current, S::Fail);
  EXPECT_EQ(r.reason, R::CounterpartLeftActive);
  // The text has this responder return to READY without passing FAIL; a
  // requester following Table 5 waits for FAIL, so only the fail_ack limit
  // frees it.
  EXPECT_EQ(rq.on_counterpart(S::Ready, now).notice, N::None);
  EXPECT_EQ(rq.recover(S::Ready, now).reason, R::FailNotAcknowledged);
  EXPECT_EQ(rq.next_deadline(), now + 5s);
  EXPECT_EQ(rq.on_tick(now + 4s).notice, N::None);
  const auto t = rq.on_tick(now + 5s);
  EXPECT_EQ(t.notice, N::TimedOut);
  EXPECT_EQ(t.reason, R::FailAckTimeout);
  EXPECT_EQ(rq.recover(S::Ready, now + 5s).current, S::Ready);
}

TEST(Scenarios16, Scenario5_OurResponderDisabledMidServiceThenAcknowledges) {
  Pair p;
  p.requester.request(p.now);
  p.to_responder();
  p.responder.accept(p.now);
  p.to_requester();
  p.responder.disable(p.now);
  EXPECT_EQ(p.to_requester().reason, R::CounterpartLeftActive);
  p.to_responder();
  EXPECT_EQ(p.responder.enable(p.now).current, S::Fail);
  EXPECT_EQ(p.to_requester().notice, N::FailAcknowledged);
  recover_both(p);
}

TEST(Scenarios16, Scenario6_LossOfCommunicationDuringService) {
  Pair p;
  p.requester.request(p.now);
  p.to_responder();
  p.responder.accept(p.now);
  p.to_requester();
  // Heartbeat lost: each side assumes the other failed.
  const auto a = p.requester.on_counterpart_lost(p.now);
  const auto b = p.responder.on_counterpart_lost(p.now);
  EXPECT_EQ(a.current, S::Fail);
  EXPECT_EQ(a.notice, N::CommsLost);
  EXPECT_EQ(b.current, S::Fail);
  EXPECT_EQ(p.requester.recover(S::Ready, p.now).reason, R::FailNotAcknowledged);
  // Reconnected: neither trusts the old state; each sees the other FAIL.
  EXPECT_EQ(p.to_requester().notice, N::FailAcknowledged);
  EXPECT_EQ(p.to_responder().notice, N::FailAcknowledged);
  recover_both(p);
}

TEST(Scenarios16, Scenario6_CounterpartUnavailableWhileIdle) {
  Pair p;
  EXPECT_EQ(p.requester.on_counterpart(S::Unavailable, p.now).current, S::Fail);
  EXPECT_EQ(p.responder.on_counterpart_text("UNAVAILABLE", p.now).current, S::Fail);
  p.to_requester();
  p.to_responder();
  recover_both(p);
}

TEST(Scenarios16, Scenario6_AcknowledgementBeforeTheLossIsNotTrusted) {
  Pair p;
  p.requester.fail(p.now);
  p.to_responder();
  EXPECT_EQ(p.to_requester().notice, N::FailAcknowledged);
  p.requester.on_counterpart_lost(p.now);
  EXPECT_FALSE(p.requester.fail_acknowledged());
  EXPECT_EQ(p.requester.recover(S::Ready, p.now).reason, R::FailNotAcknowledged);
  const auto back = p.to_requester();  // still FAIL after reconnection
  EXPECT_EQ(back.notice, N::FailAcknowledged);
  EXPECT_EQ(p.requester.recover(S::Ready, p.now).current, S::Ready);
}

// ------------------------------------------------------------------ 1.3
TEST(Scenarios13, Scenario1_ResponderFailsImmediately_RequestReturnsToReady) {
  Pair p(Profile::V1_3);
  p.requester.request(p.now);
  p.to_responder();
  p.responder.fail(p.now);
  const auto seen = p.to_requester();  // 1.3: "the request MUST transition back to READY"
  EXPECT_EQ(seen.current, S::Ready);
  EXPECT_EQ(seen.notice, N::CounterpartFailed);
  // 1.3: the request leaving ACTIVE is the acknowledgement of the FAIL.
  EXPECT_EQ(p.to_responder().notice, N::FailAcknowledged);
  EXPECT_TRUE(p.responder.fail_acknowledged());
  EXPECT_EQ(p.responder.recover(S::Ready, p.now).current, S::Ready);
}

TEST(Scenarios13, Scenario2_ResponderFailsWhileProvidingService) {
  Pair p(Profile::V1_3);
  p.requester.request(p.now);
  p.to_responder();
  p.responder.accept(p.now);
  p.to_requester();
  p.responder.fail(p.now);
  EXPECT_EQ(p.to_requester().current, S::Ready);
  p.to_responder();
  EXPECT_EQ(p.responder.recover(S::NotReady, p.now).current, S::NotReady);
}

TEST(Scenarios13, Scenario3_RequesterFails_BothFailThenClear) {
  Pair p(Profile::V1_3);
  p.requester.request(p.now);
  p.to_responder();
  p.responder.accept(p.now);
  p.to_requester();
  p.requester.fail(p.now);
  EXPECT_EQ(p.to_responder().current, S::Fail);  // "the response will fail as well"
  EXPECT_EQ(p.to_requester().notice, N::FailAcknowledged);
  recover_both(p);
}

TEST(Scenarios13, FailTimesOutToReady) {
  MachineOptions o;
  o.profile = Profile::V1_3;
  o.limits.fail_reset = 3s;
  Pair p(o, o);
  p.requester.request(p.now);
  p.to_responder();
  p.responder.accept(p.now);
  p.to_requester();
  p.requester.fail(p.now);
  // The responder never acknowledges (e.g. it has crashed); no one is stuck.
  EXPECT_EQ(p.requester.next_deadline(), p.now + 3s);
  const auto r = p.requester.on_tick(p.now + 3s);
  EXPECT_EQ(r.current, S::Ready);
  EXPECT_EQ(r.notice, N::Recovered);
  EXPECT_EQ(r.reason, R::FailResetTimeout);
}

TEST(Scenarios13, DeviceWithoutFailRequesterLeavesActiveEarly) {
  MachineOptions o;
  o.profile = Profile::V1_3;
  o.counterpart_has_fail = false;
  Responder rs(Service::MaterialLoad, o);
  TimePoint now{};
  rs.on_counterpart(S::Ready, now);
  rs.on_counterpart(S::Active, now);
  rs.accept(now);
  const auto r = rs.on_counterpart(S::Ready, now);  // simple logic control stops
  EXPECT_EQ(r.current, S::Fail);
  EXPECT_EQ(r.reason, R::CounterpartLeftActive);
  EXPECT_TRUE(rs.fail_acknowledged()) << "a device without FAIL cannot show FAIL";
  EXPECT_EQ(rs.recover(S::Ready, now).current, S::Ready);
}

TEST(Scenarios13, DeviceWithoutFailResponderLeavesActiveEarly) {
  MachineOptions o;
  o.profile = Profile::V1_3;
  o.counterpart_has_fail = false;
  Requester rq(Service::MaterialLoad, o);
  TimePoint now{};
  rq.on_counterpart(S::Ready, now);
  rq.request(now);
  rq.on_counterpart(S::Active, now);
  // "MUST be handled in the same manner as if the response had transitioned
  // to FAIL first": under 1.3 that is back to READY.
  const auto r = rq.on_counterpart(S::Ready, now);
  EXPECT_EQ(r.current, S::Ready);
  EXPECT_EQ(r.notice, N::CounterpartFailed);
  EXPECT_EQ(r.reason, R::CounterpartLeftActive);
}

TEST(Scenarios13, DeviceWithoutFailUnder16StillFailsButNeedsNoFailAck) {
  MachineOptions o;
  o.counterpart_has_fail = false;
  Requester rq(Service::MaterialLoad, o);
  TimePoint now{};
  rq.on_counterpart(S::Ready, now);
  rq.request(now);
  rq.on_counterpart(S::Active, now);
  EXPECT_EQ(rq.on_counterpart(S::NotReady, now).current, S::Fail);
  EXPECT_TRUE(rq.fail_acknowledged());
  EXPECT_EQ(rq.recover(S::Ready, now).current, S::Ready);
}

TEST(Scenarios13, Scenario6_IdleSideWaitsEngagedSideFails) {
  Pair p(Profile::V1_3);
  EXPECT_EQ(p.requester.on_counterpart_lost(p.now).current, S::Ready);
  EXPECT_EQ(p.to_requester().notice, N::CommsRestored);
  p.requester.request(p.now);
  p.to_responder();
  p.responder.accept(p.now);
  EXPECT_EQ(p.responder.on_counterpart_lost(p.now).current, S::Fail);
}

}  // namespace
}  // namespace mtc::core::testing_support
