// The handshake halves and recoveries every station script uses.
#include "station_script.hpp"

#include "console.hpp"

namespace mtc::cell::script {

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

std::string service_name(Service s) {
  return std::string(core::to_string(s));
}

void Station::say(const std::string& text) const {
  print_line(to_string(id), text);
}

void announce_fault(Station& c, const std::string& indent, const Fault& f) {
  c.say(format("%s!! %s: injected failure, scenario %d (%.*s)", indent.c_str(),
               service_name(f.service).c_str(), f.scenario, static_cast<int>(f.what.size()),
               f.what.data()));
}

Outcome request_service(Station& c, Service s, const char* responder, const std::string& indent,
                        const std::optional<Fault>& fault, const Abandon& abandon,
                        const Abandon& done) {
  RequestPort& port = c.link.requester(s);
  const auto t0 = Clock::now();
  const Abandon give_up = [&] { return (abandon && abandon()) || (done && done()); };
  if (!in_slices(
          c, c.options.handshake_timeout, [&](Millis m) { return port.raise(m); }, give_up)) {
    if (!c.stop.stopped() && done && done()) {
      return Outcome::NotNeeded;  // raise() false: nothing was changed
    }
    if (!c.stop.stopped() && !(abandon && abandon())) {
      c.say(format("%s%s: could not raise the request (%s not READY: %s)", indent.c_str(),
                   service_name(s).c_str(), responder, port.states().c_str()));
    }
    return Outcome::TimedOut;
  }
  c.say(format("%s%-15s request ACTIVE -> %s", indent.c_str(), service_name(s).c_str(), responder));
  if (fault &&
      in_slices(c, c.options.handshake_timeout, [&](Millis m) { return port.wait_engaged(m); })) {
    c.stop.sleep_for(c.options.pace / 2);
    announce_fault(c, indent, *fault);
    // The responder's motion may have ended first (a slow wake-up on a
    // loaded machine): then nothing failed, and the log must say so.
    if (!port.fail()) {
      c.say(format("%s%-15s injected failure too late: the handshake had already ended",
                   indent.c_str(), service_name(s).c_str()));
    }
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
    c.say(format("%s%-15s done in %.1f ms, both READY", indent.c_str(), service_name(s).c_str(),
                 ms_since(t0)));
  } else {
    const auto why = port.why_failed();
    c.say(format("%s%-15s %s after %.1f ms%s%s", indent.c_str(), service_name(s).c_str(),
                 out == Outcome::Failed ? "FAILED (both sides FAIL)" : "TIMED OUT", ms_since(t0),
                 why.empty() ? "" : ": ", why.c_str()));
  }
  return out;
}

bool recover_request(Station& c, Service s, const std::string& indent) {
  RequestPort& port = c.link.requester(s);
  if (in_slices(c, c.options.handshake_timeout, [&](Millis m) { return port.recover(m); })) {
    c.say(format("%s%-15s request recovered: FAIL -> READY", indent.c_str(),
                 service_name(s).c_str()));
    return true;
  }
  if (!c.stop.stopped()) {
    c.say(format("%s%-15s request could not recover", indent.c_str(), service_name(s).c_str()));
  }
  return false;
}

bool recover_response(Station& c, Service s, const std::string& indent) {
  ResponsePort& port = c.link.responder(s);
  if (in_slices(c, c.options.handshake_timeout, [&](Millis m) { return port.recover(m); })) {
    // NOT_READY, not READY, after a door/chuck job that got there anyway.
    c.say(format("%s%-15s response recovered -> %s", indent.c_str(), service_name(s).c_str(),
                 std::string(core::to_string(port.state())).c_str()));
    return true;
  }
  if (!c.stop.stopped()) {
    c.say(format("%s%-15s response could not recover", indent.c_str(), service_name(s).c_str()));
  }
  return false;
}

bool finish_job(Station& c, ResponsePort& port, Service s, const std::string& indent) {
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
             indent.c_str(), service_name(s).c_str()));
  recover_response(c, s, indent);
  return false;
}

void recover_idle(Station& c, std::initializer_list<Service> services, const std::string& indent) {
  for (Service s : services) {
    if (c.link.responder(s).failed()) {
      c.say(format("%s%-15s response FAIL while idle: recovering", indent.c_str(),
                   service_name(s).c_str()));
      recover_response(c, s, indent);
    }
  }
}

}  // namespace mtc::cell::script
