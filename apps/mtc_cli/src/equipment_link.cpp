// EquipmentLink over mtc::dds::Equipment: one device, one interface, one
// side of the configured services. Callbacks (on the runtime's executor
// thread) only translate and queue; commands wait for the executor to apply
// them, which is safe because they are never called from a callback.
#include "equipment_link.hpp"

#include <algorithm>
#include <utility>

#include "mtc/dds/equipment.hpp"

namespace mtc::cli {

namespace {

qos::Transport to_transport(const EquipmentConfig& c) {
  // --drop-percent needs the fault-injecting test transport.
  return c.drop_percent > 0 ? qos::Transport::LoopbackTest : c.transport;
}

Result to_result(const dds::RequestResult& r, core::InteractionState counterpart) {
  switch (r.outcome) {
    case dds::Outcome::Completed:
      return Result::Complete;
    case dds::Outcome::Failed:
      return Result::Fail;
    case dds::Outcome::TimedOut:
      return Result::Timeout;
    case dds::Outcome::CommsLost:
      return Result::CommsLost;
    case dds::Outcome::Rejected:
      return counterpart == core::InteractionState::NotReady ? Result::NotReady : Result::Fail;
    case dds::Outcome::Excluded:
      return Result::Excluded;
  }
  return Result::Fail;
}

EquipmentLink::Refusal refusal(std::future<core::StepResult> f) {
  const core::StepResult r = f.get();
  if (!r.rejected()) {
    return std::nullopt;
  }
  return std::string(core::describe(r.reason));
}

}  // namespace

struct EquipmentLink::Impl {
  Impl(EquipmentConfig c, core::Role r, EventQueue& q) : config(std::move(c)), role(r), events(q) {}

  bool serves(core::Service s) const {
    return std::find(config.services.begin(), config.services.end(), s) != config.services.end();
  }
  dds::ServiceHandle& handle(core::Service s) const {
    auto* h = role == core::Role::Requester
                  ? static_cast<dds::ServiceHandle*>(equipment->requester(config.interface_id, s))
                  : static_cast<dds::ServiceHandle*>(equipment->responder(config.interface_id, s));
    if (h == nullptr) {
      throw std::logic_error("service not configured on this interface");
    }
    return *h;
  }
  dds::Responder& responder(core::Service s) const {
    return static_cast<dds::Responder&>(handle(s));
  }

  void on_transition(const dds::TransitionEvent& t);
  void on_counterpart_value(const dds::ObservedValue& v);
  void on_link(const dds::LinkEvent& l);
  void note_interface_state(const dds::ObservedValue& v);
  dds::EquipmentCallbacks callbacks();
  void declare();

  EquipmentConfig config;
  core::Role role;
  EventQueue& events;
  bool lost = false;
  std::optional<core::InterfaceState> counterpart_interface_state;
  std::unique_ptr<dds::Equipment> equipment;
};

void EquipmentLink::Impl::on_transition(const dds::TransitionEvent& t) {
  LinkEvent e;
  e.service = t.step.service;
  e.notice = t.step.notice;
  e.reason = t.step.reason;
  e.state = t.step.current;
  e.reception_time_ns = t.publish_time_ns != 0 ? t.publish_time_ns : t.step_time_ns;
  e.kind = t.step.changed() ? LinkEvent::Kind::OwnState : LinkEvent::Kind::Notice;
  events.push(std::move(e));
}

void EquipmentLink::Impl::on_counterpart_value(const dds::ObservedValue& v) {
  if (v.kind() == dds::ItemKind::InterfaceState) {
    note_interface_state(v);
    return;
  }
  if (v.kind() != dds::ItemKind::Interaction || !v.service || !v.sub_type || !serves(*v.service)) {
    return;
  }
  const auto wanted =
      role == core::Role::Requester ? core::SubType::Response : core::SubType::Request;
  if (*v.sub_type != wanted) {
    return;
  }
  LinkEvent e;
  e.kind = LinkEvent::Kind::CounterpartState;
  e.service = *v.service;
  e.state = v.state.interaction().value_or(core::InteractionState::Unavailable);
  e.source_time_ns = v.source_time_ns;
  e.sequence_number = v.sequence_number;
  e.redelivered = v.redelivered;
  e.reception_time_ns = v.reception_time_ns;
  events.push(std::move(e));
}

// The counterpart's INTERFACE_STATE, reported when it changes: DISABLED is
// why its services stay NOT_READY (Part 5), which a user should be told.
void EquipmentLink::Impl::note_interface_state(const dds::ObservedValue& v) {
  const auto state = v.state.interface_state();
  if (!state || state == counterpart_interface_state) {
    return;
  }
  counterpart_interface_state = state;
  LinkEvent e;
  e.kind = LinkEvent::Kind::Notice;
  e.reception_time_ns = v.reception_time_ns;
  e.detail = "counterpart " + v.device_uuid + " interface " + v.interface_id + " is " +
             std::string(core::to_string(*state)) +
             (*state == core::InterfaceState::Disabled
                  ? " (INTERFACE_STATE DISABLED: all its services NOT_READY)"
                  : "");
  events.push(std::move(e));
}

void EquipmentLink::Impl::on_link(const dds::LinkEvent& l) {
  LinkEvent e;
  e.reception_time_ns = l.time_ns;
  if (l.current == dds::LinkState::Excluded) {
    e.kind = LinkEvent::Kind::Excluded;
    e.detail = config.device_uuid + "/" + config.interface_id + ": " + l.cause;
    events.push(std::move(e));
  } else if (l.previous == dds::LinkState::Excluded) {
    e.kind = LinkEvent::Kind::Readmitted;
    e.detail = config.device_uuid + "/" + config.interface_id + ": " + l.cause;
    events.push(std::move(e));
  } else if (l.current == dds::LinkState::Lost && !lost) {
    lost = true;
    e.kind = LinkEvent::Kind::CounterpartLost;
    e.detail =
        l.counterpart_uuid + ": " + l.cause + " after " +
        std::to_string(std::chrono::duration_cast<std::chrono::milliseconds>(l.silence).count()) +
        " ms of silence";
    events.push(std::move(e));
  } else if (l.current == dds::LinkState::Up && lost) {
    lost = false;
    e.kind = LinkEvent::Kind::CounterpartRestored;
    e.detail = l.counterpart_uuid;
    events.push(std::move(e));
  }
}

dds::EquipmentCallbacks EquipmentLink::Impl::callbacks() {
  dds::EquipmentCallbacks cb;
  cb.on_transition = [this](const dds::TransitionEvent& t) { on_transition(t); };
  cb.on_counterpart_value = [this](const dds::ObservedValue& v) { on_counterpart_value(v); };
  cb.on_link = [this](const dds::LinkEvent& l) { on_link(l); };
  cb.on_diagnostic = [this](const std::string& text) {
    LinkEvent e;
    e.kind = LinkEvent::Kind::Notice;
    e.detail = text;
    events.push(std::move(e));
  };
  return cb;
}

void EquipmentLink::Impl::declare() {
  dds::InterfaceConfig itf;
  itf.id = config.interface_id;
  itf.type = config.interface_type;
  itf.counterpart.device_uuid = config.counterpart;
  itf.counterpart.interface_id = config.counterpart_interface;
  if (config.door_state) {
    itf.publishes_door_state = true;
    itf.initial_door_state = *config.door_state;
  }
  if (config.chuck_state) {
    itf.publishes_chuck_state = true;
    itf.initial_chuck_state = *config.chuck_state;
  }
  equipment->add_interface(itf);
  dds::ServiceOptions options;
  options.limits.fail_ack = config.fail_ack_timeout;
  options.auto_accept = false;
  options.start_ready = !config.stay_not_ready;
  for (auto s : config.services) {
    if (role == core::Role::Requester) {
      equipment->add_requester(config.interface_id, s, options);
      continue;
    }
    dds::ResponderCallbacks rc;
    rc.on_request = [this](dds::Responder& r) {
      LinkEvent e;
      e.kind = LinkEvent::Kind::RequestObserved;
      e.service = r.service();
      events.push(std::move(e));
    };
    rc.on_abort = [this](dds::Responder& r, core::Reason reason) {
      LinkEvent e;
      e.kind = LinkEvent::Kind::Aborted;
      e.service = r.service();
      e.reason = reason;
      events.push(std::move(e));
    };
    equipment->add_responder(config.interface_id, s, std::move(rc), options);
  }
}

EquipmentLink::EquipmentLink(const EquipmentConfig& config, core::Role role, EventQueue& events)
    : impl_(std::make_unique<Impl>(config, role, events)) {
  dds::EquipmentOptions options;
  options.domain_id = config.common.domain;
  options.device_uuid = config.device_uuid;
  options.device_name = config.device_name;
  options.timing = config.timing;
  options.transport = to_transport(config);
  options.middleware = config.middleware;
  options.security_dir = config.common.security_dir;
  options.faults.drop_data_percent = static_cast<std::uint8_t>(config.drop_percent);
  options.profile = config.profile;
  options.pairing_settle = config.pairing_settle;
  // The tool has no partial actions to reset: clear every acknowledged FAIL.
  // A --not-ready responder clears FAIL itself, to NOT_READY (the runtime's
  // automatic recovery would make it READY).
  options.recovery =
      config.stay_not_ready ? dds::RecoveryPolicy::Manual : dds::RecoveryPolicy::Always;
  impl_->equipment = std::make_unique<dds::Equipment>(options, impl_->callbacks());
  impl_->declare();
  impl_->equipment->start();
  if (config.disabled) {
    impl_->equipment->set_interface_state(config.interface_id, core::InterfaceState::Disabled)
        .get();
  }
}

EquipmentLink::~EquipmentLink() = default;

EquipmentLink::Refusal EquipmentLink::request(core::Service s, std::chrono::milliseconds wait) {
  auto& requester = static_cast<dds::Requester&>(impl_->handle(s));
  dds::RequestOptions options;
  options.wait_for_ready = wait;
  Impl* impl = impl_.get();
  requester.request(options, [impl, s, &requester](const dds::RequestResult& r) {
    LinkEvent e;
    e.kind = LinkEvent::Kind::RequestDone;
    e.service = s;
    e.reason = r.reason;
    e.result = to_result(r, requester.counterpart_state());
    impl->events.push(std::move(e));
  });
  return std::nullopt;
}

EquipmentLink::Refusal EquipmentLink::accept(core::Service s) {
  return refusal(impl_->responder(s).accept());
}
EquipmentLink::Refusal EquipmentLink::complete(core::Service s) {
  return refusal(impl_->responder(s).complete());
}
EquipmentLink::Refusal EquipmentLink::fail(core::Service s) {
  return refusal(impl_->handle(s).fail());
}
EquipmentLink::Refusal EquipmentLink::recover(core::Service s) {
  return refusal(impl_->handle(s).recover(impl_->config.stay_not_ready
                                              ? core::InteractionState::NotReady
                                              : core::InteractionState::Ready));
}
EquipmentLink::Refusal EquipmentLink::set_ready(core::Service s, bool ready) {
  return refusal(impl_->handle(s).set_ready(ready));
}

void EquipmentLink::set_door_state(core::DoorState state) {
  impl_->equipment->set_door_state(impl_->config.interface_id, state).get();
}

void EquipmentLink::set_chuck_state(core::ChuckState state) {
  impl_->equipment->set_chuck_state(impl_->config.interface_id, state).get();
}

core::InteractionState EquipmentLink::state(core::Service s) const {
  return impl_->handle(s).state();
}

}  // namespace mtc::cli
