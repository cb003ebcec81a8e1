// Scenarios 4 and 5 and protocol violations, against a hand-driven raw
// counterpart (the Equipment API itself never produces these states).
#include <gtest/gtest.h>

#include "equipment_fixture.hpp"
#include "raw_peer.hpp"

namespace mtc::dds::testing {
namespace {

using core::InterfaceType;
using core::Reason;
using core::SubType;

// Scenario 4: the requester returns to READY while the responder is ACTIVE.
TEST(UnexpectedStates, Scenario4RequesterLeavesActive) {
  Recorder rec;
  auto o = options(41, "robot-s4");
  o.recovery = RecoveryPolicy::Manual;
  Equipment robot(o, rec.callbacks());
  robot.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"cnc-s4", "mh1"}});
  std::atomic<int> aborted{-1};
  ResponderCallbacks cb;
  cb.on_abort = [&](Responder&, Reason why) {
    aborted = static_cast<int>(why);
    rec.notify();
  };
  auto& resp = robot.add_responder("mh1", Service::MaterialLoad, cb);
  robot.start();
  RawPeer cnc(41, "cnc-s4", SubType::Request, Service::MaterialLoad);
  cnc.set(InteractionState::Ready);
  ASSERT_TRUE(rec.wait([&] { return resp.counterpart_state() == InteractionState::Ready; }));
  cnc.set(InteractionState::Active);
  ASSERT_TRUE(rec.wait_state(resp, InteractionState::Active));  // auto-accepted
  cnc.set(InteractionState::Ready);
  ASSERT_TRUE(rec.wait_state(resp, InteractionState::Fail));
  ASSERT_TRUE(rec.wait([&] { return aborted.load() >= 0; }));
  EXPECT_EQ(aborted.load(), static_cast<int>(Reason::CounterpartLeftActive));
  // Recovery waits for the requester to acknowledge the FAIL.
  EXPECT_EQ(resp.recover().get().reason, Reason::FailNotAcknowledged);
  cnc.set(InteractionState::Fail);
  ASSERT_TRUE(rec.wait_notice(core::Notice::FailAcknowledged, Reason::None));
  EXPECT_EQ(resp.recover().get().current, InteractionState::Ready);
}

// Scenario 5: the responder goes NOT_READY while ACTIVE.
TEST(UnexpectedStates, Scenario5ResponderLeavesActive) {
  Recorder rec;
  Equipment cnc(options(42, "cnc-s5"), rec.callbacks());
  cnc.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"robot-s5", "mh1"}});
  auto& req = cnc.add_requester("mh1", Service::MaterialUnload);
  cnc.start();
  RawPeer robot(42, "robot-s5", SubType::Response, Service::MaterialUnload, "cnc-s5");
  robot.set(InteractionState::Ready);
  RequestOptions wait;
  wait.wait_for_ready = 10s;
  auto outcome = req.request(wait);
  ASSERT_TRUE(rec.wait_state(req, InteractionState::Active));
  robot.set(InteractionState::Active);
  ASSERT_TRUE(rec.wait([&] { return req.counterpart_state() == InteractionState::Active; }));
  robot.set(InteractionState::NotReady);
  const auto r = outcome.get();
  EXPECT_EQ(r.outcome, Outcome::Failed);
  EXPECT_EQ(r.reason, Reason::CounterpartLeftActive);
}

// A responder that jumps to COMPLETE without ever being ACTIVE (and without
// a skipped change number) is a protocol violation, not a lost ACTIVE.
TEST(UnexpectedStates, CompleteWithoutActiveIsAViolation) {
  Recorder rec;
  Equipment cnc(options(43, "cnc-v"), rec.callbacks());
  cnc.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"robot-v", "mh1"}});
  auto& req = cnc.add_requester("mh1", Service::PartChange);
  cnc.start();
  RawPeer robot(43, "robot-v", SubType::Response, Service::PartChange, "cnc-v");
  robot.set(InteractionState::Ready);
  RequestOptions wait;
  wait.wait_for_ready = 10s;
  auto outcome = req.request(wait);
  ASSERT_TRUE(rec.wait_state(req, InteractionState::Active));
  robot.set(InteractionState::Complete);
  const auto r = outcome.get();
  EXPECT_EQ(r.outcome, Outcome::Failed);
  EXPECT_EQ(r.reason, Reason::CompleteWithoutActive);
  EXPECT_TRUE(rec.saw_notice(core::Notice::ProtocolViolation, Reason::CompleteWithoutActive));
}

}  // namespace
}  // namespace mtc::dds::testing

namespace mtc::dds::testing {
namespace {

// One robot serving two machine tools through two interfaces: losing one
// machine fails only the interface paired with it.
TEST(MultiDevice, LossOfOneCounterpartLeavesTheOtherInterfaceAlone) {
  Recorder rec;
  Equipment robot(options(44, "robot-m"), rec.callbacks());
  robot.add_interface({"to_a", core::InterfaceType::MaterialHandler, "", {"cnc-a", "mh1"}});
  robot.add_interface({"to_b", core::InterfaceType::MaterialHandler, "", {"cnc-b", "mh1"}});
  ResponderCallbacks cb;
  cb.on_request = [](Responder& r) { r.complete(); };
  auto& serve_a = robot.add_responder("to_a", Service::MaterialLoad, cb);
  auto& serve_b = robot.add_responder("to_b", Service::MaterialLoad, cb);
  robot.start();
  auto make_cnc = [](const std::string& uuid, const std::string& robot_itf) {
    auto cnc = std::make_unique<Equipment>(options(44, uuid));
    cnc->add_interface({"mh1", core::InterfaceType::MaterialHandler, "", {"robot-m", robot_itf}});
    cnc->add_requester("mh1", Service::MaterialLoad);
    cnc->start();
    return cnc;
  };
  auto cnc_a = make_cnc("cnc-a", "to_a");
  auto cnc_b = make_cnc("cnc-b", "to_b");
  RequestOptions wait;
  wait.wait_for_ready = 10s;
  EXPECT_EQ(cnc_a->requester("mh1", Service::MaterialLoad)->request(wait).get().outcome,
            Outcome::Completed);
  EXPECT_EQ(cnc_b->requester("mh1", Service::MaterialLoad)->request(wait).get().outcome,
            Outcome::Completed);
  ASSERT_TRUE(rec.wait([&] { return serve_a.counterpart_state() == InteractionState::Ready; }));
  cnc_a.reset();
  ASSERT_TRUE(rec.wait_state(serve_a, InteractionState::Fail));
  EXPECT_EQ(robot.link_state("to_a"), LinkState::Lost);
  EXPECT_EQ(robot.link_state("to_b"), LinkState::Up);
  EXPECT_EQ(serve_b.state(), InteractionState::Ready);
  EXPECT_EQ(cnc_b->requester("mh1", Service::MaterialLoad)->request(wait).get().outcome,
            Outcome::Completed);
}

}  // namespace
}  // namespace mtc::dds::testing

namespace mtc::dds::testing {
namespace {

// RecoveryPolicy::Always: after the responder's own failure (scenario 2)
// both sides return to READY without recover() calls.
TEST(Recovery, AlwaysPolicyClearsEveryAcknowledgedFail) {
  Recorder rec;
  auto cnc_o = options(45, "cnc-al");
  cnc_o.recovery = RecoveryPolicy::Always;
  auto robot_o = options(45, "robot-al");
  robot_o.recovery = RecoveryPolicy::Always;
  Equipment cnc(cnc_o, rec.callbacks());
  Equipment robot(robot_o, rec.callbacks());
  cnc.add_interface({"ch1", core::InterfaceType::Chuck, "", {"robot-al", "ch1"}});
  InterfaceConfig chuck{"ch1", core::InterfaceType::Chuck, "", {"cnc-al", "ch1"}};
  chuck.publishes_chuck_state = true;
  chuck.initial_chuck_state = core::ChuckState::Open;
  robot.add_interface(chuck);
  auto& close = cnc.add_requester("ch1", Service::CloseChuck);
  ResponderCallbacks cb;
  cb.on_request = [](Responder& r) { r.fail(); };  // the chuck jams
  auto& resp = robot.add_responder("ch1", Service::CloseChuck, cb);
  cnc.start();
  robot.start();
  RequestOptions wait;
  wait.wait_for_ready = 10s;
  EXPECT_EQ(close.request(wait).get().outcome, Outcome::Failed);
  EXPECT_TRUE(rec.wait_state(close, InteractionState::Ready));
  EXPECT_TRUE(rec.wait_state(resp, InteractionState::Ready));
  // Once the chuck is CLOSED, CLOSE_CHUCK can no longer be served.
  robot.set_chuck_state("ch1", core::ChuckState::Closed).get();
  EXPECT_EQ(resp.state(), InteractionState::NotReady);
  EXPECT_TRUE(rec.wait([&] { return close.counterpart_state() == InteractionState::NotReady; }));
}

}  // namespace
}  // namespace mtc::dds::testing
