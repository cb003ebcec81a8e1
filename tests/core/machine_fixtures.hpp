// Helpers shared by the core tests: bring a machine into a given state
// through its public API only, and print results readably on failure.
#pragma once

#include <ostream>
#include <string>

#include "mtc/core/requester.hpp"
#include "mtc/core/responder.hpp"

namespace mtc::core {

inline std::ostream& operator<<(std::ostream& os, InteractionState s) {
  return os << to_string(s);
}
inline std::ostream& operator<<(std::ostream& os, Notice n) {
  return os << to_string(n);
}
inline std::ostream& operator<<(std::ostream& os, Reason r) {
  return os << to_string(r);
}
inline std::ostream& operator<<(std::ostream& os, Event e) {
  return os << to_string(e);
}
inline std::ostream& operator<<(std::ostream& os, Phase p) {
  return os << to_string(p);
}

namespace testing_support {

inline MachineOptions options_for(Profile p) {
  MachineOptions o;
  o.profile = p;
  return o;
}

inline const TimePoint kT0{};

// Name suffix of profile-parameterised tests.
template <typename ParamInfo>
std::string profile_name(const ParamInfo& param_info) {
  return param_info.param == Profile::V1_3 ? "V1_3" : "V1_6";
}

// The starting points of the exhaustive table tests. Each names the phase and
// the context that matters for the guards.
enum class Setup {
  Ready,          // READY, counterpart READY
  NotReady,       // NOT_READY by application wish, counterpart READY
  Active,         // requester ACTIVE, response still READY (not engaged)
  ActiveEngaged,  // requester ACTIVE, response ACTIVE; responder: ACTIVE, request ACTIVE
  ResponderReadyRequestActive,  // responder READY, request ACTIVE
  Complete,                     // responder COMPLETE, request ACTIVE
  Fail,                         // FAIL by own failure, counterpart READY
  FailAcknowledged,             // FAIL, counterpart FAIL
  Disabled,                     // DISABLED, counterpart READY
  DisabledFailPending,          // DISABLED, counterpart went FAIL meanwhile
};

inline const char* setup_name(Setup s) {
  switch (s) {
    case Setup::Ready:
      return "Ready";
    case Setup::NotReady:
      return "NotReady";
    case Setup::Active:
      return "Active";
    case Setup::ActiveEngaged:
      return "ActiveEngaged";
    case Setup::ResponderReadyRequestActive:
      return "ReadyRequestActive";
    case Setup::Complete:
      return "Complete";
    case Setup::Fail:
      return "Fail";
    case Setup::FailAcknowledged:
      return "FailAcknowledged";
    case Setup::Disabled:
      return "Disabled";
    case Setup::DisabledFailPending:
      return "DisabledFailPending";
  }
  return "?";
}

inline Requester requester_in(Setup s, Profile p) {
  Requester m(Service::MaterialLoad, options_for(p));
  m.on_counterpart(InteractionState::Ready, kT0);
  switch (s) {
    case Setup::Ready:
      break;
    case Setup::NotReady:
      m.set_not_ready(kT0);
      break;
    case Setup::Active:
      m.request(kT0);
      break;
    case Setup::ActiveEngaged:
      m.request(kT0);
      m.on_counterpart(InteractionState::Active, kT0);
      break;
    case Setup::Fail:
      m.fail(kT0);
      break;
    case Setup::FailAcknowledged:
      m.fail(kT0);
      m.on_counterpart(InteractionState::Fail, kT0);
      break;
    case Setup::Disabled:
      m.disable(kT0);
      break;
    case Setup::DisabledFailPending:
      m.disable(kT0);
      m.on_counterpart(InteractionState::Fail, kT0);
      break;
    case Setup::ResponderReadyRequestActive:
    case Setup::Complete:
      break;
  }
  return m;
}

inline Responder responder_in(Setup s, Profile p) {
  Responder m(Service::MaterialLoad, options_for(p));
  m.on_counterpart(InteractionState::Ready, kT0);
  switch (s) {
    case Setup::Ready:
      break;
    case Setup::NotReady:
      m.set_not_ready(kT0);
      break;
    case Setup::ResponderReadyRequestActive:
      m.on_counterpart(InteractionState::Active, kT0);
      break;
    case Setup::Active:
    case Setup::ActiveEngaged:
      m.on_counterpart(InteractionState::Active, kT0);
      m.accept(kT0);
      break;
    case Setup::Complete:
      m.on_counterpart(InteractionState::Active, kT0);
      m.accept(kT0);
      m.complete(kT0);
      break;
    case Setup::Fail:
      m.fail(kT0);
      break;
    case Setup::FailAcknowledged:
      m.fail(kT0);
      m.on_counterpart(InteractionState::Fail, kT0);
      break;
    case Setup::Disabled:
      m.disable(kT0);
      break;
    case Setup::DisabledFailPending:
      m.disable(kT0);
      m.on_counterpart(InteractionState::Fail, kT0);
      break;
  }
  return m;
}

}  // namespace testing_support
}  // namespace mtc::core

namespace mtc::core::testing_support {

// A requester and a responder wired back to back with instantaneous
// delivery: to_responder() shows the responder the request's current value,
// to_requester() the other way round. The simulated clock only moves when a
// test advances it.
struct Pair {
  explicit Pair(Profile p = Profile::V1_6, Service s = Service::MaterialLoad)
      : requester(s, options_for(p)), responder(s, options_for(p)) {
    to_responder();
    to_requester();
  }
  Pair(const MachineOptions& requester_options, const MachineOptions& responder_options,
       Service s = Service::MaterialLoad)
      : requester(s, requester_options), responder(s, responder_options) {
    to_responder();
    to_requester();
  }

  StepResult to_responder() { return responder.on_counterpart(requester.state(), now); }
  StepResult to_requester() { return requester.on_counterpart(responder.state(), now); }

  Requester requester;
  Responder responder;
  TimePoint now{};
};

}  // namespace mtc::core::testing_support
