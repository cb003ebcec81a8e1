// The transition tables of the requester (Table 5) and responder (Table 6)
// machines, in the style of boost-ext/sml: one row per transition,
//   from + event [guard && guard2] -> to / notice(reason).
// Rows are searched in order; the first row whose state, event and guards
// match is taken, rows with `from == Phase::Any` come last. Every (state,
// event) pair resolves to a row (checked at compile time in machine.cpp), so
// an event is never silently dropped: unwanted application commands resolve
// to Notice::Rejected, unexpected counterpart values to a failure or a
// Notice::ProtocolViolation.
#pragma once

#include <cstddef>
#include <cstdint>

#include "mtc/core/result.hpp"

namespace mtc::core {

// A machine's own state. Disabled publishes NOT_READY (Table 3) but, unlike
// NotReady, refuses every command until Enable.
enum class Phase : std::uint8_t { NotReady, Ready, Active, Complete, Fail, Disabled, Any };
inline constexpr std::size_t kPhaseCount = 6;  // without Any

// The published value of a phase.
constexpr InteractionState published(Phase p) noexcept {
  switch (p) {
    case Phase::Ready:
      return InteractionState::Ready;
    case Phase::Active:
      return InteractionState::Active;
    case Phase::Complete:
      return InteractionState::Complete;
    case Phase::Fail:
      return InteractionState::Fail;
    case Phase::NotReady:
    case Phase::Disabled:
    case Phase::Any:
      break;
  }
  return InteractionState::NotReady;
}

// Named guards. Each is a small predicate over the machine's context
// (evaluated in machine.cpp, `guard_holds`).
enum class Guard : std::uint8_t {
  Always,
  V13,        // profile is V1_3
  V16,        // profile is V1_6 (also 1.8)
  Permitted,  // precondition hook allows this service now
  NotPermitted,
  WantsReady,           // the application's last wish was READY
  CounterpartReady,     // counterpart currently READY
  CounterpartNotReady,  // counterpart currently anything but READY
  CounterpartEngaged,   // requester: responder went ACTIVE for this request
  CounterpartNotEngaged,
  RequestActive,  // responder: request currently ACTIVE
  RequestNotActive,
  AcknowledgesFail,  // the value just seen acknowledges our (unacknowledged) FAIL
  Acknowledged,      // our FAIL was acknowledged, or the wait was waived
  NotAcknowledged,
  CounterpartFailPending,  // counterpart went FAIL and we have not yet reacted
  LateAcknowledgement,     // idle: the FAIL just seen answers our FAIL whose wait we waived
};

// Where a row leads. Idle = READY if the application wants READY and the
// precondition hook permits, NOT_READY otherwise.
enum class Target : std::uint8_t { Stay, NotReady, Ready, Active, Complete, Fail, Idle, Disabled };

struct Transition {
  Phase from;
  Event event;
  Guard guard;
  Guard guard2;
  Target to;
  Notice notice;
  Reason reason;
};

struct TransitionTable {
  const Transition* rows;
  std::size_t size;
  constexpr const Transition* begin() const noexcept { return rows; }
  constexpr const Transition* end() const noexcept { return rows + size; }
};

TransitionTable requester_table() noexcept;
TransitionTable responder_table() noexcept;

std::string_view to_string(Phase p) noexcept;
std::string_view to_string(Guard g) noexcept;
std::string_view to_string(Target t) noexcept;

}  // namespace mtc::core
