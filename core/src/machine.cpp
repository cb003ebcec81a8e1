// The table interpreter: bookkeeping of what the counterpart showed, guard
// evaluation, row lookup and the few effects a row has besides its target.
#include "mtc/core/machine.hpp"

#include <algorithm>

namespace mtc::core {
namespace {

constexpr bool is_seen(Event e) noexcept {
  return e >= Event::SeenNotReady && e <= Event::SeenInvalid;
}

constexpr InteractionState observed_state(Event e) noexcept {
  switch (e) {
    case Event::SeenNotReady:
      return InteractionState::NotReady;
    case Event::SeenReady:
      return InteractionState::Ready;
    case Event::SeenActive:
      return InteractionState::Active;
    case Event::SeenComplete:
      return InteractionState::Complete;
    case Event::SeenFail:
      return InteractionState::Fail;
    default:
      break;
  }
  return InteractionState::Unavailable;
}

constexpr bool is_valid_enum(InteractionState s) noexcept {
  return static_cast<unsigned>(s) <= static_cast<unsigned>(InteractionState::Fail);
}

constexpr bool is_valid_event(Event e) noexcept {
  return static_cast<std::size_t>(e) < kEventCount;
}

// Falls back to a rejection (commands) or a violation (observations) if the
// table had no row; the static_asserts in transition_table.cpp make that
// unreachable for defined events.
template <typename Holds>
Transition find_row(TransitionTable table, Phase phase, Event event, Holds&& holds) noexcept {
  for (const auto& r : table) {
    if (r.event != event) continue;
    if (r.from != phase && r.from != Phase::Any) continue;
    if (holds(r.guard) && holds(r.guard2)) return r;
  }
  return Transition{phase,
                    event,
                    Guard::Always,
                    Guard::Always,
                    Target::Stay,
                    Notice::Rejected,
                    Reason::UnknownValue};
}

}  // namespace

Event seen_event(InteractionState observed) noexcept {
  switch (observed) {
    case InteractionState::Unavailable:
      return Event::SeenUnavailable;
    case InteractionState::NotReady:
      return Event::SeenNotReady;
    case InteractionState::Ready:
      return Event::SeenReady;
    case InteractionState::Active:
      return Event::SeenActive;
    case InteractionState::Complete:
      return Event::SeenComplete;
    case InteractionState::Fail:
      return Event::SeenFail;
  }
  return Event::SeenInvalid;
}

ServiceMachine::ServiceMachine(Role role, Service service, const MachineOptions& options,
                               const ServicePreconditions* hook) noexcept
    : role_(role),
      service_(service),
      options_(options),
      hook_(hook),
      wants_ready_(options.start_ready) {
  // Not in the initialiser list: resolve() reads wants_ready_, which is
  // declared (so initialised) after phase_.
  phase_ = resolve(Target::Idle);  // NOLINT(cppcoreguidelines-prefer-member-initializer)
}

// Whether a counterpart value acknowledges our FAIL. A FAIL counts only when
// it is fresh: a FAIL we already answered in an earlier episode (the
// counterpart's value may be stale, its owner already recovering) does not.
bool ServiceMachine::counterpart_acknowledges(InteractionState s) const noexcept {
  if (s == InteractionState::Fail) return fail_pending_ || phase_ == Phase::Fail;
  if (s != InteractionState::Ready && s != InteractionState::NotReady) return false;
  // A counterpart with no FAIL state cannot show FAIL; being out of
  // ACTIVE/COMPLETE is all it can do. Under 1.3 the request acknowledges a
  // response FAIL by "transition[ing] back to READY or NOT_READY".
  return !options_.counterpart_has_fail ||
         (options_.profile == Profile::V1_3 && role_ == Role::Responder);
}

bool ServiceMachine::guard_holds(Guard g) const noexcept {
  const bool permitted = hook_ == nullptr || hook_->permits(service_, role_);
  switch (g) {
    case Guard::Always:
      return true;
    case Guard::V13:
      return options_.profile == Profile::V1_3;
    case Guard::V16:
      return options_.profile != Profile::V1_3;
    case Guard::Permitted:
      return permitted;
    case Guard::NotPermitted:
      return !permitted;
    case Guard::WantsReady:
      return wants_ready_;
    case Guard::CounterpartReady:
      return counterpart_ == InteractionState::Ready;
    case Guard::CounterpartNotReady:
      return counterpart_ != InteractionState::Ready;
    case Guard::CounterpartEngaged:
      return counterpart_engaged_;
    case Guard::CounterpartNotEngaged:
      return !counterpart_engaged_;
    case Guard::RequestActive:
      return counterpart_ == InteractionState::Active;
    case Guard::RequestNotActive:
      return counterpart_ != InteractionState::Active;
    case Guard::AcknowledgesFail:
      return !acknowledged_ && counterpart_acknowledges(counterpart_);
    case Guard::Acknowledged:
      return fail_acknowledged();
    case Guard::NotAcknowledged:
      return !fail_acknowledged();
    case Guard::CounterpartFailPending:
      return fail_pending_;
    case Guard::LateAcknowledgement:
      return late_ack_ && counterpart_ == InteractionState::Fail;
  }
  return false;
}

Phase ServiceMachine::resolve(Target t) const noexcept {
  switch (t) {
    case Target::Stay:
      return phase_;
    case Target::NotReady:
      return Phase::NotReady;
    case Target::Ready:
      return Phase::Ready;
    case Target::Active:
      return Phase::Active;
    case Target::Complete:
      return Phase::Complete;
    case Target::Fail:
      return Phase::Fail;
    case Target::Disabled:
      return Phase::Disabled;
    case Target::Idle:
      break;
  }
  const bool permitted = hook_ == nullptr || hook_->permits(service_, role_);
  return wants_ready_ && permitted ? Phase::Ready : Phase::NotReady;
}

void ServiceMachine::enter(Phase next, TimePoint now) noexcept {
  if (next == phase_) return;
  // Leaving FAIL without its acknowledgement (fail_ack waived the wait):
  // the counterpart may still answer it, late. A new handshake or a new
  // FAIL ends that wait.
  if (phase_ == Phase::Fail) {
    ack_owed_ = !acknowledged_ && ack_waived_;
  } else if (next == Phase::Active || next == Phase::Complete || next == Phase::Fail) {
    ack_owed_ = false;
    late_ack_ = false;
  }
  phase_ = next;
  since_ = now;
  switch (next) {
    case Phase::Active:
      counterpart_engaged_ = false;
      break;
    case Phase::Complete:
      completion_ack_reported_ = false;
      break;
    case Phase::Fail:
      // Entering FAIL because the counterpart went FAIL acknowledges at once;
      // a FAIL of the counterpart that we already answered does not.
      acknowledged_ = counterpart_ == InteractionState::Fail
                          ? fail_pending_
                          : counterpart_acknowledges(counterpart_);
      ack_waived_ = false;
      fail_pending_ = false;
      break;
    default:
      break;
  }
}

void ServiceMachine::apply_effects(Event event, Phase before, Notice notice) noexcept {
  if (event == Event::SeenActive && role_ == Role::Requester && phase_ == Phase::Active) {
    counterpart_engaged_ = true;
  }
  if (notice == Notice::FailAcknowledged) acknowledged_ = true;
  if (notice == Notice::FailAcknowledged && before != Phase::Fail) ack_owed_ = false;
  if (event == Event::SeenUnavailable && before == Phase::Fail) acknowledged_ = false;
  if (event == Event::FailAckTimeout && notice == Notice::TimedOut) ack_waived_ = true;
  if (event == Event::CompletionAckTimeout && notice == Notice::TimedOut) {
    completion_ack_reported_ = true;
  }
}

StepResult ServiceMachine::make_result(Event event, Phase before, Notice notice,
                                       Reason reason) const noexcept {
  return StepResult{service_, role_, event, published(before), published(phase_), notice, reason};
}

StepResult ServiceMachine::step(Event event, TimePoint now) noexcept {
  const Phase before = phase_;
  if (!is_valid_event(event)) {
    return make_result(event, before, Notice::Rejected, Reason::UnknownValue);
  }
  const bool was_lost = counterpart_lost_;
  if (is_seen(event) && event != Event::SeenInvalid) {
    const InteractionState observed = observed_state(event);
    // Reactions are to changes; a repeated value (heartbeat) is a no-op.
    if (observed == counterpart_) return make_result(event, before, Notice::None, Reason::None);
    counterpart_ = observed;
    counterpart_lost_ = observed == InteractionState::Unavailable;
    // A change to FAIL needs our reaction (Tables 5/6 condition 2) unless it
    // is the acknowledgement of our own unacknowledged FAIL. If ours was
    // already acknowledged, the counterpart has failed anew (it recovered
    // and failed again while we were still in FAIL): we answer that after
    // our own recovery (see next_deadline).
    //
    // After we left FAIL by the fail_ack limit, unacknowledged, the next
    // FAIL of the counterpart while we are idle is that acknowledgement,
    // late, not a new failure: failing again for it would fail the
    // handshake the counterpart starts next (issue 10: a requester restarted
    // while the responder's FAIL waited for it, whose FAIL arrived after the
    // responder's fail_ack expired, failed its first request). A handshake
    // step of the counterpart in between means it moved on. It may still
    // be a new failure that waits for our acknowledgement: if the
    // counterpart is still FAIL after the fail_ack limit, we answer it then
    // (reaction_at), as any pending reaction.
    const bool idle = phase_ == Phase::Ready || phase_ == Phase::NotReady;
    if (observed == InteractionState::Active || observed == InteractionState::Complete) {
      ack_owed_ = false;
    }
    late_ack_ = observed == InteractionState::Fail && ack_owed_ && idle;
    if (late_ack_) late_ack_until_ = now + options_.limits.fail_ack;
    fail_pending_ = observed == InteractionState::Fail && (phase_ != Phase::Fail || acknowledged_);
  }
  const TransitionTable table = role_ == Role::Requester ? requester_table() : responder_table();
  const Transition row = find_row(table, phase_, event, [this](Guard g) { return guard_holds(g); });
  if (row.notice != Notice::Rejected) {
    if (event == Event::SetReady || event == Event::RecoverReady) wants_ready_ = true;
    if (event == Event::SetNotReady || event == Event::RecoverNotReady) wants_ready_ = false;
  }
  enter(resolve(row.to), now);
  apply_effects(event, before, row.notice);
  Notice notice = row.notice;
  if (notice == Notice::None && was_lost && is_seen(event) && !counterpart_lost_ &&
      event != Event::SeenInvalid) {
    notice = Notice::CommsRestored;
  }
  return make_result(event, before, notice, row.reason);
}

StepResult ServiceMachine::on_counterpart(InteractionState observed, TimePoint now) noexcept {
  return step(is_valid_enum(observed) ? seen_event(observed) : Event::SeenInvalid, now);
}

StepResult ServiceMachine::on_counterpart_text(std::string_view text, TimePoint now) noexcept {
  const auto parsed = parse_interaction_state(text);
  return step(parsed ? seen_event(*parsed) : Event::SeenInvalid, now);
}

StepResult ServiceMachine::on_counterpart_lost(TimePoint now) noexcept {
  return step(Event::SeenUnavailable, now);
}

StepResult ServiceMachine::fail(TimePoint now) noexcept {
  return step(Event::Fail, now);
}

StepResult ServiceMachine::recover(InteractionState target, TimePoint now) noexcept {
  if (target == InteractionState::Ready) return step(Event::RecoverReady, now);
  if (target == InteractionState::NotReady) return step(Event::RecoverNotReady, now);
  return make_result(Event::RecoverReady, phase_, Notice::Rejected, Reason::InvalidTarget);
}

StepResult ServiceMachine::set_ready(TimePoint now) noexcept {
  return step(Event::SetReady, now);
}
StepResult ServiceMachine::set_not_ready(TimePoint now) noexcept {
  return step(Event::SetNotReady, now);
}
StepResult ServiceMachine::disable(TimePoint now) noexcept {
  return step(Event::Disable, now);
}
StepResult ServiceMachine::enable(TimePoint now) noexcept {
  return step(Event::Enable, now);
}
StepResult ServiceMachine::reevaluate(TimePoint now) noexcept {
  return step(Event::Reevaluate, now);
}

namespace {
struct Armed {
  TimePoint at = kNever;
  Event event = Event::ServiceTimeout;
  void consider(TimePoint candidate, Event e) noexcept {
    if (candidate < at) {
      at = candidate;
      event = e;
    }
  }
};
}  // namespace

// The time limits armed in the current phase, earliest first wins.
static Armed earliest(const ServiceMachine& m, bool engaged, bool acked, bool reported) noexcept {
  Armed armed;
  const TimeLimits& l = m.options().limits;
  const TimePoint since = m.phase_since();
  const Duration zero{0};
  switch (m.phase()) {
    case Phase::Active:
      if (m.role() == Role::Requester && l.response > zero && !engaged) {
        armed.consider(since + l.response, Event::ResponseTimeout);
      }
      if (l.service > zero) armed.consider(since + l.service, Event::ServiceTimeout);
      break;
    case Phase::Complete:
      if (l.completion_ack > zero && !reported) {
        armed.consider(since + l.completion_ack, Event::CompletionAckTimeout);
      }
      break;
    case Phase::Fail:
      if (l.fail_ack > zero && !acked) armed.consider(since + l.fail_ack, Event::FailAckTimeout);
      if (m.options().profile == Profile::V1_3 && l.fail_reset > zero) {
        armed.consider(since + l.fail_reset, Event::FailResetTimeout);
      }
      break;
    default:
      break;
  }
  return armed;
}

// A counterpart FAIL still waiting for our reaction while we are idle (we
// were in FAIL ourselves when it began): react at once, on the next tick, so
// that READY is published before FAIL and the counterpart sees a change.
// When a due reaction runs: at once, or, for a FAIL taken for a late
// acknowledgement, once the counterpart stayed FAIL for the fail_ack limit.
TimePoint ServiceMachine::reaction_at() const noexcept {
  return late_ack_ ? std::max(late_ack_until_, since_) : since_;
}

bool ServiceMachine::reaction_due() const noexcept {
  const bool idle = phase_ == Phase::Ready || phase_ == Phase::NotReady;
  const bool reacts = role_ == Role::Responder || options_.profile != Profile::V1_3;
  return idle && reacts && fail_pending_ && counterpart_ == InteractionState::Fail;
}

TimePoint ServiceMachine::next_deadline() const noexcept {
  if (reaction_due()) return reaction_at();
  return earliest(*this, counterpart_engaged_, fail_acknowledged(), completion_ack_reported_).at;
}

StepResult ServiceMachine::on_tick(TimePoint now) noexcept {
  if (reaction_due() && reaction_at() <= now) return step(Event::Reevaluate, now);
  const Armed armed =
      earliest(*this, counterpart_engaged_, fail_acknowledged(), completion_ack_reported_);
  if (armed.at > now) return make_result(Event::Reevaluate, phase_, Notice::None, Reason::None);
  return step(armed.event, now);
}

}  // namespace mtc::core
