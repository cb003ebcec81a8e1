#include "respond_runner.hpp"

#include <algorithm>

#include "exit_codes.hpp"

namespace mtc::cli {

namespace {
using core::InteractionState;
using Clock = std::chrono::steady_clock;

bool idle(InteractionState s) {
  return s == InteractionState::Ready || s == InteractionState::NotReady;
}
}  // namespace

RespondRunner::RespondRunner(RespondConfig config, Context& context, EquipmentLink& link,
                             EventQueue& events)
    : config_(std::move(config)), context_(context), link_(link), events_(events) {
  slots_.reserve(config_.equipment.services.size());
  for (auto s : config_.equipment.services) {
    slots_.emplace_back(s, context.out, config_.equipment.common.json);
  }
}

RespondRunner::Slot* RespondRunner::slot_for(core::Service s) {
  for (auto& slot : slots_) {
    if (slot.service == s) {
      return &slot;
    }
  }
  return nullptr;
}

void RespondRunner::report(Slot& slot, Result result, const std::string& reason) {
  if (slot.reported || !slot.busy) {
    return;
  }
  slot.reported = true;
  slot.action_end.reset();
  slot.fail_at.reset();
  slot.trace.outcome(result, reason);
}

void RespondRunner::on_request(Slot& slot) {
  slot.busy = true;
  slot.reported = false;
  slot.last_reason = core::Reason::None;
  slot.trace.begin(++started_, slot.service);
  slot.trace.note("request", "request ACTIVE");
  slot.decision = config_.fail_plan.decide(slot.trace.number());
  if (slot.decision.step == FailStep::Accept) {
    inject(slot);
    return;
  }
  if (auto refused = link_.accept(slot.service)) {
    slot.trace.note("refused", *refused);
    report(slot, Result::Fail, "accept refused: " + *refused);
    return;
  }
  const auto& actions = config_.action;
  const auto index = std::min<std::size_t>(slot.trace.number() - 1, actions.size() - 1);
  const auto now = Clock::now();
  slot.action_end = now + actions[index];
  if (slot.decision.step == FailStep::Active) {
    slot.fail_at = now + actions[index] / 2;
  }
}

void RespondRunner::inject(Slot& slot) {
  const auto refused = link_.fail(slot.service);
  const std::string where = std::string(to_string(slot.decision.step));
  slot.trace.note("inject",
                  "response -> FAIL at " + where + (refused ? " refused: " + *refused : ""));
  report(slot, Result::Fail, "injected FAIL at " + where);
}

void RespondRunner::on_timers(Slot& slot, TimePoint now) {
  if (slot.fail_at && now >= *slot.fail_at) {
    slot.fail_at.reset();
    inject(slot);
  }
  if (slot.action_end && now >= *slot.action_end) {
    slot.action_end.reset();
    if (slot.decision.step == FailStep::Complete) {
      inject(slot);
      return;
    }
    // The door/chuck is where the service puts it before COMPLETE is
    // reported, so the acknowledgement finds the new precondition in place.
    move_door_or_chuck(slot);
    if (auto refused = link_.complete(slot.service)) {
      slot.trace.note("refused", *refused);
    }
  }
}

// The requester's liveliness lost or back: every slot hears of it.
void RespondRunner::on_peer_link(const LinkEvent& e) {
  const bool lost = e.kind == LinkEvent::Kind::CounterpartLost;
  peer_lost_ = lost;
  for (auto& slot : slots_) {
    if (lost) {
      slot.peer = InteractionState::Unavailable;
    }
    if (&slot == &slots_.front() || slot.busy) {
      slot.trace.note(lost ? "peer_lost" : "peer_restored", e.detail);
    }
    if (!lost) continue;
    // A requester that leaves right after COMPLETE (its process exits) may
    // never be seen READY again: the handshake's outcome is known and it is
    // over, or `respond --count` would wait for good.
    const bool outcome_known = slot.busy && slot.reported;
    report(slot, Result::Fail, "requester lost (no heartbeat within the lease)");
    if (outcome_known) close(slot);
  }
}

void RespondRunner::on_event(const LinkEvent& e) {
  if (e.kind == LinkEvent::Kind::CounterpartLost ||
      e.kind == LinkEvent::Kind::CounterpartRestored) {
    on_peer_link(e);
    return;
  }
  const bool pairing = e.kind == LinkEvent::Kind::Excluded || e.kind == LinkEvent::Kind::Readmitted;
  if ((e.kind == LinkEvent::Kind::Notice || pairing) && !e.detail.empty()) {
    context_.err.line("mtc respond: " + e.detail);
    return;
  }
  Slot* slot = slot_for(e.service);
  if (slot == nullptr) {
    return;
  }
  if (e.kind == LinkEvent::Kind::RequestObserved) {
    // A new request while the last handshake still looks open means its
    // closing READY was overwritten by this ACTIVE (KEEP_LAST 1): close it.
    if (slot->busy && slot->reported) {
      close(*slot);
    }
    if (!slot->busy) {
      on_request(*slot);
    }
    return;
  }
  if (e.kind == LinkEvent::Kind::Aborted) {
    report(*slot, Result::Fail, std::string(core::describe(e.reason)));
    return;
  }
  if (e.reason != core::Reason::None && e.notice != core::Notice::Rejected) {
    slot->last_reason = e.reason;
  }
  on_state(*slot, e);
}

// A new value of our response or of the requester's request.
void RespondRunner::on_state(Slot& slot, const LinkEvent& e) {
  if (e.kind == LinkEvent::Kind::OwnState && e.state != slot.own) {
    slot.own = e.state;
    if (e.state == InteractionState::Fail) {
      slot.failed_at = Clock::now();
    }
    slot.trace.transition(true, e);
    if (e.state == InteractionState::Complete) {
      report(slot, Result::Complete, "");
    }
    if (e.state == InteractionState::Fail) {
      report(slot, Result::Fail,
             slot.last_reason != core::Reason::None ? std::string(core::describe(slot.last_reason))
                                                    : "response FAIL");
    }
  } else if (e.kind == LinkEvent::Kind::CounterpartState && e.state != slot.peer) {
    slot.peer = e.state;
    slot.trace.transition(false, e);
  }
}

// Recovery and cycle closing, re-checked after every event and timer.
void RespondRunner::maintain(Slot& slot) {
  // No recovery while the requester is gone (scenario 6: meet again in FAIL).
  if (slot.own == InteractionState::Fail && !peer_lost_) {
    link_.recover(slot.service);
  }
  if (slot.busy && slot.reported && idle(slot.own) && idle(slot.peer)) {
    close(slot);
  }
}

void RespondRunner::close(Slot& slot) {
  slot.busy = false;
  ++closed_;
  slot.trace.note("closed", "response " + std::string(core::to_string(slot.own)) + ", request " +
                                std::string(core::to_string(slot.peer)));
}

// The door/chuck reaches the position the service was asked for.
void RespondRunner::move_door_or_chuck(Slot& slot) {
  const auto& eq = config_.equipment;
  const bool door =
      slot.service == core::Service::OpenDoor || slot.service == core::Service::CloseDoor;
  const bool chuck =
      slot.service == core::Service::OpenChuck || slot.service == core::Service::CloseChuck;
  if (door && eq.door_state) {
    const auto s =
        slot.service == core::Service::OpenDoor ? core::DoorState::Open : core::DoorState::Closed;
    link_.set_door_state(s);
    slot.trace.note("door_state", std::string(core::to_string(s)));
  } else if (chuck && eq.chuck_state) {
    const auto s = slot.service == core::Service::OpenChuck ? core::ChuckState::Open
                                                            : core::ChuckState::Closed;
    link_.set_chuck_state(s);
    slot.trace.note("chuck_state", std::string(core::to_string(s)));
  }
}

RespondRunner::TimePoint RespondRunner::next_wake() const {
  auto wake = Clock::now() + std::chrono::hours(1);
  for (const auto& slot : slots_) {
    if (slot.action_end) {
      wake = std::min(wake, *slot.action_end);
    }
    if (slot.fail_at) {
      wake = std::min(wake, *slot.fail_at);
    }
    const auto retry =
        slot.failed_at + config_.equipment.fail_ack_timeout + std::chrono::milliseconds(50);
    if (slot.own == InteractionState::Fail && retry > Clock::now()) {
      wake = std::min(wake, retry);
    }
  }
  return wake;
}

int RespondRunner::run() {
  for (auto& slot : slots_) {
    if (config_.not_ready) {
      link_.set_ready(slot.service, false);
    }
    slot.own = link_.state(slot.service);
  }
  while (!context_.shutdown.requested() && (config_.count == 0 || closed_ < config_.count)) {
    if (auto e = events_.pop_until(next_wake())) {
      on_event(*e);
    }
    const auto now = Clock::now();
    for (auto& slot : slots_) {
      on_timers(slot, now);
      maintain(slot);
    }
  }
  JsonLine line;
  if (config_.equipment.common.json) {
    context_.out.line(line.field("event", "stopped").field("handshakes", closed_).str());
  } else {
    context_.out.line("stopped after " + std::to_string(closed_) + " handshake(s)");
  }
  return ExitOk;
}

}  // namespace mtc::cli
