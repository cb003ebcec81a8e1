// What the three station scripts (machine_station.cpp, robot_station.cpp,
// feeder_station.cpp) share: the station's context, blocking port calls cut
// into stop-aware slices, and the requester and responder halves of a
// handshake with their recoveries, each logged the same way.
#pragma once

#include <chrono>
#include <functional>
#include <initializer_list>
#include <optional>
#include <set>
#include <string>
#include <utility>

#include "cell_plan.hpp"
#include "ports.hpp"
#include "stations.hpp"

namespace mtc::cell::script {

using core::Service;
using Clock = std::chrono::steady_clock;

constexpr Millis kPoll{100};  // how often an idle unit re-checks for stop

double ms_since(Clock::time_point t0);
std::string service_name(Service s);

// One station (or one of the machine's door/chuck units) at work: its
// link, options, stop request and the faults it has injected so far.
struct Station {
  StationId id;
  Link& link;
  const CellOptions& options;
  Stopper& stop;
  FaultPlan plan;
  std::set<std::pair<int, FaultPoint>> injected;  // each fault fires once

  void say(const std::string& text) const;

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
bool in_slices(const Station& c, Millis total, Step step, const Abandon& abandon = {}) {
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

void announce_fault(Station& c, const std::string& indent, const Fault& f);

// Requester side of one handshake, from raising the request to its end,
// with the requester's own fault (scenario 3 or 4) injected when given.
// `done` (may be empty) says that what the request asks for already holds.
// It is checked while waiting for the responder to be READY, because a
// door/chuck responder never becomes READY then: it is NOT_READY (1.3
// section 3.3) once the door or chuck got there, e.g. a chuck still opening
// for a request the robot had withdrawn. Outcome::NotNeeded: not raised.
Outcome request_service(Station& c, Service s, const char* responder, const std::string& indent,
                        const std::optional<Fault>& fault, const Abandon& abandon = {},
                        const Abandon& done = {});

bool recover_request(Station& c, Service s, const std::string& indent);
bool recover_response(Station& c, Service s, const std::string& indent);

// complete() and then the requester's acknowledgement (steps 4-8). A
// requester that fails or is lost before acknowledging leaves the response
// FAIL, which must be recovered like any other failure. True when acked.
bool finish_job(Station& c, ResponsePort& port, Service s, const std::string& indent);

// An idle unit's responses can still be failed by a loss of communication
// or a late counterpart FAIL: clear them so the next request finds READY.
void recover_idle(Station& c, std::initializer_list<Service> services, const std::string& indent);

// The station scripts; each returns the station's exit code.
int run_machine(Station& c);
int run_robot(Station& c);
int run_feeder(Station& c);

}  // namespace mtc::cell::script
