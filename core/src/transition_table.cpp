// The transition tables of Tables 5 (request) and 6 (response), 1.6/1.8 with
// the 1.3 differences as V13-guarded rows. Read a row as
//   from + event [guard && guard2] -> to / notice(reason).
// First match wins; role rows come first, then rows shared by both roles
// (FAIL, DISABLED, wildcard). The static_asserts at the bottom prove every
// reachable (phase, event) pair has an unguarded fallback row.
#include <array>
#include <cstddef>

#include "mtc/core/transition.hpp"

namespace mtc::core {
namespace {

using P = Phase;
using E = Event;
using G = Guard;
using T = Target;
using N = Notice;
using R = Reason;

constexpr Transition row(P from, E event, G g, G g2, T to, N notice, R reason = R::None) {
  return Transition{from, event, g, g2, to, notice, reason};
}
constexpr Transition row(P from, E event, G g, T to, N notice, R reason = R::None) {
  return Transition{from, event, g, G::Always, to, notice, reason};
}
constexpr Transition row(P from, E event, T to, N notice, R reason = R::None) {
  return Transition{from, event, G::Always, G::Always, to, notice, reason};
}

template <std::size_t A, std::size_t B>
constexpr std::array<Transition, A + B> concat(const std::array<Transition, A>& a,
                                               const std::array<Transition, B>& b) {
  std::array<Transition, A + B> out{};
  for (std::size_t i = 0; i < A; ++i) out[i] = a[i];
  for (std::size_t i = 0; i < B; ++i) out[A + i] = b[i];
  return out;
}

// clang-format off
// ---------------------------------------------------------------- requester
constexpr std::array kRequesterRows{
    // READY: "will transition to ACTIVE when it needs a service" (Table 5).
    row(P::Ready, E::Request, G::NotPermitted, T::Stay, N::Rejected, R::PreconditionNotMet),
    row(P::Ready, E::Request, G::CounterpartNotReady, T::Stay, N::Rejected, R::CounterpartBusy),
    row(P::Ready, E::Request, T::Active, N::RequestIssued),
    row(P::Ready, E::SetNotReady, T::NotReady, N::ReadinessChanged, R::Application),
    row(P::Ready, E::SetReady, T::Stay, N::None),
    row(P::Ready, E::Reevaluate, G::CounterpartFailPending, G::V16, T::Fail,
        N::CounterpartFailed, R::CounterpartFail),
    row(P::Ready, E::Reevaluate, G::NotPermitted, T::NotReady, N::ReadinessChanged,
        R::PreconditionNotMet),
    // Table 6: a response goes ACTIVE/COMPLETE only for an ACTIVE request.
    row(P::Ready, E::SeenActive, T::Fail, N::ProtocolViolation, R::ActiveWithoutRequest),
    row(P::Ready, E::SeenComplete, T::Fail, N::ProtocolViolation, R::CompleteWithoutRequest),
    // Table 5 condition 2 (1.6); 1.3 only returns to / stays READY.
    row(P::Ready, E::SeenFail, G::V13, T::Stay, N::CounterpartFailed, R::CounterpartFail),
    row(P::Ready, E::SeenFail, G::LateAcknowledgement, T::Stay, N::FailAcknowledged),
    row(P::Ready, E::SeenFail, T::Fail, N::CounterpartFailed, R::CounterpartFail),

    // NOT_READY
    row(P::NotReady, E::Request, T::Stay, N::Rejected, R::NotReady),
    row(P::NotReady, E::SetReady, G::NotPermitted, T::Stay, N::None, R::PreconditionNotMet),
    row(P::NotReady, E::SetReady, T::Ready, N::ReadinessChanged, R::Application),
    row(P::NotReady, E::SetNotReady, T::Stay, N::None),
    row(P::NotReady, E::Reevaluate, G::CounterpartFailPending, G::V16, T::Fail,
        N::CounterpartFailed, R::CounterpartFail),
    row(P::NotReady, E::Reevaluate, G::WantsReady, G::Permitted, T::Ready, N::ReadinessChanged),
    row(P::NotReady, E::SeenActive, T::Fail, N::ProtocolViolation, R::ActiveWithoutRequest),
    row(P::NotReady, E::SeenComplete, T::Fail, N::ProtocolViolation, R::CompleteWithoutRequest),
    row(P::NotReady, E::SeenFail, G::V13, T::Stay, N::CounterpartFailed, R::CounterpartFail),
    row(P::NotReady, E::SeenFail, G::LateAcknowledgement, T::Stay, N::FailAcknowledged),
    row(P::NotReady, E::SeenFail, T::Fail, N::CounterpartFailed, R::CounterpartFail),

    // ACTIVE: waiting for the response to go ACTIVE, then COMPLETE.
    row(P::Active, E::Request, T::Stay, N::Rejected, R::AlreadyActive),
    row(P::Active, E::SetReady, T::Stay, N::Rejected, R::NotIdle),
    row(P::Active, E::SetNotReady, T::Stay, N::Rejected, R::NotIdle),
    row(P::Active, E::SeenActive, T::Stay, N::Accepted),
    // Table 1 steps 5-6: COMPLETE seen, back to READY acknowledging it.
    row(P::Active, E::SeenComplete, G::CounterpartEngaged, T::Ready, N::Completed),
    row(P::Active, E::SeenComplete, T::Fail, N::ProtocolViolation, R::CompleteWithoutActive),
    // Scenario 5 / 1.3 "no FAIL state": leaving ACTIVE early is a failure.
    row(P::Active, E::SeenReady, G::CounterpartEngaged, G::V13, T::Ready, N::CounterpartFailed,
        R::CounterpartLeftActive),
    row(P::Active, E::SeenReady, G::CounterpartEngaged, T::Fail, N::CounterpartFailed,
        R::CounterpartLeftActive),
    row(P::Active, E::SeenReady, T::Stay, N::None),
    row(P::Active, E::SeenNotReady, G::CounterpartEngaged, G::V13, T::Ready, N::CounterpartFailed,
        R::CounterpartLeftActive),
    row(P::Active, E::SeenNotReady, G::CounterpartEngaged, T::Fail, N::CounterpartFailed,
        R::CounterpartLeftActive),
    // Refused before accepting: the service cannot happen.
    row(P::Active, E::SeenNotReady, G::V13, T::Ready, N::CounterpartFailed, R::CounterpartNotReady),
    row(P::Active, E::SeenNotReady, T::Fail, N::CounterpartFailed, R::CounterpartNotReady),
    // Scenarios 1 and 2: 1.6 MUST go FAIL; 1.3 MUST go back to READY.
    row(P::Active, E::SeenFail, G::V13, T::Ready, N::CounterpartFailed, R::CounterpartFail),
    row(P::Active, E::SeenFail, T::Fail, N::CounterpartFailed, R::CounterpartFail),
    row(P::Active, E::SeenUnavailable, T::Fail, N::CommsLost, R::CommsLost),
    row(P::Active, E::ResponseTimeout, G::CounterpartNotEngaged, T::Fail, N::TimedOut,
        R::ResponseTimeout),
    row(P::Active, E::ServiceTimeout, T::Fail, N::TimedOut, R::ServiceTimeout),

    row(P::Fail, E::Request, T::Stay, N::Rejected, R::AlreadyFailed),
    row(P::Disabled, E::Enable, G::CounterpartFailPending, G::V16, T::Fail, N::CounterpartFailed,
        R::CounterpartFail),
    row(P::Any, E::Accept, T::Stay, N::Rejected, R::WrongRole),
    row(P::Any, E::Complete, T::Stay, N::Rejected, R::WrongRole),
};

// ---------------------------------------------------------------- responder
constexpr std::array kResponderRows{
    // READY: "MUST transition to ACTIVE ... accepted the Request"; "MUST NOT
    // change its state to ACTIVE unless the Requester state is ACTIVE".
    row(P::Ready, E::Accept, G::RequestNotActive, T::Stay, N::Rejected, R::RequestNotActive),
    row(P::Ready, E::Accept, G::NotPermitted, T::Stay, N::Rejected, R::PreconditionNotMet),
    row(P::Ready, E::Accept, T::Active, N::Accepted),
    row(P::Ready, E::Complete, T::Stay, N::Rejected, R::NotActive),
    row(P::Ready, E::SetNotReady, T::NotReady, N::ReadinessChanged, R::Application),
    row(P::Ready, E::SetReady, T::Stay, N::None),
    row(P::Ready, E::Reevaluate, G::CounterpartFailPending, T::Fail, N::CounterpartFailed,
        R::CounterpartFail),
    row(P::Ready, E::Reevaluate, G::NotPermitted, T::NotReady, N::ReadinessChanged,
        R::PreconditionNotMet),
    row(P::Ready, E::SeenActive, T::Stay, N::RequestObserved),  // Table 1 step 2
    row(P::Ready, E::SeenComplete, T::Fail, N::ProtocolViolation, R::CompleteOnRequest),
    row(P::Ready, E::SeenFail, G::LateAcknowledgement, T::Stay, N::FailAcknowledged),
    row(P::Ready, E::SeenFail, T::Fail, N::CounterpartFailed, R::CounterpartFail),

    // NOT_READY
    row(P::NotReady, E::Accept, T::Stay, N::Rejected, R::NotReady),
    row(P::NotReady, E::Complete, T::Stay, N::Rejected, R::NotActive),
    row(P::NotReady, E::SetReady, G::NotPermitted, T::Stay, N::None, R::PreconditionNotMet),
    row(P::NotReady, E::SetReady, T::Ready, N::ReadinessChanged, R::Application),
    row(P::NotReady, E::SetNotReady, T::Stay, N::None),
    row(P::NotReady, E::Reevaluate, G::CounterpartFailPending, T::Fail, N::CounterpartFailed,
        R::CounterpartFail),
    row(P::NotReady, E::Reevaluate, G::WantsReady, G::Permitted, T::Ready, N::ReadinessChanged),
    row(P::NotReady, E::SeenActive, T::Stay, N::RequestObserved, R::NotReady),
    row(P::NotReady, E::SeenComplete, T::Fail, N::ProtocolViolation, R::CompleteOnRequest),
    row(P::NotReady, E::SeenFail, G::LateAcknowledgement, T::Stay, N::FailAcknowledged),
    row(P::NotReady, E::SeenFail, T::Fail, N::CounterpartFailed, R::CounterpartFail),

    // ACTIVE: performing the service.
    row(P::Active, E::Complete, T::Complete, N::Completed),  // Table 1 step 4
    row(P::Active, E::Accept, T::Stay, N::Rejected, R::AlreadyActive),
    row(P::Active, E::SetReady, T::Stay, N::Rejected, R::NotIdle),
    row(P::Active, E::SetNotReady, T::Stay, N::Rejected, R::NotIdle),
    // Scenario 4 (and its NOT_READY note; 1.3 "no FAIL state" requester).
    row(P::Active, E::SeenReady, T::Fail, N::CounterpartFailed, R::CounterpartLeftActive),
    row(P::Active, E::SeenNotReady, T::Fail, N::CounterpartFailed, R::CounterpartLeftActive),
    row(P::Active, E::SeenActive, T::Stay, N::None),
    row(P::Active, E::SeenComplete, T::Fail, N::ProtocolViolation, R::CompleteOnRequest),
    row(P::Active, E::SeenFail, T::Fail, N::CounterpartFailed, R::CounterpartFail),  // scenario 3
    row(P::Active, E::SeenUnavailable, T::Fail, N::CommsLost, R::CommsLost),
    row(P::Active, E::ServiceTimeout, T::Fail, N::TimedOut, R::ServiceTimeout),

    // COMPLETE: "MUST remain in the COMPLETE state until the Requester
    // acknowledges ... by changing its state to READY", then READY/NOT_READY.
    row(P::Complete, E::Complete, T::Stay, N::Rejected, R::NotActive),
    row(P::Complete, E::Accept, T::Stay, N::Rejected, R::NotIdle),
    row(P::Complete, E::SetReady, T::Stay, N::None),     // wish applies after the ack
    row(P::Complete, E::SetNotReady, T::Stay, N::None),  // wish applies after the ack
    row(P::Complete, E::SeenReady, T::Idle, N::Acknowledged),  // steps 7-8
    row(P::Complete, E::SeenNotReady, T::Idle, N::Acknowledged),
    row(P::Complete, E::SeenActive, T::Stay, N::None),
    row(P::Complete, E::SeenComplete, T::Fail, N::ProtocolViolation, R::CompleteOnRequest),
    row(P::Complete, E::SeenFail, T::Fail, N::CounterpartFailed, R::CounterpartFail),
    row(P::Complete, E::SeenUnavailable, T::Fail, N::CommsLost, R::CommsLost),
    row(P::Complete, E::CompletionAckTimeout, T::Stay, N::TimedOut, R::CompletionAckTimeout),

    row(P::Fail, E::Accept, T::Stay, N::Rejected, R::AlreadyFailed),
    row(P::Fail, E::Complete, T::Stay, N::Rejected, R::NotActive),
    row(P::Fail, E::SeenComplete, T::Stay, N::ProtocolViolation, R::CompleteOnRequest),
    row(P::Disabled, E::SeenComplete, T::Stay, N::ProtocolViolation, R::CompleteOnRequest),
    row(P::Disabled, E::Enable, G::CounterpartFailPending, T::Fail, N::CounterpartFailed,
        R::CounterpartFail),
    row(P::Any, E::Request, T::Stay, N::Rejected, R::WrongRole),
};

// ------------------------------------------------------ shared: FAIL phase
constexpr std::array kFailRows{
    row(P::Fail, E::Fail, T::Stay, N::Rejected, R::AlreadyFailed),
    // Tables 5/6 ACTIONS: SHOULD NOT leave FAIL before the acknowledgement.
    row(P::Fail, E::RecoverReady, G::NotAcknowledged, T::Stay, N::Rejected,
        R::FailNotAcknowledged),
    row(P::Fail, E::RecoverReady, T::Idle, N::Recovered),
    row(P::Fail, E::RecoverNotReady, G::NotAcknowledged, T::Stay, N::Rejected,
        R::FailNotAcknowledged),
    row(P::Fail, E::RecoverNotReady, T::NotReady, N::Recovered),
    row(P::Fail, E::SetReady, T::Stay, N::Rejected, R::NotIdle),
    row(P::Fail, E::SetNotReady, T::Stay, N::Rejected, R::NotIdle),
    row(P::Fail, E::SeenFail, G::AcknowledgesFail, T::Stay, N::FailAcknowledged),
    row(P::Fail, E::SeenReady, G::AcknowledgesFail, T::Stay, N::FailAcknowledged),
    row(P::Fail, E::SeenNotReady, G::AcknowledgesFail, T::Stay, N::FailAcknowledged),
    row(P::Fail, E::SeenFail, T::Stay, N::None),
    row(P::Fail, E::SeenReady, T::Stay, N::None),
    row(P::Fail, E::SeenNotReady, T::Stay, N::None),
    row(P::Fail, E::SeenActive, T::Stay, N::None),
    row(P::Fail, E::SeenComplete, T::Stay, N::None),
    // Scenario 6: no trust in what the counterpart said before the loss.
    row(P::Fail, E::SeenUnavailable, T::Stay, N::CommsLost, R::CommsLost),
    row(P::Fail, E::SeenInvalid, T::Stay, N::ProtocolViolation, R::UnknownValue),
    row(P::Fail, E::FailAckTimeout, G::NotAcknowledged, T::Stay, N::TimedOut, R::FailAckTimeout),
    // 1.3: "can also transition back to READY after a period of time".
    row(P::Fail, E::FailResetTimeout, G::V13, T::Idle, N::Recovered, R::FailResetTimeout),
};

// -------------------------------------------------- shared: DISABLED phase
// Table 3: while DISABLED every interaction item is NOT_READY.
constexpr std::array kDisabledRows{
    row(P::Disabled, E::Enable, T::Idle, N::Enabled),
    row(P::Disabled, E::Disable, T::Stay, N::None),
    row(P::Disabled, E::Request, T::Stay, N::Rejected, R::InterfaceDisabled),
    row(P::Disabled, E::Accept, T::Stay, N::Rejected, R::InterfaceDisabled),
    row(P::Disabled, E::Complete, T::Stay, N::Rejected, R::InterfaceDisabled),
    row(P::Disabled, E::Fail, T::Stay, N::Rejected, R::InterfaceDisabled),
    row(P::Disabled, E::RecoverReady, T::Stay, N::Rejected, R::InterfaceDisabled),
    row(P::Disabled, E::RecoverNotReady, T::Stay, N::Rejected, R::InterfaceDisabled),
    row(P::Disabled, E::SetReady, T::Stay, N::Rejected, R::InterfaceDisabled),
    row(P::Disabled, E::SetNotReady, T::Stay, N::Rejected, R::InterfaceDisabled),
    row(P::Disabled, E::SeenNotReady, T::Stay, N::None, R::InterfaceDisabled),
    row(P::Disabled, E::SeenReady, T::Stay, N::None, R::InterfaceDisabled),
    row(P::Disabled, E::SeenActive, T::Stay, N::None, R::InterfaceDisabled),
    row(P::Disabled, E::SeenComplete, T::Stay, N::None, R::InterfaceDisabled),
    row(P::Disabled, E::SeenFail, T::Stay, N::CounterpartFailed, R::InterfaceDisabled),
    row(P::Disabled, E::SeenUnavailable, T::Stay, N::CommsLost, R::CommsLost),
    row(P::Disabled, E::SeenInvalid, T::Stay, N::ProtocolViolation, R::UnknownValue),
};

// ------------------------------------------------------ shared: wildcards
constexpr std::array kAnyRows{
    row(P::Any, E::Disable, T::Disabled, N::Disabled, R::InterfaceDisabled),
    row(P::Any, E::Enable, T::Stay, N::None),
    row(P::Any, E::Fail, T::Fail, N::Failed, R::Application),  // Table 5/6 condition 1
    row(P::Any, E::RecoverReady, T::Stay, N::Rejected, R::NotFailed),
    row(P::Any, E::RecoverNotReady, T::Stay, N::Rejected, R::NotFailed),
    row(P::Any, E::Reevaluate, T::Stay, N::None),
    row(P::Any, E::SeenNotReady, T::Stay, N::None),
    row(P::Any, E::SeenReady, T::Stay, N::None),
    row(P::Any, E::SeenActive, T::Stay, N::None),
    row(P::Any, E::SeenComplete, T::Stay, N::None),
    row(P::Any, E::SeenFail, T::Stay, N::None),
    // Scenario 6: 1.6 both sides FAIL; 1.3 idle sides re-read on reconnection.
    row(P::Any, E::SeenUnavailable, G::V13, T::Stay, N::CommsLost, R::CommsLost),
    row(P::Any, E::SeenUnavailable, T::Fail, N::CommsLost, R::CommsLost),
    row(P::Any, E::SeenInvalid, T::Fail, N::ProtocolViolation, R::UnknownValue),
    // A time limit that is no longer armed (state moved on): nothing to do.
    row(P::Any, E::ResponseTimeout, T::Stay, N::None),
    row(P::Any, E::ServiceTimeout, T::Stay, N::None),
    row(P::Any, E::CompletionAckTimeout, T::Stay, N::None),
    row(P::Any, E::FailAckTimeout, T::Stay, N::None),
    row(P::Any, E::FailResetTimeout, T::Stay, N::None),
};

// clang-format on

constexpr auto kRequesterTable =
    concat(concat(kRequesterRows, kFailRows), concat(kDisabledRows, kAnyRows));
constexpr auto kResponderTable =
    concat(concat(kResponderRows, kFailRows), concat(kDisabledRows, kAnyRows));

// Every (phase, event) pair a role can meet must end in an unguarded row, so
// lookup never falls off the table.
template <std::size_t N>
constexpr bool has_fallback(const std::array<Transition, N>& table, P phase, E event) {
  // A loop, not std::any_of: that is constexpr only from C++20.
  for (const auto& r : table) {  // NOLINT(readability-use-anyofallof)
    if ((r.from == phase || r.from == P::Any) && r.event == event && r.guard == G::Always &&
        r.guard2 == G::Always) {
      return true;
    }
  }
  return false;
}
template <std::size_t N>
constexpr bool complete_for(const std::array<Transition, N>& table, bool with_complete_phase) {
  for (std::size_t p = 0; p < kPhaseCount; ++p) {
    const auto phase = static_cast<P>(p);
    if (phase == P::Complete && !with_complete_phase) continue;
    for (std::size_t e = 0; e < kEventCount; ++e) {
      if (!has_fallback(table, phase, static_cast<E>(e))) return false;
    }
  }
  return true;
}
static_assert(complete_for(kRequesterTable, false), "requester table has a gap");
static_assert(complete_for(kResponderTable, true), "responder table has a gap");

}  // namespace

TransitionTable requester_table() noexcept {
  return {kRequesterTable.data(), kRequesterTable.size()};
}
TransitionTable responder_table() noexcept {
  return {kResponderTable.data(), kResponderTable.size()};
}

}  // namespace mtc::core
