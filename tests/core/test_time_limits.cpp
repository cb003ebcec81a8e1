// Time limits are driven by injected time: deadlines are reported, never slept on.
#include <gtest/gtest.h>

#include "machine_fixtures.hpp"

namespace mtc::core::testing_support {
namespace {

using S = InteractionState;
using N = Notice;
using R = Reason;
using namespace std::chrono_literals;

MachineOptions limits(Duration response, Duration service, Duration completion_ack,
                      Duration fail_ack, Profile p = Profile::V1_6) {
  MachineOptions o;
  o.profile = p;
  o.limits.response = response;
  o.limits.service = service;
  o.limits.completion_ack = completion_ack;
  o.limits.fail_ack = fail_ack;
  return o;
}

TEST(TimeLimits, NothingArmedByDefaultUnder16) {
  Pair p;
  EXPECT_EQ(p.requester.next_deadline(), kNever);
  p.requester.request(p.now);
  p.requester.fail(p.now);
  EXPECT_EQ(p.requester.next_deadline(), kNever) << "1.6 ignores fail_reset";
  EXPECT_EQ(p.requester.on_tick(p.now + 1h).notice, N::None);
  EXPECT_EQ(p.requester.state(), S::Fail);
}

TEST(TimeLimits, RequestUnansweredFailsTheRequester) {
  Pair p(limits(2s, 0s, 0s, 0s), MachineOptions{});
  p.now += 1s;
  p.requester.request(p.now);
  EXPECT_EQ(p.requester.next_deadline(), p.now + 2s);
  EXPECT_EQ(p.requester.on_tick(p.now + 1999ms).notice, N::None);
  const auto r = p.requester.on_tick(p.now + 2s);
  EXPECT_EQ(r.current, S::Fail);
  EXPECT_EQ(r.notice, N::TimedOut);
  EXPECT_EQ(r.reason, R::ResponseTimeout);
}

TEST(TimeLimits, ResponseLimitDisarmsOnceTheResponderIsActive) {
  Pair p(limits(2s, 0s, 0s, 0s), MachineOptions{});
  p.requester.request(p.now);
  p.to_responder();
  p.responder.accept(p.now);
  p.to_requester();
  EXPECT_EQ(p.requester.next_deadline(), kNever);
  EXPECT_EQ(p.requester.on_tick(p.now + 10s).notice, N::None);
  EXPECT_EQ(p.requester.state(), S::Active);
}

TEST(TimeLimits, ServiceTooLongFailsBothSides) {
  const auto o = limits(0s, 10s, 0s, 0s);
  Pair p(o, o);
  p.requester.request(p.now);
  p.now += 1s;
  p.to_responder();
  p.responder.accept(p.now);
  p.to_requester();
  EXPECT_EQ(p.requester.next_deadline(), TimePoint{} + 10s);
  EXPECT_EQ(p.responder.next_deadline(), TimePoint{} + 11s);
  const auto rq = p.requester.on_tick(TimePoint{} + 10s);
  EXPECT_EQ(rq.reason, R::ServiceTimeout);
  EXPECT_EQ(rq.current, S::Fail);
  const auto rs = p.responder.on_tick(TimePoint{} + 11s);
  EXPECT_EQ(rs.reason, R::ServiceTimeout);
  EXPECT_EQ(rs.current, S::Fail);
}

TEST(TimeLimits, CompletionNotAcknowledgedIsReportedOnceAndCompleteHolds) {
  Pair p(MachineOptions{}, limits(0s, 0s, 3s, 0s));
  p.requester.request(p.now);
  p.to_responder();
  p.responder.accept(p.now);
  p.to_requester();
  p.responder.complete(p.now);
  EXPECT_EQ(p.responder.next_deadline(), p.now + 3s);
  const auto r = p.responder.on_tick(p.now + 3s);
  EXPECT_EQ(r.notice, N::TimedOut);
  EXPECT_EQ(r.reason, R::CompletionAckTimeout);
  EXPECT_EQ(r.current, S::Complete) << "COMPLETE MUST hold until acknowledged";
  EXPECT_EQ(p.responder.next_deadline(), kNever);
  p.to_requester();
  EXPECT_EQ(p.to_responder().current, S::Ready);
}

TEST(TimeLimits, FailNotAcknowledgedWaivesTheWait) {
  Pair p(limits(0s, 0s, 0s, 4s), MachineOptions{});
  p.requester.fail(p.now);
  EXPECT_EQ(p.requester.next_deadline(), p.now + 4s);
  EXPECT_EQ(p.requester.recover(S::Ready, p.now).reason, R::FailNotAcknowledged);
  const auto r = p.requester.on_tick(p.now + 4s);
  EXPECT_EQ(r.notice, N::TimedOut);
  EXPECT_EQ(r.reason, R::FailAckTimeout);
  EXPECT_EQ(r.current, S::Fail) << "the limit only permits recovery";
  EXPECT_EQ(p.requester.next_deadline(), kNever);
  EXPECT_EQ(p.requester.recover(S::NotReady, p.now + 4s).current, S::NotReady);
}

TEST(TimeLimits, FailAcknowledgedDisarmsTheFailLimit) {
  Pair p(limits(0s, 0s, 0s, 4s), MachineOptions{});
  p.requester.fail(p.now);
  p.to_responder();
  p.to_requester();
  EXPECT_EQ(p.requester.next_deadline(), kNever);
}

TEST(TimeLimits, FailResetOnlyUnder13) {
  auto o = limits(0s, 0s, 0s, 0s, Profile::V1_3);
  o.limits.fail_reset = 7s;
  Requester rq(Service::PartChange, o);
  rq.on_counterpart(S::Ready, TimePoint{});
  rq.fail(TimePoint{} + 1s);
  EXPECT_EQ(rq.next_deadline(), TimePoint{} + 8s);
  EXPECT_EQ(rq.on_tick(TimePoint{} + 8s).current, S::Ready);
}

TEST(TimeLimits, EarliestLimitFiresFirstOnePerTick) {
  const auto o = limits(1s, 2s, 0s, 0s);
  Pair p(o, o);
  p.requester.request(p.now);
  const auto first = p.requester.on_tick(p.now + 5s);
  EXPECT_EQ(first.reason, R::ResponseTimeout);
  EXPECT_EQ(p.requester.on_tick(p.now + 5s).notice, N::None) << "FAIL disarms the service limit";
}

TEST(TimeLimits, ClockIsWhateverTheCallerSays) {
  const auto o = limits(0s, 0s, 0s, 0s);
  Pair p(o, o);
  p.now = TimePoint{} + 100h;
  p.requester.request(p.now);
  EXPECT_EQ(p.requester.phase_since(), p.now);
}

}  // namespace
}  // namespace mtc::core::testing_support
