// FAIL acknowledgement across failure episodes (Tables 5/6 ACTIONS): only a
// fresh FAIL of the counterpart acknowledges ours. Found by the randomized
// test: a FAIL already answered in an earlier episode must not let a new
// FAIL be cleared early.
#include <gtest/gtest.h>

#include "machine_fixtures.hpp"

namespace mtc::core::testing_support {
namespace {

using S = InteractionState;
using N = Notice;
using R = Reason;

TEST(Acknowledgement, AnsweredFailOfAnEarlierEpisodeDoesNotAcknowledge) {
  Responder rs(Service::MaterialLoad);
  const TimePoint t{};
  rs.on_counterpart(S::Ready, t);
  rs.on_counterpart(S::Fail, t);  // episode 1: request FAIL, response follows
  ASSERT_EQ(rs.state(), S::Fail);
  ASSERT_TRUE(rs.fail_acknowledged());
  ASSERT_EQ(rs.recover(S::Ready, t).current, S::Ready);
  // The requester has recovered too, but its READY is still in flight: the
  // responder still sees the old FAIL when it fails on its own.
  const auto f = rs.fail(t);
  EXPECT_EQ(f.current, S::Fail);
  EXPECT_FALSE(rs.fail_acknowledged()) << "that FAIL was the previous episode's";
  EXPECT_EQ(rs.recover(S::Ready, t).reason, R::FailNotAcknowledged);
  rs.on_counterpart(S::Ready, t);                                        // the late READY
  EXPECT_EQ(rs.on_counterpart(S::Fail, t).notice, N::FailAcknowledged);  // the real ack
}

TEST(Acknowledgement, CounterpartFailingAnewWhileWeAreInFailIsAnsweredAfterRecovery) {
  Requester rq(Service::MaterialLoad);
  const TimePoint t{};
  rq.on_counterpart(S::Ready, t);
  rq.fail(t);
  EXPECT_EQ(rq.on_counterpart(S::Fail, t).notice, N::FailAcknowledged);
  // The responder recovers and fails again before it saw us recover; it
  // waits for our change to FAIL, which we cannot show while in FAIL.
  rq.on_counterpart(S::Ready, t);
  EXPECT_EQ(rq.on_counterpart(S::Fail, t).notice, N::None);
  const auto rec = rq.recover(S::Ready, t + std::chrono::seconds(1));
  EXPECT_EQ(rec.current, S::Ready) << "READY is published first";
  EXPECT_EQ(rq.next_deadline(), t + std::chrono::seconds(1)) << "reaction due at once";
  const auto react = rq.on_tick(t + std::chrono::seconds(1));
  EXPECT_EQ(react.current, S::Fail);
  EXPECT_EQ(react.notice, N::CounterpartFailed);
  EXPECT_TRUE(rq.fail_acknowledged());
  EXPECT_EQ(rq.next_deadline(), kNever);
}

// Issue 10: a responder failed by a loss of communication leaves FAIL by
// the fail_ack limit before the (restarted) requester's acknowledgement
// arrives. That FAIL, late, answers ours: failing again for it failed the
// request the requester made next, on seeing the responder READY.
TEST(Acknowledgement, LateAcknowledgementAfterTheWaitWasWaivedIsNoNewFailure) {
  MachineOptions o;
  o.limits.fail_ack = std::chrono::seconds(2);
  Responder rs(Service::MaterialLoad, o);
  const TimePoint t{};
  rs.on_counterpart(S::Ready, t);
  ASSERT_EQ(rs.on_counterpart_lost(t).current, S::Fail);
  rs.on_counterpart(S::Ready, t);  // the new incarnation, not an acknowledgement
  ASSERT_FALSE(rs.fail_acknowledged());
  const auto waived = rs.on_tick(t + std::chrono::seconds(2));
  ASSERT_EQ(waived.reason, R::FailAckTimeout);
  ASSERT_EQ(rs.recover(S::Ready, t + std::chrono::seconds(2)).current, S::Ready);
  const auto late = rs.on_counterpart(S::Fail, t + std::chrono::seconds(3));
  EXPECT_EQ(late.current, S::Ready) << "the late acknowledgement is no new failure";
  EXPECT_EQ(late.notice, N::FailAcknowledged);
  EXPECT_EQ(rs.next_deadline(), t + std::chrono::seconds(5)) << "unless it stays FAIL";
  rs.on_counterpart(S::Ready, t + std::chrono::seconds(3));
  EXPECT_EQ(rs.next_deadline(), kNever) << "it recovered: it was an acknowledgement";
  EXPECT_EQ(rs.on_counterpart(S::Active, t + std::chrono::seconds(3)).notice, N::RequestObserved);
  // Once a handshake moved on, a FAIL is a failure again.
  ASSERT_EQ(rs.accept(t + std::chrono::seconds(3)).current, S::Active);
  ASSERT_EQ(rs.complete(t + std::chrono::seconds(3)).current, S::Complete);
  rs.on_counterpart(S::Ready, t + std::chrono::seconds(3));
  ASSERT_EQ(rs.state(), S::Ready);
  EXPECT_EQ(rs.on_counterpart(S::Fail, t + std::chrono::seconds(4)).current, S::Fail);
}

// The FAIL taken for a late acknowledgement was a new failure after all:
// the counterpart stays FAIL, waiting for ours; it gets it after fail_ack
// (the randomized test found the deadlock when it never came).
TEST(Acknowledgement, ALateAcknowledgementThatStaysFailIsAnsweredAfterFailAck) {
  MachineOptions o;
  o.limits.fail_ack = std::chrono::seconds(2);
  Requester rq(Service::MaterialLoad, o);
  const TimePoint t{};
  rq.on_counterpart(S::Ready, t);
  rq.on_counterpart_lost(t);
  rq.on_tick(t + std::chrono::seconds(2));  // fail_ack waived
  ASSERT_EQ(rq.recover(S::Ready, t + std::chrono::seconds(2)).current, S::Ready);
  ASSERT_EQ(rq.on_counterpart(S::Fail, t + std::chrono::seconds(3)).current, S::Ready);
  EXPECT_EQ(rq.on_tick(t + std::chrono::seconds(4)).current, S::Ready) << "not yet";
  const auto answer = rq.on_tick(t + std::chrono::seconds(5));
  EXPECT_EQ(answer.current, S::Fail);
  EXPECT_EQ(answer.notice, N::CounterpartFailed);
  EXPECT_TRUE(rq.fail_acknowledged());
}

// Without a waived wait, a counterpart FAIL while idle stays a failure.
TEST(Acknowledgement, AcknowledgedRecoveryOwesNothing) {
  Responder rs(Service::MaterialLoad);
  const TimePoint t{};
  rs.on_counterpart(S::Ready, t);
  rs.on_counterpart_lost(t);
  rs.on_counterpart(S::Fail, t);  // acknowledged
  ASSERT_EQ(rs.recover(S::Ready, t).current, S::Ready);
  rs.on_counterpart(S::Ready, t);
  EXPECT_EQ(rs.on_counterpart(S::Fail, t).current, S::Fail);
}

TEST(Acknowledgement, PairSettlesAfterCrossedFailures) {
  Pair p;
  p.requester.fail(p.now);
  p.responder.fail(p.now);  // independent failures cross on the wire
  EXPECT_EQ(p.to_requester().notice, N::FailAcknowledged);
  EXPECT_EQ(p.to_responder().notice, N::FailAcknowledged);
  p.requester.recover(S::Ready, p.now);
  p.responder.recover(S::Ready, p.now);
  p.to_requester();
  p.to_responder();
  EXPECT_EQ(p.requester.state(), S::Ready);
  EXPECT_EQ(p.responder.state(), S::Ready);
  EXPECT_EQ(p.requester.next_deadline(), kNever);
  EXPECT_EQ(p.responder.next_deadline(), kNever);
}

}  // namespace
}  // namespace mtc::core::testing_support
