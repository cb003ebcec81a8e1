#include "stations.hpp"

#include <chrono>
#include <functional>
#include <set>
#include <string>
#include <thread>
#include <utility>

#include "console.hpp"

namespace mtc::cell {

void Stopper::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopped_ = true;
  }
  cv_.notify_all();
}

bool Stopper::stopped() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stopped_;
}

bool Stopper::sleep_for(Millis d) {
  std::unique_lock<std::mutex> lock(mutex_);
  return !cv_.wait_for(lock, d, [this] { return stopped_; });
}

namespace {

using core::Service;
using Clock = std::chrono::steady_clock;

constexpr Millis kPoll{100};  // how often an idle unit re-checks for stop
// A step that has not completed this long after its first attempt stops the
// cell: a real fault, not a passing one. Time rather than a count of
// attempts, because a burst of loss-of-communication alarms under load can
// fail many quick attempts in a row (see README "Simulated cell").
constexpr std::chrono::seconds kGiveUpAfter{60};

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

std::string name(Service s) {
  return std::string(core::to_string(s));
}

struct Ctx {
  StationId id;
  Link& link;
  const CellOptions& options;
  Stopper& stop;
  FaultPlan plan;
  std::set<std::pair<int, FaultPoint>> injected;  // each fault fires once

  void say(const std::string& text) const { print_line(to_string(id), text); }

  // True (once) when `point` is due in `cycle`.
  bool take_fault(int cycle, FaultPoint point) {
    return plan.hits(cycle, point) && injected.insert({cycle, point}).second;
  }
};

// Runs a blocking port call in slices of kPoll until it succeeds, `total`
// has passed or the station is stopped, so Ctrl-C never waits on a timeout.
// `abandon` (may be empty) ends the wait early too: the robot gives up a
// door/chuck request once its own load/unload has been aborted.
using Abandon = std::function<bool()>;

template <class Step>
bool in_slices(const Ctx& c, Millis total, Step step, const Abandon& abandon = {}) {
  const auto deadline = Clock::now() + total;
  while (!c.stop.stopped() && !(abandon && abandon())) {
    if (step(kPoll)) {
      return true;
    }
    if (Clock::now() >= deadline) {
      return false;
    }
  }
  return false;
}

void announce_fault(Ctx& c, const std::string& indent, const Fault& f) {
  c.say(format("%s!! %s: injected failure, scenario %d (%.*s)", indent.c_str(),
               name(f.service).c_str(), f.scenario, static_cast<int>(f.what.size()),
               f.what.data()));
}

// Requester side of one handshake, from raising the request to its end,
// with the requester's own fault (scenario 3 or 4) injected when given.
Outcome request_service(Ctx& c, Service s, const char* responder, const std::string& indent,
                        const std::optional<Fault>& fault, const Abandon& abandon = {}) {
  RequestPort& port = c.link.requester(s);
  const auto t0 = Clock::now();
  if (!in_slices(
          c, c.options.handshake_timeout, [&](Millis m) { return port.raise(m); }, abandon)) {
    if (!c.stop.stopped() && !(abandon && abandon())) {
      c.say(format("%s%s: could not raise the request (%s not READY: %s)", indent.c_str(),
                   name(s).c_str(), responder, port.states().c_str()));
    }
    return Outcome::TimedOut;
  }
  c.say(format("%s%-15s request ACTIVE -> %s", indent.c_str(), name(s).c_str(), responder));
  if (fault &&
      in_slices(c, c.options.handshake_timeout, [&](Millis m) { return port.wait_engaged(m); })) {
    c.stop.sleep_for(c.options.pace / 2);
    announce_fault(c, indent, *fault);
    port.fail();
  }
  Outcome out = Outcome::TimedOut;
  in_slices(c, c.options.handshake_timeout, [&](Millis m) {
    out = port.wait_outcome(m);
    return out != Outcome::TimedOut;
  });
  if (c.stop.stopped()) {
    return out;
  }
  if (out == Outcome::Completed) {
    c.say(format("%s%-15s done in %.1f ms, both READY", indent.c_str(), name(s).c_str(),
                 ms_since(t0)));
  } else {
    c.say(format("%s%-15s %s after %.1f ms", indent.c_str(), name(s).c_str(),
                 out == Outcome::Failed ? "FAILED (both sides FAIL)" : "TIMED OUT", ms_since(t0)));
  }
  return out;
}

bool recover_request(Ctx& c, Service s, const std::string& indent) {
  RequestPort& port = c.link.requester(s);
  if (in_slices(c, c.options.handshake_timeout, [&](Millis m) { return port.recover(m); })) {
    c.say(format("%s%-15s request recovered: FAIL -> READY", indent.c_str(), name(s).c_str()));
    return true;
  }
  if (!c.stop.stopped()) {
    c.say(format("%s%-15s request could not recover", indent.c_str(), name(s).c_str()));
  }
  return false;
}

bool recover_response(Ctx& c, Service s, const std::string& indent) {
  ResponsePort& port = c.link.responder(s);
  if (in_slices(c, c.options.handshake_timeout, [&](Millis m) { return port.recover(m); })) {
    c.say(format("%s%-15s response recovered -> READY", indent.c_str(), name(s).c_str()));
    return true;
  }
  if (!c.stop.stopped()) {
    c.say(format("%s%-15s response could not recover", indent.c_str(), name(s).c_str()));
  }
  return false;
}

// complete() and then the requester's acknowledgement (steps 4-8). A
// requester that fails or is lost before acknowledging leaves the response
// FAIL, which must be recovered like any other failure. True when acked.
bool finish_job(Ctx& c, ResponsePort& port, Service s, const std::string& indent) {
  if (!port.complete()) {
    recover_response(c, s, indent);
    return false;
  }
  Outcome out = Outcome::TimedOut;
  in_slices(c, c.options.handshake_timeout, [&](Millis m) {
    out = port.wait_settled(m);
    return out != Outcome::TimedOut;
  });
  if (out == Outcome::Completed || c.stop.stopped()) {
    return out == Outcome::Completed;
  }
  c.say(
      format("%s%-15s response FAIL after COMPLETE (requester failed or lost before its "
             "acknowledgement)",
             indent.c_str(), name(s).c_str()));
  recover_response(c, s, indent);
  return false;
}

// An idle unit's responses can still be failed by a loss of communication
// or a late counterpart FAIL: clear them so the next request finds READY.
void recover_idle(Ctx& c, std::initializer_list<Service> services, const std::string& indent) {
  for (Service s : services) {
    if (c.link.responder(s).failed()) {
      c.say(
          format("%s%-15s response FAIL while idle: recovering", indent.c_str(), name(s).c_str()));
      recover_response(c, s, indent);
    }
  }
}

// ---------------------------------------------------------------- machine

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
void count_failure(const Ctx& c, int cycle, Service s, MachineStats& st) {
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
bool machine_step(Ctx& c, int cycle, Service s, MachineStats& st) {
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
    c.say(format("%s: retrying (attempt %d)", name(s).c_str(), attempt + 1));
  }
  return false;
}

bool machine_cycle(Ctx& c, int cycle, MachineStats& st) {
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

void actuator_job(Ctx& c, const Actuator& a, Service job, int cycle, bool& is_open) {
  ResponsePort& port = c.link.responder(job);
  const bool want_open = job == a.open;
  if (!port.accept()) {
    return;
  }
  c.say(format("  %-15s ACTIVE, %s %s", name(job).c_str(), a.item,
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
    c.say(format("  %-15s request withdrawn, response FAIL", name(job).c_str()));
    recover_response(c, job, "  ");
    return;
  }
  // Logged first: once published, the robot's reaction may print before us.
  c.say(format("  %-15s COMPLETE, %s %s", name(job).c_str(), a.item, is_open ? "OPEN" : "CLOSED"));
  finish_job(c, port, job, "  ");
}

void run_actuator(Ctx& c, const Actuator& a, const std::atomic<int>& cycle_now,
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

int run_machine(Ctx& c) {
  std::atomic<int> cycle_now{0};
  std::atomic<bool> done{false};
  // Door and chuck are their own control units (a PLC's job on a real
  // machine): they answer the robot while the cycle waits on the robot.
  Ctx door_ctx{c.id, c.link, c.options, c.stop, c.plan, {}};
  Ctx chuck_ctx{c.id, c.link, c.options, c.stop, c.plan, {}};
  std::thread door([&] {
    run_actuator(door_ctx, {Service::OpenDoor, Service::CloseDoor, "DOOR_STATE", publish_door},
                 cycle_now, done);
  });
  std::thread chuck([&] {
    run_actuator(chuck_ctx, {Service::OpenChuck, Service::CloseChuck, "CHUCK_STATE", publish_chuck},
                 cycle_now, done);
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

// ------------------------------------------------------------------ robot

enum class JobEnd : std::uint8_t { Done, Aborted, Stopped };

JobEnd robot_job(Ctx& c, ResponsePort& port, bool load, int cycle) {
  const Service steps[] = {Service::OpenDoor, Service::OpenChuck, Service::CloseChuck,
                           Service::CloseDoor};
  for (std::size_t i = 0; i < 4; ++i) {
    if (c.stop.stopped()) {
      return JobEnd::Stopped;
    }
    if (port.cancelled()) {
      c.say("  the machine left ACTIVE: job aborted, response FAIL");
      return JobEnd::Aborted;
    }
    if (i == 2) {
      c.say(load ? "  placing the blank in the chuck" : "  gripping the finished part");
      if (load && c.take_fault(cycle, FaultPoint::RobotDropsPartOnLoad)) {
        announce_fault(c, "", describe(FaultPoint::RobotDropsPartOnLoad, cycle));
        port.fail();
        return JobEnd::Aborted;
      }
      if (!c.stop.sleep_for(c.options.pace * 2)) {
        return JobEnd::Stopped;
      }
    }
    if (c.link.holds(steps[i])) {
      c.say(format("  %-15s skipped: already done", name(steps[i]).c_str()));
      continue;
    }
    std::optional<Fault> fault;
    if (load && steps[i] == Service::OpenChuck &&
        c.take_fault(cycle, FaultPoint::RobotCollisionAtChuck)) {
      fault = describe(FaultPoint::RobotCollisionAtChuck, cycle);
    }
    const Abandon aborted = [&port] { return port.cancelled(); };
    if (request_service(c, steps[i], "machine", "  ", fault, aborted) != Outcome::Completed) {
      if (c.stop.stopped()) {
        return JobEnd::Stopped;
      }
      recover_request(c, steps[i], "  ");
      if (port.cancelled()) {
        c.say("  the machine left ACTIVE (or was lost): job aborted");
        return JobEnd::Aborted;
      }
      c.say(format("%s cannot go on: response FAIL (scenario 2)", load ? "load" : "unload"));
      port.fail();
      return JobEnd::Aborted;
    }
  }
  return JobEnd::Done;
}

int run_robot(Ctx& c) {
  int done[2] = {0, 0};  // completed loads, unloads: the cycle each job belongs to
  while (!c.stop.stopped()) {
    const auto job = c.link.wait_job({Service::MaterialLoad, Service::MaterialUnload}, kPoll);
    if (!job) {
      recover_idle(c, {Service::MaterialLoad, Service::MaterialUnload}, "");
      continue;
    }
    const bool load = *job == Service::MaterialLoad;
    ResponsePort& port = c.link.responder(*job);
    if (!port.accept()) {
      continue;
    }
    c.say(format("%-15s ACTIVE: %s", name(*job).c_str(),
                 load ? "loading a blank" : "unloading the finished part"));
    const JobEnd end = robot_job(c, port, load, done[load ? 0 : 1] + 1);
    if (end == JobEnd::Stopped) {
      break;
    }
    if (end == JobEnd::Done) {
      c.say(format("%-15s COMPLETE", name(*job).c_str()));
      // Counted once acknowledged: a load the machine failed is retried.
      if (finish_job(c, port, *job, "")) {
        ++done[load ? 0 : 1];
      }
      continue;
    }
    recover_response(c, *job, "");
  }
  return 0;
}

// ----------------------------------------------------------------- feeder

int run_feeder(Ctx& c) {
  int feeds = 0;
  while (!c.stop.stopped()) {
    const auto job = c.link.wait_job({Service::MaterialFeed}, kPoll);
    if (!job) {
      recover_idle(c, {Service::MaterialFeed}, "");
      continue;
    }
    ResponsePort& port = c.link.responder(*job);
    if (c.take_fault(feeds + 1, FaultPoint::FeederRefusesFeed)) {
      announce_fault(c, "", describe(FaultPoint::FeederRefusesFeed, feeds + 1));
      port.fail();
      recover_response(c, *job, "");
      continue;
    }
    if (!port.accept()) {
      continue;
    }
    c.say("MATERIAL_FEED   ACTIVE: advancing bar stock to the pick position");
    if (!c.stop.sleep_for(c.options.pace * 2)) {
      break;
    }
    if (!port.cancelled()) {
      c.say("MATERIAL_FEED   COMPLETE");
      if (finish_job(c, port, *job, "")) {
        ++feeds;
      }
      continue;
    }
    recover_response(c, *job, "");
  }
  return 0;
}

}  // namespace

int run_station(StationId id, Link& link, const CellOptions& options, Stopper& stop) {
  Ctx c{id, link, options, stop, FaultPlan(options.seed, options.fail_every), {}};
  switch (id) {
    case StationId::Machine:
      return run_machine(c);
    case StationId::Robot:
      return run_robot(c);
    case StationId::Feeder:
      return run_feeder(c);
  }
  return 2;
}

}  // namespace mtc::cell
