// The machine tool: each cycle requests MATERIAL_FEED from the feeder, then
// MATERIAL_LOAD and MATERIAL_UNLOAD from the robot, machining in between; its
// door and chuck units serve OPEN/CLOSE_DOOR and OPEN/CLOSE_CHUCK on threads
// of their own and publish DOOR_STATE / CHUCK_STATE.
#include <atomic>
#include <thread>

#include "console.hpp"
#include "station_script.hpp"

namespace mtc::cell::script {
namespace {

// A step that has not completed this long after its first attempt stops the
// cell: a real fault, not a passing one. Time rather than a count of
// attempts, because a burst of loss-of-communication alarms under load can
// fail many quick attempts in a row (see README "Simulated cell").
constexpr std::chrono::seconds kGiveUpAfter{60};

struct MachineStats {
  int cycles = 0;
  int handshakes = 0;
  int failures = 0;
  int injected = 0;  // failures the fault plan explains
  int other = 0;     // any other: a false alarm, a timeout, a lost peer
  int recovered = 0;
  int explained_cycle = 0;  // the last cycle whose planned fault was counted
};

// Counts a failed step as injected when the cycle's planned fault fails this
// step and has not been counted yet (each fault fires once), else as other.
void count_failure(const Station& c, int cycle, Service s, MachineStats& st) {
  ++st.failures;
  const auto due = c.plan.at(cycle);
  if (due && machine_step_failed_by(due->point) == s && st.explained_cycle != cycle) {
    st.explained_cycle = cycle;
    ++st.injected;
  } else {
    ++st.other;
  }
}

// One step of the machine's cycle; retried after a recovered failure.
bool machine_step(Station& c, int cycle, Service s, MachineStats& st) {
  const char* responder = s == Service::MaterialFeed ? "feeder" : "robot";
  const auto give_up = Clock::now() + kGiveUpAfter;
  for (int attempt = 1; Clock::now() < give_up && !c.stop.stopped(); ++attempt) {
    std::optional<Fault> fault;
    const auto due = c.plan.at(cycle);
    if (due && due->party == StationId::Machine && due->service == s &&
        c.take_fault(cycle, due->point)) {
      fault = due;
    }
    const Outcome out = request_service(c, s, responder, "", fault);
    if (out == Outcome::Completed) {
      ++st.handshakes;
      return true;
    }
    if (c.stop.stopped()) {
      return false;
    }
    count_failure(c, cycle, s, st);
    if (!recover_request(c, s, "")) {
      return false;
    }
    ++st.recovered;
    c.say(format("%s: retrying (attempt %d)", service_name(s).c_str(), attempt + 1));
  }
  return false;
}

bool machine_cycle(Station& c, int cycle, MachineStats& st) {
  const auto t0 = Clock::now();
  c.say(format("=== cycle %d begins", cycle));
  if (!machine_step(c, cycle, Service::MaterialFeed, st)) {
    return false;
  }
  if (!machine_step(c, cycle, Service::MaterialLoad, st)) {
    return false;
  }
  c.say(format("machining part %d (door CLOSED, chuck CLOSED)", cycle));
  if (!c.stop.sleep_for(c.options.pace * 4)) {
    return false;
  }
  if (!machine_step(c, cycle, Service::MaterialUnload, st)) {
    return false;
  }
  ++st.cycles;
  c.say(format("=== cycle %d complete in %.2f s", cycle, ms_since(t0) / 1000.0));
  return true;
}

// Door or chuck: the machine's responder unit for one open/close pair.
struct Actuator {
  Service open;
  Service close;
  const char* item;  // DOOR_STATE or CHUCK_STATE
  void (*publish)(Link&, bool open, bool moving);
};

void publish_door(Link& l, bool open, bool moving) {
  l.set_door(moving ? core::DoorState::Unlatched
                    : (open ? core::DoorState::Open : core::DoorState::Closed));
}

void publish_chuck(Link& l, bool open, bool moving) {
  l.set_chuck(moving ? core::ChuckState::Unlatched
                     : (open ? core::ChuckState::Open : core::ChuckState::Closed));
}

void actuator_job(Station& c, const Actuator& a, Service job, int cycle, bool& is_open) {
  ResponsePort& port = c.link.responder(job);
  const bool want_open = job == a.open;
  if (!port.accept()) {
    return;
  }
  c.say(format("  %-15s ACTIVE, %s %s", service_name(job).c_str(), a.item,
               is_open == want_open ? "already there" : "UNLATCHED"));
  if (job == Service::OpenDoor && !is_open && c.take_fault(cycle, FaultPoint::DoorJams)) {
    a.publish(c.link, is_open, true);
    c.stop.sleep_for(c.options.pace / 2);
    announce_fault(c, "  ", describe(FaultPoint::DoorJams, cycle));
    port.fail();
    recover_response(c, job, "  ");
    // The door is freed by hand: back to CLOSED, ready for the next request.
    a.publish(c.link, is_open, false);
    return;
  }
  if (is_open != want_open) {
    a.publish(c.link, is_open, true);
    if (!c.stop.sleep_for(c.options.pace)) {
      return;
    }
    is_open = want_open;
    a.publish(c.link, is_open, false);
  }
  if (port.cancelled()) {
    c.say(format("  %-15s request withdrawn, response FAIL", service_name(job).c_str()));
    recover_response(c, job, "  ");
    return;
  }
  // Logged first: once published, the robot's reaction may print before us.
  c.say(format("  %-15s COMPLETE, %s %s", service_name(job).c_str(), a.item,
               is_open ? "OPEN" : "CLOSED"));
  finish_job(c, port, job, "  ");
}

void run_actuator(Station& c, const Actuator& a, const std::atomic<int>& cycle_now,
                  const std::atomic<bool>& done) {
  bool is_open = false;
  a.publish(c.link, is_open, false);
  while (!c.stop.stopped() && !done.load()) {
    const auto job = c.link.wait_job({a.open, a.close}, kPoll);
    if (job) {
      actuator_job(c, a, *job, cycle_now.load(), is_open);
    } else {
      recover_idle(c, {a.open, a.close}, "  ");
    }
  }
}

}  // namespace

int run_machine(Station& c) {
  std::atomic<int> cycle_now{0};
  std::atomic<bool> done{false};
  // Door and chuck are their own control units (a PLC's job on a real
  // machine): they answer the robot while the cycle waits on the robot.
  Station door_unit{c.id, c.link, c.options, c.stop, c.plan, {}};
  Station chuck_unit{c.id, c.link, c.options, c.stop, c.plan, {}};
  std::thread door([&] {
    run_actuator(door_unit, {Service::OpenDoor, Service::CloseDoor, "DOOR_STATE", publish_door},
                 cycle_now, done);
  });
  std::thread chuck([&] {
    run_actuator(chuck_unit,
                 {Service::OpenChuck, Service::CloseChuck, "CHUCK_STATE", publish_chuck}, cycle_now,
                 done);
  });
  MachineStats st;
  bool ok = true;
  for (int cycle = 1;
       ok && !c.stop.stopped() && (c.options.cycles == 0 || cycle <= c.options.cycles); ++cycle) {
    cycle_now.store(cycle);
    ok = machine_cycle(c, cycle, st) || c.stop.stopped();
  }
  done.store(true);
  door.join();
  chuck.join();
  // Read by scripts (apps/cell/test_cell.sh, benchmarks/endurance): keep the
  // wording of the counts.
  c.say(
      format("cell summary: %d cycles complete, %d handshakes by the machine, %d failures "
             "(%d injected, %d other), %d recovered%s",
             st.cycles, st.handshakes, st.failures, st.injected, st.other, st.recovered,
             ok ? "" : " -- STOPPED ON AN UNRECOVERED FAILURE"));
  return ok ? 0 : 1;
}

}  // namespace mtc::cell::script
