// One side of one service: the state machine behind one REQUEST or RESPONSE
// data item. Requester and Responder (requester.hpp, responder.hpp) add the
// role's own commands; everything else is here.
//
// Usage (runtime): feed every change of the counterpart's data item to
// on_counterpart(), loss of communication to on_counterpart_lost(), the
// application's commands to the named functions, and call on_tick(now) when
// next_deadline() has passed. Each call returns a StepResult; publish
// `current` when it changed() and hand `notice`/`reason` to the application.
//
// Every function is noexcept, allocation-free and never blocks. A machine is
// a plain value (copyable); it is not thread-safe: drive it from one thread.
#pragma once

#include <string_view>

#include "mtc/core/preconditions.hpp"
#include "mtc/core/profile.hpp"
#include "mtc/core/result.hpp"
#include "mtc/core/time.hpp"
#include "mtc/core/transition.hpp"
#include "mtc/core/vocabulary.hpp"

namespace mtc::core {

class ServiceMachine {
 public:
  // Starts READY (options.start_ready and the hook permitting) or NOT_READY,
  // with the counterpart UNAVAILABLE (not yet seen).
  ServiceMachine(Role role, Service service, const MachineOptions& options = {},
                 const ServicePreconditions* hook = nullptr) noexcept;

  // Generic entry point: apply one event. The named functions below call it.
  StepResult step(Event event, TimePoint now) noexcept;

  // --- The counterpart's data item -------------------------------------
  // A new value of the counterpart's item. Repeats of the current value are
  // no-ops (Notice::None): transitions react to changes, as the text says
  // ("if the Responder changes its state to FAIL"). Values outside the enum
  // are reported as ProtocolViolation(UnknownValue).
  StepResult on_counterpart(InteractionState observed, TimePoint now) noexcept;
  // Same, from the MTConnect spelling ("ACTIVE"); unknown text is a violation.
  StepResult on_counterpart_text(std::string_view text, TimePoint now) noexcept;
  // Loss of communication / heartbeat / counterpart INTERFACE_STATE
  // UNAVAILABLE (scenario 6). Equivalent to observing UNAVAILABLE.
  StepResult on_counterpart_lost(TimePoint now) noexcept;

  // --- Application commands common to both roles -----------------------
  StepResult fail(TimePoint now) noexcept;
  // Clear FAIL to READY or NOT_READY (anything else: Rejected/InvalidTarget).
  // Allowed only once the counterpart acknowledged this FAIL (Tables 5/6
  // ACTIONS): by showing a fresh FAIL; under V1_3 a request also
  // acknowledges a response FAIL by leaving ACTIVE; a counterpart without a
  // FAIL state by being out of ACTIVE/COMPLETE. TimeLimits::fail_ack waives
  // the wait. READY may still land on NOT_READY when the hook says no.
  StepResult recover(InteractionState target, TimePoint now) noexcept;
  StepResult set_ready(TimePoint now) noexcept;
  StepResult set_not_ready(TimePoint now) noexcept;
  // INTERFACE_STATE DISABLED / ENABLED (Table 3). InterfaceModel does this
  // for every machine of an interface.
  StepResult disable(TimePoint now) noexcept;
  StepResult enable(TimePoint now) noexcept;
  // The precondition hook's answer may have changed (door/chuck moved).
  StepResult reevaluate(TimePoint now) noexcept;

  // --- Time ---------------------------------------------------------------
  // Fires the earliest expired time limit, if any; otherwise returns an
  // unchanged result with Notice::None. At most one limit per call: call
  // again while next_deadline() <= now.
  StepResult on_tick(TimePoint now) noexcept;
  // Earliest instant a time limit expires, kNever when none is armed. Also
  // "now" (the phase's start) when a deferred reaction is due: a counterpart
  // that failed anew while this side was in FAIL is answered right after
  // this side's recovery (READY is published first, then FAIL, so the
  // counterpart sees the change it waits for).
  TimePoint next_deadline() const noexcept;

  // --- Observers --------------------------------------------------------
  InteractionState state() const noexcept { return published(phase_); }
  Phase phase() const noexcept { return phase_; }
  InteractionState counterpart() const noexcept { return counterpart_; }
  // FAIL was acknowledged by the counterpart (or the wait waived by timeout).
  bool fail_acknowledged() const noexcept { return acknowledged_ || ack_waived_; }
  bool disabled() const noexcept { return phase_ == Phase::Disabled; }
  Role role() const noexcept { return role_; }
  Service service() const noexcept { return service_; }
  const MachineOptions& options() const noexcept { return options_; }
  // Instant the current phase was entered (the `now` of that step).
  TimePoint phase_since() const noexcept { return since_; }

  void set_preconditions(const ServicePreconditions* hook) noexcept { hook_ = hook; }

 private:
  bool guard_holds(Guard g) const noexcept;
  bool counterpart_acknowledges(InteractionState s) const noexcept;
  bool reaction_due() const noexcept;
  TimePoint reaction_at() const noexcept;
  Phase resolve(Target t) const noexcept;
  void enter(Phase next, TimePoint now) noexcept;
  void apply_effects(Event event, Phase before, Notice notice) noexcept;
  StepResult make_result(Event event, Phase before, Notice notice, Reason reason) const noexcept;

  Role role_;
  Service service_;
  MachineOptions options_;
  const ServicePreconditions* hook_;
  Phase phase_ = Phase::Ready;
  TimePoint since_{};
  InteractionState counterpart_ = InteractionState::Unavailable;
  bool wants_ready_ = true;           // application's last wish
  bool counterpart_engaged_ = false;  // requester: responder went ACTIVE for this request
  bool acknowledged_ = false;         // our FAIL acknowledged
  bool ack_waived_ = false;           // fail_ack expired
  bool fail_pending_ = false;         // counterpart went FAIL, not yet reacted to
  bool ack_owed_ = false;             // we left FAIL unacknowledged (wait waived)
  bool late_ack_ = false;             // the counterpart FAIL seen idle was taken for that ack
  TimePoint late_ack_until_{};        // ...unless it stays FAIL until then
  bool counterpart_lost_ = false;     // last counterpart value was UNAVAILABLE
  bool completion_ack_reported_ = false;
};

}  // namespace mtc::core
