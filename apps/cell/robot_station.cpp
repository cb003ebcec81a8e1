// The robot: serves MATERIAL_LOAD and MATERIAL_UNLOAD, requesting the
// machine's door and chuck while it works; a job the machine abandons, or a
// door/chuck step that fails, ends the job in FAIL.
#include <cstdint>

#include "console.hpp"
#include "station_script.hpp"

namespace mtc::cell::script {
namespace {

enum class JobEnd : std::uint8_t { Done, Aborted, Stopped };

JobEnd robot_job(Station& c, ResponsePort& port, bool load, int cycle) {
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
    // Checked again while the request waits for READY: a door/chuck still
    // moving for a request withdrawn before (scenario 3 at the chuck) gets
    // there meanwhile, and its responder then stays NOT_READY.
    const Service step = steps[i];
    const Abandon done = [&c, step] { return c.link.holds(step); };
    if (done()) {
      c.say(format("  %-15s skipped: already done", service_name(step).c_str()));
      continue;
    }
    std::optional<Fault> fault;
    if (load && step == Service::OpenChuck &&
        c.take_fault(cycle, FaultPoint::RobotCollisionAtChuck)) {
      fault = describe(FaultPoint::RobotCollisionAtChuck, cycle);
    }
    const Abandon aborted = [&port] { return port.cancelled(); };
    const Outcome out = request_service(c, step, "machine", "  ", fault, aborted, done);
    if (out == Outcome::NotNeeded) {
      c.say(format("  %-15s skipped: already done (got there while waiting)",
                   service_name(step).c_str()));
      continue;
    }
    if (out != Outcome::Completed) {
      if (c.stop.stopped()) {
        return JobEnd::Stopped;
      }
      recover_request(c, step, "  ");
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

}  // namespace

int run_robot(Station& c) {
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
    c.say(format("%-15s ACTIVE: %s", service_name(*job).c_str(),
                 load ? "loading a blank" : "unloading the finished part"));
    const JobEnd end = robot_job(c, port, load, done[load ? 0 : 1] + 1);
    if (end == JobEnd::Stopped) {
      break;
    }
    if (end == JobEnd::Done) {
      c.say(format("%-15s COMPLETE", service_name(*job).c_str()));
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

}  // namespace mtc::cell::script
