#include "scenarios.hpp"

#include <chrono>

#include "stage.hpp"

namespace mtc::demo {
namespace {

using core::InteractionState;
using core::MachineOptions;
using core::Profile;
using namespace std::chrono_literals;

MachineOptions options(Profile p) {
  MachineOptions o;
  o.profile = p;
  return o;
}

// Table 1 steps 1-3: the cnc asks, the robot accepts.
void start_service(Stage& s) {
  s.say("cnc needs material loaded");
  s.show(s.cnc().request(s.now()));
  s.advance(50ms);
  s.to_robot();
  s.show(s.robot().accept(s.now()));
  s.advance(50ms);
  s.to_cnc();
}

void success(Profile p) {
  Stage s(p, options(p), options(p));
  start_service(s);
  s.advance(4000ms);
  s.say("robot has loaded the part");
  s.show(s.robot().complete(s.now()));
  s.advance(50ms);
  s.to_cnc();
  s.advance(50ms);
  s.to_robot();
  s.advance(50ms);
  s.to_cnc();
  s.finish();
}

void responder_fails_immediately(Profile p) {
  Stage s(p, options(p), options(p));
  s.say("cnc needs material loaded");
  s.show(s.cnc().request(s.now()));
  s.advance(50ms);
  s.to_robot();
  s.say("robot detects a fault before it can start (gripper not homed)");
  s.show(s.robot().fail(s.now()));
  s.advance(50ms);
  s.to_cnc();
  s.recover_both();
  s.finish();
}

void responder_fails_during_service(Profile p) {
  Stage s(p, options(p), options(p));
  start_service(s);
  s.advance(1500ms);
  s.say("robot drops the part");
  s.show(s.robot().fail(s.now()));
  s.show(s.robot().recover(InteractionState::Ready, s.now()));
  s.advance(50ms);
  s.to_cnc();
  s.recover_both();
  s.finish();
}

void requester_fails_during_service(Profile p) {
  Stage s(p, options(p), options(p));
  start_service(s);
  s.advance(1500ms);
  s.say("cnc detects a failure (spindle alarm)");
  s.show(s.cnc().fail(s.now()));
  s.advance(50ms);
  s.to_robot();
  s.recover_both();
  s.finish();
}

void requester_unexpected_state(Profile p) {
  Stage s(p, options(p), options(p));
  start_service(s);
  s.advance(1000ms);
  s.say("cnc operator disables the interface: INTERFACE_STATE DISABLED, request NOT_READY");
  s.show(s.cnc().disable(s.now()));
  s.show(s.cnc().request(s.now()));
  s.advance(50ms);
  s.to_robot();
  s.advance(50ms);
  s.to_cnc();
  s.advance(2000ms);
  s.say("cnc interface ENABLED again");
  s.show(s.cnc().enable(s.now()));
  s.recover_both();
  s.finish();
}

void responder_unexpected_state(Profile p) {
  Stage s(p, options(p), options(p));
  start_service(s);
  s.advance(1000ms);
  s.say("robot goes NOT_READY mid-service (its interface is DISABLED)");
  s.show(s.robot().disable(s.now()));
  s.advance(50ms);
  s.to_cnc();
  s.advance(50ms);
  s.to_robot();
  s.advance(2000ms);
  s.say("robot interface ENABLED again");
  s.show(s.robot().enable(s.now()));
  s.recover_both();
  s.finish();
}

void communication_lost(Profile p) {
  Stage s(p, options(p), options(p));
  start_service(s);
  s.advance(800ms);
  s.say("heartbeat lost: each side sees the other UNAVAILABLE");
  s.lose_link();
  s.advance(3000ms);
  s.show(s.cnc().recover(InteractionState::Ready, s.now()));
  s.say("communication re-established: neither trusts the other's old state");
  s.recover_both();
  s.advance(2000ms);
  s.say("a second loss, this time while both sides are idle");
  s.lose_link();
  s.advance(1000ms);
  s.say("communication re-established");
  s.recover_both();
  s.finish();
}

void time_limits(Profile p) {
  MachineOptions o = options(p);
  o.limits.response = 2s;
  o.limits.fail_ack = 5s;
  o.limits.fail_reset = 3s;  // used by 1.3 only
  Stage s(p, o, options(p));
  s.say("limits: response 2 s, FAIL acknowledgement 5 s (1.3: FAIL resets after 3 s)");
  s.say("robot's application hangs: it sees the request but never accepts");
  s.show(s.cnc().request(s.now()));
  s.advance(50ms);
  s.to_robot();
  s.say("link to the robot goes silent (values stop arriving)");
  s.advance(9000ms);
  if (s.cnc().state() == InteractionState::Fail) {
    s.show(s.cnc().recover(InteractionState::Ready, s.now()));
  }
  s.say("link back");
  s.recover_both();
  s.finish();
}

const std::array<Scenario, 8> kScenarios{{
    {0, "Success (Table 1, steps 1-8)",
     "request ACTIVE, response ACTIVE, COMPLETE, request READY, response READY", false, success},
    {1, "Scenario 1 - Responder fails immediately",
     "1.6: the requester MUST go FAIL, both clear FAIL; 1.3: the request goes back to READY", true,
     responder_fails_immediately},
    {2, "Scenario 2 - Responder fails while providing a service",
     "1.6: requester ACTIVE -> FAIL, both recover; 1.3: requester back to READY", true,
     responder_fails_during_service},
    {3, "Scenario 3 - Requester fails during a service request",
     "the responder also goes FAIL; each clears FAIL once the other is FAIL", false,
     requester_fails_during_service},
    {4, "Scenario 4 - Requester changes to an unexpected state",
     "request leaves ACTIVE before COMPLETE (here: INTERFACE_STATE DISABLED): responder FAIL", true,
     requester_unexpected_state},
    {5, "Scenario 5 - Responder changes to an unexpected state",
     "response leaves ACTIVE for NOT_READY: 1.6 requester FAIL; 1.3 requester READY", true,
     responder_unexpected_state},
    {6, "Scenario 6 - Loss of communication / UNAVAILABLE",
     "1.6: both sides FAIL and recover after reconnection; 1.3: only a service in progress fails",
     true, communication_lost},
    {7, "Time limits",
     "request unanswered -> FAIL; FAIL unacknowledged -> recovery allowed; 1.3 FAIL time-out", true,
     time_limits},
}};

}  // namespace

const std::array<Scenario, 8>& scenarios() {
  return kScenarios;
}

}  // namespace mtc::demo
