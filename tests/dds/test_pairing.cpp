// The pairing rule and the excluded requester through the Equipment API
// (issue 12): a responder interface with no counterpart configured pairs
// with the lowest (device uuid, interface id) announced within its settle
// window; the requester left out gets LinkState::Excluded (its cause names
// the pairing) and Outcome::Excluded, never a failure or a violation; the
// pairing holds until the paired device leaves.
#include <gtest/gtest.h>

#include <algorithm>
#include <future>
#include <string>

#include "equipment_fixture.hpp"

namespace mtc::dds::testing {
namespace {

using core::InterfaceType;

EquipmentOptions settled(int domain, const std::string& uuid) {
  auto o = options(domain, uuid);
  // Long enough for both robots below, started one after the other, to be
  // announced before the machine chooses.
  o.pairing_settle = 1500ms;
  return o;
}

bool went_active(Recorder& rec) {
  const auto t = rec.transitions();
  return std::any_of(t.begin(), t.end(), [](const TransitionEvent& e) {
    return e.step.current == InteractionState::Active;
  });
}

bool saw_violation(Recorder& rec) {
  const auto t = rec.transitions();
  return std::any_of(t.begin(), t.end(),
                     [](const TransitionEvent& e) { return e.step.violation(); });
}

std::string excluded_cause(Recorder& rec) {
  for (const auto& l : rec.links()) {
    if (l.current == LinkState::Excluded) return l.cause;
  }
  return "";
}

TEST(PairingRule, LowestCandidateWinsTheOtherIsExcluded) {
  constexpr int kDomain = 146;
  Recorder machine_rec;
  Recorder rec1;
  Recorder rec2;
  Equipment machine(settled(kDomain, "m-p"), machine_rec.callbacks());
  Equipment robot2(options(kDomain, "robot-p2"), rec2.callbacks());
  Equipment robot1(options(kDomain, "robot-p1"), rec1.callbacks());
  machine.add_interface({"mh", InterfaceType::MaterialHandler, "", {}});
  ResponderCallbacks serve;
  serve.on_request = [](Responder& r) { r.complete(); };
  machine.add_responder("mh", Service::MaterialLoad, serve);
  robot2.add_interface({"mh", InterfaceType::MaterialHandler, "", {"m-p", ""}});
  robot1.add_interface({"mh", InterfaceType::MaterialHandler, "", {"m-p", ""}});
  auto& load2 = robot2.add_requester("mh", Service::MaterialLoad);
  auto& load1 = robot1.add_requester("mh", Service::MaterialLoad);
  machine.start();
  robot2.start();  // first, yet robot-p1 < robot-p2
  robot1.start();
  RequestOptions wait;
  wait.wait_for_ready = 15s;
  auto r2 = load2.request(wait);
  auto r1 = load1.request(wait);
  EXPECT_EQ(r1.get().outcome, Outcome::Completed) << rec1.dump() << machine_rec.dump();
  const auto out2 = r2.get();
  EXPECT_EQ(out2.outcome, Outcome::Excluded) << rec2.dump();
  EXPECT_EQ(robot2.link_state("mh"), LinkState::Excluded);
  EXPECT_EQ(excluded_cause(rec2), "m-p/mh is paired with robot-p1/mh") << rec2.dump();
  EXPECT_FALSE(went_active(rec2)) << rec2.dump();
  EXPECT_FALSE(saw_violation(rec2)) << rec2.dump();
  EXPECT_FALSE(saw_violation(machine_rec)) << machine_rec.dump();
  const auto cp = machine.counterpart("mh");
  ASSERT_TRUE(cp.has_value());
  EXPECT_EQ(cp->device_uuid, "robot-p1");
  EXPECT_EQ(cp->interface_id, "mh");
  // Asked again while excluded: the same answer at once.
  EXPECT_EQ(load2.request(wait).get().outcome, Outcome::Excluded);
}

// A requester that comes after the pairing and its first handshake is
// excluded too: the responder's values now name its counterpart's
// participant as well (issue 10's paired_participant), and a value naming
// another interface excludes whatever participant it names. Only a value
// naming our own interface with another participant (written for a previous
// process of our uuid) is ignored instead.
TEST(PairingRule, ARequesterArrivingAfterAHandshakeIsExcluded) {
  constexpr int kDomain = 149;
  Recorder machine_rec;
  Recorder rec2;
  Equipment machine(settled(kDomain, "m-l"), machine_rec.callbacks());
  Equipment robot1(options(kDomain, "robot-l1"));
  machine.add_interface({"mh", InterfaceType::MaterialHandler, "", {}});
  ResponderCallbacks serve;
  serve.on_request = [](Responder& r) { r.complete(); };
  machine.add_responder("mh", Service::MaterialLoad, serve);
  robot1.add_interface({"mh", InterfaceType::MaterialHandler, "", {"m-l", ""}});
  auto& load1 = robot1.add_requester("mh", Service::MaterialLoad);
  machine.start();
  robot1.start();
  RequestOptions wait;
  wait.wait_for_ready = 15s;
  ASSERT_EQ(load1.request(wait).get().outcome, Outcome::Completed) << machine_rec.dump();
  Equipment robot2(options(kDomain, "robot-l2"), rec2.callbacks());
  robot2.add_interface({"mh", InterfaceType::MaterialHandler, "", {"m-l", ""}});
  auto& load2 = robot2.add_requester("mh", Service::MaterialLoad);
  robot2.start();
  EXPECT_EQ(load2.request(wait).get().outcome, Outcome::Excluded) << rec2.dump();
  EXPECT_EQ(excluded_cause(rec2), "m-l/mh is paired with robot-l1/mh") << rec2.dump();
  EXPECT_FALSE(went_active(rec2)) << rec2.dump();
}

// The pairing holds until the paired device leaves: then the responder
// chooses among those still there, and the one left out is served.
TEST(PairingRule, PairingHoldsUntilThePairedDeviceLeaves) {
  constexpr int kDomain = 148;
  Recorder machine_rec;
  Recorder rec2;
  Equipment machine(settled(kDomain, "m-q"), machine_rec.callbacks());
  Equipment robot2(options(kDomain, "robot-q2"), rec2.callbacks());
  machine.add_interface({"mh", InterfaceType::MaterialHandler, "", {}});
  ResponderCallbacks serve;
  serve.on_request = [](Responder& r) { r.complete(); };
  machine.add_responder("mh", Service::MaterialLoad, serve);
  robot2.add_interface({"mh", InterfaceType::MaterialHandler, "", {"m-q", ""}});
  auto& load2 = robot2.add_requester("mh", Service::MaterialLoad);
  RequestOptions wait;
  wait.wait_for_ready = 15s;
  {
    Equipment robot1(options(kDomain, "robot-q1"));
    robot1.add_interface({"mh", InterfaceType::MaterialHandler, "", {"m-q", ""}});
    auto& load1 = robot1.add_requester("mh", Service::MaterialLoad);
    machine.start();
    robot2.start();
    robot1.start();
    EXPECT_EQ(load1.request(wait).get().outcome, Outcome::Completed);
    ASSERT_TRUE(rec2.wait_link(robot2, "mh", LinkState::Excluded)) << rec2.dump();
  }  // robot-q1 leaves: disposes its announcement
  ASSERT_TRUE(machine_rec.wait([&] {
    const auto cp = machine.counterpart("mh");
    return cp && cp->device_uuid == "robot-q2";
  })) << machine_rec.dump();
  ASSERT_TRUE(rec2.wait_link(robot2, "mh", LinkState::Up)) << rec2.dump();
  EXPECT_EQ(load2.request(wait).get().outcome, Outcome::Completed) << rec2.dump();
}

}  // namespace
}  // namespace mtc::dds::testing
