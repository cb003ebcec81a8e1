// INTERFACE_STATE (Table 3), the door/chuck precondition hook (1.3 section
// 3.3) and interface-wide operations.
#include <gtest/gtest.h>

#include "machine_fixtures.hpp"
#include "mtc/core/interface_model.hpp"

namespace mtc::core::testing_support {
namespace {

using S = InteractionState;
using N = Notice;
using R = Reason;
using namespace std::chrono_literals;

InterfaceModel material_handler() {
  InterfaceModel m(InterfaceType::MaterialHandler);
  EXPECT_TRUE(m.add_requester(Service::MaterialLoad));
  EXPECT_TRUE(m.add_requester(Service::MaterialUnload));
  EXPECT_TRUE(m.add_responder(Service::PartChange));
  return m;
}

TEST(InterfaceModel, EachServiceAtMostOncePerRole) {
  InterfaceModel m = material_handler();
  EXPECT_FALSE(m.add_requester(Service::MaterialLoad));
  EXPECT_TRUE(m.add_responder(Service::MaterialLoad));
  EXPECT_EQ(m.machine_count(), 4u);
  EXPECT_EQ(m.responder(Service::OpenDoor), nullptr);
  EXPECT_FALSE(m.add_requester(static_cast<Service>(99)));
  EXPECT_EQ(m.requester(static_cast<Service>(99)), nullptr);
  EXPECT_EQ(m.machine(Service::PartChange, Role::Responder), m.responder(Service::PartChange));
}

TEST(InterfaceModel, DisabledForcesEveryItemNotReadyAndRefusesCommands) {
  InterfaceModel m = material_handler();
  const TimePoint t{};
  auto* load = m.requester(Service::MaterialLoad);
  load->on_counterpart(S::Ready, t);
  load->request(t);
  auto batch = m.set_interface_state(InterfaceState::Disabled, t);
  EXPECT_EQ(batch.size(), 3u);
  for (const auto& r : batch) {
    EXPECT_EQ(r.current, S::NotReady) << to_string(r.service);
    EXPECT_EQ(r.notice, N::Disabled);
  }
  EXPECT_TRUE(batch.any_changed());
  EXPECT_EQ(load->request(t).reason, R::InterfaceDisabled);
  EXPECT_EQ(m.responder(Service::PartChange)->set_ready(t).reason, R::InterfaceDisabled);
  // Re-enabled: the items may return to READY.
  batch = m.set_interface_state(InterfaceState::Enabled, t);
  for (const auto& r : batch) {
    EXPECT_EQ(r.current, S::Ready);
    EXPECT_EQ(r.notice, N::Enabled);
  }
}

TEST(InterfaceModel, UnavailableInterfaceStateCountsAsDisabled) {
  InterfaceModel m = material_handler();
  m.set_interface_state(InterfaceState::Unavailable, TimePoint{});
  EXPECT_EQ(m.interface_state(), InterfaceState::Unavailable);
  EXPECT_TRUE(m.requester(Service::MaterialLoad)->disabled());
  EXPECT_TRUE(m.add_responder(Service::MaterialFeed));
  EXPECT_TRUE(m.responder(Service::MaterialFeed)->disabled()) << "added while disabled";
}

TEST(InterfaceModel, CounterpartLostReachesEveryMachine) {
  InterfaceModel m = material_handler();
  const TimePoint t{};
  for (auto s : {Service::MaterialLoad, Service::MaterialUnload}) {
    m.requester(s)->on_counterpart(S::Ready, t);
  }
  m.responder(Service::PartChange)->on_counterpart(S::Ready, t);
  const auto batch = m.counterpart_lost(t);
  ASSERT_EQ(batch.size(), 3u);
  for (const auto& r : batch) {
    EXPECT_EQ(r.current, S::Fail);
    EXPECT_EQ(r.notice, N::CommsLost);
  }
}

// The earliest limit of any machine, requester or responder, whatever order
// they were added in; a copy of the model answers from its own machines.
TEST(InterfaceModel, NextDeadlineIsTheEarliestOfEveryMachine) {
  MachineOptions o;
  o.limits.response = 1s;
  InterfaceModel m(InterfaceType::MaterialHandler, o);
  EXPECT_EQ(m.next_deadline(), kNever);
  EXPECT_EQ(m.machine_count(), 0u);
  m.add_responder(Service::PartChange);
  m.add_requester(Service::MaterialUnload);
  m.add_requester(Service::MaterialLoad);
  EXPECT_EQ(m.machine_count(), 3u);
  const TimePoint t{};
  for (auto s : {Service::MaterialLoad, Service::MaterialUnload}) {
    m.requester(s)->on_counterpart(S::Ready, t);
  }
  EXPECT_EQ(m.next_deadline(), kNever);
  m.requester(Service::MaterialUnload)->request(t + 300ms);
  EXPECT_EQ(m.next_deadline(), t + 1300ms);
  const InterfaceModel before_load = m;
  m.requester(Service::MaterialLoad)->request(t + 100ms);
  EXPECT_EQ(m.next_deadline(), t + 1100ms);
  EXPECT_EQ(before_load.next_deadline(), t + 1300ms);
  EXPECT_EQ(before_load.machine_count(), 3u);
}

TEST(InterfaceModel, TickFiresEveryExpiredLimit) {
  MachineOptions o;
  o.limits.response = 1s;
  InterfaceModel m(InterfaceType::MaterialHandler, o);
  m.add_requester(Service::MaterialLoad);
  m.add_requester(Service::MaterialUnload);
  const TimePoint t{};
  for (auto s : {Service::MaterialLoad, Service::MaterialUnload}) {
    m.requester(s)->on_counterpart(S::Ready, t);
  }
  m.requester(Service::MaterialLoad)->request(t);
  m.requester(Service::MaterialUnload)->request(t + 500ms);
  EXPECT_EQ(m.next_deadline(), t + 1s);
  EXPECT_TRUE(m.on_tick(t + 900ms).empty());
  const auto batch = m.on_tick(t + 2s);
  ASSERT_EQ(batch.size(), 2u);
  for (const auto& r : batch) EXPECT_EQ(r.reason, R::ResponseTimeout);
  EXPECT_EQ(m.next_deadline(), kNever);
}

// 1.3 section 3.3: OPEN_DOOR is NOT_READY while the door is OPEN.
TEST(DoorHook, OpenDoorNotReadyWhileOpenCloseDoorNotReadyWhileClosed) {
  DoorChuckPreconditions door(DoorState::Closed, ChuckState::Unavailable);
  InterfaceModel m(InterfaceType::Door, MachineOptions{}, &door);
  m.add_responder(Service::OpenDoor);
  m.add_responder(Service::CloseDoor);
  const TimePoint t{};
  EXPECT_EQ(m.responder(Service::OpenDoor)->state(), S::Ready);
  EXPECT_EQ(m.responder(Service::CloseDoor)->state(), S::NotReady);
  door.set_door_state(DoorState::Open);
  m.reevaluate(t);
  EXPECT_EQ(m.responder(Service::OpenDoor)->state(), S::NotReady);
  EXPECT_EQ(m.responder(Service::CloseDoor)->state(), S::Ready);
  door.set_door_state(DoorState::Unlatched);
  m.reevaluate(t);
  EXPECT_EQ(m.responder(Service::OpenDoor)->state(), S::Ready);
  EXPECT_EQ(m.responder(Service::CloseDoor)->state(), S::Ready);
  door.set_door_state(DoorState::Unavailable);
  m.reevaluate(t);
  EXPECT_EQ(m.responder(Service::OpenDoor)->state(), S::NotReady) << "unknown door never moves";
  EXPECT_EQ(m.responder(Service::CloseDoor)->state(), S::NotReady);
}

TEST(DoorHook, OpenDoorServiceEndsNotReadyBecauseTheDoorIsNowOpen) {
  DoorChuckPreconditions door(DoorState::Closed, ChuckState::Unavailable);
  Responder machine_door(Service::OpenDoor, MachineOptions{}, &door);
  Requester robot(Service::OpenDoor);
  const TimePoint t{};
  robot.on_counterpart(machine_door.state(), t);
  machine_door.on_counterpart(robot.state(), t);
  robot.request(t);
  machine_door.on_counterpart(robot.state(), t);
  EXPECT_EQ(machine_door.accept(t).current, S::Active);
  robot.on_counterpart(machine_door.state(), t);
  door.set_door_state(DoorState::Open);  // the door moves while ACTIVE
  EXPECT_EQ(machine_door.reevaluate(t).current, S::Active) << "not consulted while ACTIVE";
  machine_door.complete(t);
  robot.on_counterpart(machine_door.state(), t);
  const auto ack = machine_door.on_counterpart(robot.state(), t);
  EXPECT_EQ(ack.notice, N::Acknowledged);
  EXPECT_EQ(ack.current, S::NotReady) << "cannot open a door that is already open";
}

TEST(DoorHook, AcceptRefusedWhenPreconditionFails) {
  DoorChuckPreconditions chuck(DoorState::Unavailable, ChuckState::Closed);
  Responder close_chuck(Service::CloseChuck, MachineOptions{}, &chuck);
  const TimePoint t{};
  EXPECT_EQ(close_chuck.state(), S::NotReady);
  EXPECT_EQ(close_chuck.set_ready(t).reason, R::PreconditionNotMet);
  chuck.set_chuck_state(ChuckState::Open);
  EXPECT_EQ(close_chuck.reevaluate(t).current, S::Ready);
  close_chuck.on_counterpart(S::Active, t);
  chuck.set_chuck_state(ChuckState::Closed);  // changed, not yet re-evaluated
  EXPECT_EQ(close_chuck.accept(t).reason, R::PreconditionNotMet);
}

TEST(DoorHook, RulesMatchTheText) {
  EXPECT_FALSE(door_permits(Service::OpenDoor, DoorState::Open));
  EXPECT_TRUE(door_permits(Service::OpenDoor, DoorState::Closed));
  EXPECT_FALSE(door_permits(Service::CloseDoor, DoorState::Closed));
  EXPECT_TRUE(door_permits(Service::MaterialLoad, DoorState::Unavailable));
  EXPECT_FALSE(chuck_permits(Service::OpenChuck, ChuckState::Open));
  EXPECT_FALSE(chuck_permits(Service::CloseChuck, ChuckState::Closed));
  DoorChuckPreconditions hook(DoorState::Open, ChuckState::Open);
  EXPECT_TRUE(hook.permits(Service::OpenDoor, Role::Requester)) << "only the controlling side";
  EXPECT_FALSE(hook.permits(Service::OpenDoor, Role::Responder));
}

TEST(Commands, RecoverToAnythingButReadyOrNotReadyIsRejected) {
  Pair p;
  p.requester.fail(p.now);
  p.to_responder();
  p.to_requester();
  for (auto target : {S::Active, S::Complete, S::Fail, S::Unavailable}) {
    const auto r = p.requester.recover(target, p.now);
    EXPECT_TRUE(r.rejected());
    EXPECT_EQ(r.reason, R::InvalidTarget);
  }
  EXPECT_EQ(p.requester.state(), S::Fail);
}

TEST(Commands, GarbageEventsAndValuesNeverCrash) {
  Pair p;
  const auto r = p.requester.step(static_cast<Event>(200), p.now);
  EXPECT_TRUE(r.rejected());
  const auto v = p.responder.on_counterpart(static_cast<S>(77), p.now);
  EXPECT_TRUE(v.violation());
  EXPECT_EQ(v.reason, R::UnknownValue);
  const auto t = p.requester.on_counterpart_text("BANANA", p.now);
  EXPECT_TRUE(t.violation());
}

}  // namespace
}  // namespace mtc::core::testing_support
