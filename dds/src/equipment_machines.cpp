// Equipment: driving the core machines on the executor thread, turning their
// StepResults into publications, application callbacks and request outcomes.
#include <algorithm>
#include <iostream>

#include "equipment_impl.hpp"
#include "mtc/dds/detail/topic_names.hpp"

namespace mtc::dds {

namespace {

bool idle(core::InteractionState s) {
  return s == core::InteractionState::Ready || s == core::InteractionState::NotReady;
}

}  // namespace

void EquipmentImpl::diagnostic(const std::string& text) {
  const auto say = [this, text] {
    if (callbacks.on_diagnostic) {
      try {
        callbacks.on_diagnostic(text);
        return;
      } catch (...) {
      }
    }
    std::cerr << "mtc::dds::Equipment " << options.device_uuid << ": " << text << '\n';
  };
  settle(say, Settles::Callback);  // a report, never through guard_callback
}

ServiceSlot* EquipmentImpl::slot_for(InterfaceSlot& itf, core::Service service,
                                     core::Role role) const {
  for (auto index : itf.services) {
    auto& s = *slots[index];
    if (s.service == service && s.role == role) return &s;
  }
  return nullptr;
}

core::StepResult EquipmentImpl::apply(ServiceSlot& slot, core::Event event,
                                      SteadyClock::time_point now, std::int64_t source_ns,
                                      std::int64_t receive_ns) {
  auto& itf = *interfaces[slot.interface_index];
  const auto r = itf.model_to_change().machine(slot.service, slot.role)->step(event, now);
  handle_result(slot, r, source_ns, receive_ns);
  return r;
}

void EquipmentImpl::handle_batch(InterfaceSlot& itf, const core::StepBatch& batch) {
  for (const auto& r : batch) {
    if (auto* slot = slot_for(itf, r.service, r.role)) handle_result(*slot, r, 0, 0);
  }
  const auto now = SteadyClock::now();
  for (auto index : itf.services) auto_recover(*slots[index], now);
}

void EquipmentImpl::handle_result(ServiceSlot& slot, const core::StepResult& r,
                                  std::int64_t source_ns, std::int64_t receive_ns) {
  auto& itf = *interfaces[slot.interface_index];
  const auto* machine = itf.model().machine(slot.service, slot.role);
  TransitionEvent ev;
  ev.step_time_ns = topics::realtime_ns();
  if (r.changed()) {
    publish_interaction(slot, ev.step_time_ns);
    ev.publish_time_ns = topics::realtime_ns();
  }
  slot.snap_state = machine->state();
  slot.snap_counterpart = machine->counterpart();
  if (r.entered_fail()) {
    slot.idle_failure = idle(r.previous);
    slot.fail_reason = r.reason;
  }
  if (r.changed() || r.notice != core::Notice::None) {
    ev.interface_id = itf.config.id;
    ev.step = r;
    ev.counterpart = machine->counterpart();
    ev.trigger_source_time_ns = source_ns;
    ev.trigger_receive_time_ns = receive_ns;
    if (callbacks.on_transition) {
      report("on_transition", [this, ev] { callbacks.on_transition(ev); });
    }
  }
  resolve_pending(slot, r);
  if (slot.role != core::Role::Responder) return;
  auto* responder = static_cast<Responder*>(slot.handle.get());
  const auto* cb = &slot.responder_callbacks;
  if (r.notice == core::Notice::RequestObserved) {
    if (!slot.options.auto_accept) {
      if (cb->on_request) report("on_request", [cb, responder] { cb->on_request(*responder); });
    } else if (machine->state() == core::InteractionState::Ready) {
      apply(slot, core::Event::Accept, SteadyClock::now(), source_ns, receive_ns);
    }
  } else if (r.notice == core::Notice::Accepted && r.changed() && slot.options.auto_accept) {
    if (cb->on_request) report("on_request", [cb, responder] { cb->on_request(*responder); });
  }
  const bool was_serving = r.previous == core::InteractionState::Active ||
                           r.previous == core::InteractionState::Complete;
  if (was_serving && r.entered_fail() && r.notice != core::Notice::Failed && cb->on_abort) {
    report("on_abort", [cb, responder, reason = r.reason] { cb->on_abort(*responder, reason); });
  }
}

void EquipmentImpl::auto_recover(ServiceSlot& slot, SteadyClock::time_point now) {
  auto& itf = *interfaces[slot.interface_index];
  const auto* machine = itf.model().machine(slot.service, slot.role);
  if (machine->state() != core::InteractionState::Fail || !machine->fail_acknowledged() ||
      itf.link.load() != LinkState::Up) {
    return;
  }
  bool recover = false;
  switch (options.recovery) {
    case RecoveryPolicy::Manual:
      break;
    case RecoveryPolicy::Always:
      recover = true;
      break;
    case RecoveryPolicy::AfterCommsLoss:
      recover = slot.fail_reason == core::Reason::CommsLost || slot.idle_failure;
      break;
  }
  if (recover) apply(slot, core::Event::RecoverReady, now);
}

void EquipmentImpl::resolve_pending(ServiceSlot& slot, const core::StepResult& r) {
  if (!slot.pending || !slot.pending->issued) return;
  if (r.previous != core::InteractionState::Active || r.current == core::InteractionState::Active) {
    return;
  }
  RequestResult result;
  result.reason = r.reason;
  if (r.notice == core::Notice::Completed) {
    result.outcome = Outcome::Completed;
  } else if (r.reason == core::Reason::CommsLost) {
    result.outcome = Outcome::CommsLost;
  } else if (r.notice == core::Notice::TimedOut) {
    result.outcome = Outcome::TimedOut;
  } else {
    result.outcome = Outcome::Failed;
  }
  result.elapsed = SteadyClock::now() - slot.pending->started;
  auto pending = std::move(*slot.pending);
  slot.pending.reset();
  if (pending.callback) {
    report("request result", [cb = std::move(pending.callback), result] { cb(result); });
  }
}

// Issues a pending request when both sides are READY; otherwise waits until
// its ready deadline, then reports the machine's own rejection.
void EquipmentImpl::try_issue(ServiceSlot& slot, SteadyClock::time_point now) {
  if (!slot.pending || slot.pending->issued) return;
  auto& itf = *interfaces[slot.interface_index];
  if (itf.link.load() == LinkState::Excluded) {
    end_pending(slot, Outcome::Excluded, core::Reason::None);
    return;
  }
  const auto* machine = itf.model().machine(slot.service, slot.role);
  // The response must name this interface: a responder not paired yet
  // reads no request, one paired with another never will (exclude()).
  const bool both_ready = machine->state() == core::InteractionState::Ready &&
                          machine->counterpart() == core::InteractionState::Ready;
  const bool addressed = slot.role != core::Role::Requester || slot.addressed;
  if (!(both_ready && addressed) && now < slot.pending->ready_deadline) return;
  if (both_ready && !addressed) {
    end_pending(slot, Outcome::Rejected, core::Reason::CounterpartBusy);
    return;
  }
  slot.pending->issued = true;  // set first: the step below may already resolve it
  const auto r = apply(slot, core::Event::Request, now);
  if (r.notice != core::Notice::RequestIssued && slot.pending) {
    end_pending(slot, Outcome::Rejected, r.reason);
  }
}

void EquipmentImpl::end_pending(ServiceSlot& slot, Outcome outcome, core::Reason reason) {
  RequestResult result{outcome, reason, SteadyClock::now() - slot.pending->started};
  auto pending = std::move(*slot.pending);
  slot.pending.reset();
  if (pending.callback) {
    report("request result", [cb = std::move(pending.callback), result] { cb(result); });
  }
}

SteadyClock::time_point EquipmentImpl::next_wake() {
  auto wake = std::min(next_silence_check(), next_election());
  wake = std::min(wake, reannounce.next());
  for (const auto index : changed_interfaces) {
    auto& itf = *interfaces[index];
    itf.change_taken();
    interface_deadlines.set(index, itf.next_deadline());
  }
  changed_interfaces.clear();
  wake = std::min(wake, interface_deadlines.earliest());
  const auto issued_or_gone = [this](std::size_t index) {
    const auto& pending = slots[index]->pending;
    return !pending || pending->issued;
  };
  waiting_to_issue.erase(
      std::remove_if(waiting_to_issue.begin(), waiting_to_issue.end(), issued_or_gone),
      waiting_to_issue.end());
  for (const auto index : waiting_to_issue) {
    wake = std::min(wake, slots[index]->pending->ready_deadline);
  }
  return wake;
}

void EquipmentImpl::on_wake(SteadyClock::time_point now) {
  check_silence();
  elect_due(now);
  reannounce_due(now);
  for (auto& itf : interfaces) {
    // At most one limit per machine per on_tick; bounded loop for safety.
    for (int i = 0; i < 32 && itf->next_deadline() <= now; ++i) {
      handle_batch(*itf, itf->model_to_change().on_tick(now));
    }
  }
  for (auto& s : slots) {
    if (s->pending && !s->pending->issued && now >= s->pending->ready_deadline) try_issue(*s, now);
  }
}

}  // namespace mtc::dds
