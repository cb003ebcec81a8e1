// What one step of a service machine did, as a small value the runtime can
// publish, log and turn into application callbacks without further
// interpretation.
#pragma once

#include <cstdint>
#include <string_view>

#include "mtc/core/vocabulary.hpp"

namespace mtc::core {

// Every input a service machine understands. Application commands, counterpart
// observations (one event per observed value) and expired time limits.
enum class Event : std::uint8_t {
  // Application commands.
  Request,          // requester: ask for the service (READY -> ACTIVE)
  Accept,           // responder: take the request on (READY -> ACTIVE)
  Complete,         // responder: service done (ACTIVE -> COMPLETE)
  Fail,             // either: a failure was detected locally (-> FAIL)
  RecoverReady,     // either: clear FAIL to READY
  RecoverNotReady,  // either: clear FAIL to NOT_READY
  SetReady,         // either: idle side becomes willing (NOT_READY -> READY)
  SetNotReady,      // either: idle side becomes unwilling (READY -> NOT_READY)
  Disable,          // INTERFACE_STATE went DISABLED: force NOT_READY
  Enable,           // INTERFACE_STATE went ENABLED again
  Reevaluate,       // the precondition hook's answer may have changed
  // The counterpart's data item changed to this value.
  SeenNotReady,
  SeenReady,
  SeenActive,
  SeenComplete,
  SeenFail,
  SeenUnavailable,  // value UNAVAILABLE or loss of communication (scenario 6)
  SeenInvalid,      // a value outside the vocabulary
  // Time limits (see TimeLimits).
  ResponseTimeout,
  ServiceTimeout,
  CompletionAckTimeout,
  FailAckTimeout,
  FailResetTimeout,
};
inline constexpr std::size_t kEventCount = 23;

// What the application should learn from a step.
enum class Notice : std::uint8_t {
  None,               // nothing to report (state may still be unchanged)
  RequestIssued,      // requester: READY -> ACTIVE (Table 1 step 1)
  RequestObserved,    // responder: the request went ACTIVE (step 2); accept() or refuse
  Accepted,           // responder went ACTIVE (step 3; seen by either side)
  Completed,          // responder COMPLETE (step 4) / requester back to READY (steps 5-6)
  Acknowledged,       // responder: request back to READY after COMPLETE (steps 7-8)
  Failed,             // own side failed (application), see reason
  CounterpartFailed,  // counterpart FAIL or unexpected state change, see reason
  FailAcknowledged,   // counterpart acknowledged our FAIL: recover() now allowed
  Recovered,          // FAIL -> READY / NOT_READY
  TimedOut,           // a time limit expired, reason says which
  ProtocolViolation,  // counterpart broke Tables 5/6, reason says how
  Rejected,           // application command refused, reason says why; nothing changed
  ReadinessChanged,   // idle READY <-> NOT_READY
  Disabled,           // INTERFACE_STATE DISABLED forced NOT_READY
  Enabled,            // INTERFACE_STATE ENABLED again
  CommsLost,          // counterpart UNAVAILABLE / heartbeat lost
  CommsRestored,      // first counterpart value after a loss
};

// Why. One enum for failure causes, violations, time limits and rejections.
enum class Reason : std::uint8_t {
  None,
  // Failure causes.
  Application,            // the application called fail()
  CounterpartFail,        // counterpart went FAIL
  CounterpartLeftActive,  // counterpart left ACTIVE before COMPLETE (scenarios 4, 5)
  CounterpartNotReady,    // responder went NOT_READY while the request was ACTIVE
  CommsLost,              // counterpart UNAVAILABLE / no heartbeat (scenario 6)
  // Time limits.
  ResponseTimeout,
  ServiceTimeout,
  CompletionAckTimeout,
  FailAckTimeout,
  FailResetTimeout,
  // Protocol violations by the counterpart.
  UnknownValue,            // value outside the vocabulary
  CompleteOnRequest,       // a REQUEST reported COMPLETE (not in Table 5)
  ActiveWithoutRequest,    // response ACTIVE while the request was not ACTIVE
  CompleteWithoutRequest,  // response COMPLETE while the request was not ACTIVE
  CompleteWithoutActive,   // response COMPLETE without having been ACTIVE
  // Rejections of application commands.
  WrongRole,  // e.g. accept() on a requester
  NotReady,   // own state is NOT_READY
  NotIdle,    // only allowed in READY / NOT_READY
  NotActive,  // only allowed in ACTIVE
  NotFailed,  // recover() outside FAIL
  AlreadyActive,
  AlreadyFailed,
  FailNotAcknowledged,  // recover() before the counterpart acknowledged FAIL
  RequestNotActive,     // accept() while the request is not ACTIVE (Table 6)
  CounterpartBusy,      // request() while the response is not READY
  InterfaceDisabled,
  PreconditionNotMet,  // hook says no (e.g. OPEN_DOOR while the door is OPEN)
  InvalidTarget,       // recover() to a state other than READY / NOT_READY
};

// The outcome of one step. `previous`/`current` are the PUBLISHED values of
// this side's data item; publish `current` when changed() is true.
struct StepResult {
  Service service = Service::MaterialLoad;
  Role role = Role::Requester;
  Event event = Event::Reevaluate;
  InteractionState previous = InteractionState::Unavailable;
  InteractionState current = InteractionState::Unavailable;
  Notice notice = Notice::None;
  Reason reason = Reason::None;

  constexpr bool changed() const noexcept { return previous != current; }
  constexpr bool rejected() const noexcept { return notice == Notice::Rejected; }
  constexpr bool violation() const noexcept { return notice == Notice::ProtocolViolation; }
  // True when the step put this side into FAIL.
  constexpr bool entered_fail() const noexcept {
    return changed() && current == InteractionState::Fail;
  }
};

// Stable identifiers for logs ("SeenActive", "CounterpartLeftActive", ...).
std::string_view to_string(Event e) noexcept;
std::string_view to_string(Notice n) noexcept;
std::string_view to_string(Reason r) noexcept;
// Short human sentence for a reason, e.g. "responder left ACTIVE before COMPLETE".
std::string_view describe(Reason r) noexcept;

// The counterpart event for an observed value; SeenInvalid for anything that
// is not a defined enumerator.
Event seen_event(InteractionState observed) noexcept;

}  // namespace mtc::core
