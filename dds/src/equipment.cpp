// Equipment: declaration, lifecycle and the thread-safe command surface.
// Commands are posted to the executor; the machines are never touched here.
#include <algorithm>

#include "equipment_impl.hpp"
#include "mtc/dds/detail/topic_names.hpp"
#include "mtc/qos/participant.hpp"
#include "mtc/qos/presets.hpp"

namespace mtc::dds {

std::string_view to_string(Outcome o) noexcept {
  switch (o) {
    case Outcome::Completed:
      return "COMPLETED";
    case Outcome::Failed:
      return "FAILED";
    case Outcome::TimedOut:
      return "TIMED_OUT";
    case Outcome::CommsLost:
      return "COMMS_LOST";
    case Outcome::Rejected:
      return "REJECTED";
    case Outcome::Excluded:
      return "EXCLUDED";
  }
  return "?";
}

std::string_view to_string(LinkState s) noexcept {
  switch (s) {
    case LinkState::Unpaired:
      return "UNPAIRED";
    case LinkState::Paired:
      return "PAIRED";
    case LinkState::Up:
      return "UP";
    case LinkState::Lost:
      return "LOST";
    case LinkState::Excluded:
      return "EXCLUDED";
  }
  return "?";
}

// Runs fn() -> R on the executor and returns its result as a future.
template <typename R, typename Fn>
std::future<R> EquipmentImpl::run(Fn fn) {
  if (!started.load()) {
    throw ConfigError("Equipment " + options.device_uuid + ": call start() first");
  }
  auto promise = std::make_shared<std::promise<R>>();
  auto future = promise->get_future();
  executor.dispatch([this, promise, fn = std::move(fn)]() mutable {
    try {
      if constexpr (std::is_void_v<R>) {
        fn();
        settle([promise] { promise->set_value(); });
      } else {
        settle([promise, result = fn()] { promise->set_value(result); });
      }
    } catch (...) {
      settle([promise, e = std::current_exception()] { promise->set_exception(e); });
    }
  });
  return future;
}

template <typename Fn>
void EquipmentImpl::run_unawaited(const char* what, Fn fn) {
  if (!started.load()) {
    throw ConfigError("Equipment " + options.device_uuid + ": call start() first");
  }
  executor.dispatch(
      [this, what, fn = std::move(fn)]() mutable { diagnose_throw(what, "failed", fn); });
}

// ------------------------------------------------------------ ServiceHandle

const std::string& ServiceHandle::interface_id() const noexcept {
  return impl_.interfaces[impl_.slots[slot_]->interface_index]->config.id;
}
core::Service ServiceHandle::service() const noexcept {
  return impl_.slots[slot_]->service;
}
core::Role ServiceHandle::role() const noexcept {
  return impl_.slots[slot_]->role;
}
core::InteractionState ServiceHandle::state() const noexcept {
  return impl_.slots[slot_]->snap_state.load();
}
core::InteractionState ServiceHandle::counterpart_state() const noexcept {
  return impl_.slots[slot_]->snap_counterpart.load();
}

namespace {
core::StepResult step_command(EquipmentImpl& impl, std::size_t slot, core::Event event) {
  auto& s = *impl.slots[slot];
  const auto now = SteadyClock::now();
  auto r = impl.apply(s, event, now);
  impl.auto_recover(s, now);
  return r;
}
}  // namespace

std::future<core::StepResult> ServiceHandle::command(core::Event event) {
  auto* impl = &impl_;
  const auto slot = slot_;
  return impl_.run<core::StepResult>(
      [impl, slot, event] { return step_command(*impl, slot, event); });
}

void ServiceHandle::command(core::Event event, OnStep on_result) {
  auto* impl = &impl_;
  const auto slot = slot_;
  impl_.run_unawaited("command", [impl, slot, event, cb = std::move(on_result)] {
    const auto r = step_command(*impl, slot, event);
    if (cb) impl->report("command result", [cb, r] { cb(r); });
  });
}

std::future<core::StepResult> ServiceHandle::fail() {
  return command(core::Event::Fail);
}
std::future<core::StepResult> ServiceHandle::recover(core::InteractionState target) {
  return command(target == core::InteractionState::NotReady ? core::Event::RecoverNotReady
                                                            : core::Event::RecoverReady);
}
std::future<core::StepResult> ServiceHandle::set_ready(bool ready) {
  return command(ready ? core::Event::SetReady : core::Event::SetNotReady);
}
std::future<core::StepResult> Responder::accept() {
  return command(core::Event::Accept);
}
std::future<core::StepResult> Responder::complete() {
  return command(core::Event::Complete);
}
void ServiceHandle::fail(OnStep on_result) {
  command(core::Event::Fail, std::move(on_result));
}
void ServiceHandle::recover(core::InteractionState target, OnStep on_result) {
  command(target == core::InteractionState::NotReady ? core::Event::RecoverNotReady
                                                     : core::Event::RecoverReady,
          std::move(on_result));
}
void ServiceHandle::set_ready(bool ready, OnStep on_result) {
  command(ready ? core::Event::SetReady : core::Event::SetNotReady, std::move(on_result));
}
void Responder::accept(OnStep on_result) {
  command(core::Event::Accept, std::move(on_result));
}
void Responder::complete(OnStep on_result) {
  command(core::Event::Complete, std::move(on_result));
}

void Requester::request(RequestOptions options,
                        std::function<void(const RequestResult&)> on_result) {
  auto* impl = &impl_;
  const auto slot = slot_;
  impl_.run_unawaited("request", [impl, slot, options, cb = std::move(on_result)]() mutable {
    auto& s = *impl->slots[slot];
    impl->check_own_silence();  // before trusting what we last saw
    const auto now = SteadyClock::now();
    auto reject = [&](core::Reason reason) {
      RequestResult r{Outcome::Rejected, reason, {}};
      if (cb) impl->report("request result", [cb, r] { cb(r); });
    };
    if (s.pending) {
      reject(core::Reason::AlreadyActive);
      return;
    }
    PendingRequest p;
    p.callback = std::move(cb);
    p.started = now;
    p.ready_deadline = now + options.wait_for_ready;
    s.pending = std::move(p);
    auto& waiting = impl->waiting_to_issue;
    if (std::find(waiting.begin(), waiting.end(), slot) == waiting.end()) waiting.push_back(slot);
    impl->try_issue(s, now);
  });
}

std::future<RequestResult> Requester::request(RequestOptions options) {
  auto promise = std::make_shared<std::promise<RequestResult>>();
  auto future = promise->get_future();
  request(options, [promise](const RequestResult& r) { promise->set_value(r); });
  return future;
}

// ---------------------------------------------------------------- Equipment

Equipment::Equipment(EquipmentOptions options, EquipmentCallbacks callbacks)
    : impl_(std::make_unique<EquipmentImpl>()) {
  if (auto problem = topics::check_device_uuid(options.device_uuid)) {
    throw ConfigError("Equipment: " + *problem);
  }
  if (options.domain_id < 0 || options.domain_id > qos::kMaxDomainId) {
    throw ConfigError("Equipment: domain id " + std::to_string(options.domain_id) + " outside 0.." +
                      std::to_string(qos::kMaxDomainId));
  }
  try {
    qos::validate(options.timing);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(std::string("Equipment: ") + e.what());
  }
  if (options.pack_callback_writes && !options.inline_steps) {
    throw ConfigError(
        "Equipment: pack_callback_writes needs inline_steps (callbacks that run "
        "with their step)");
  }
  if (!options.security_dir.empty()) {
    if (auto problem = qos::check_security_dir(options.security_dir)) {
      throw ConfigError("Equipment " + options.device_uuid + ": " + *problem);
    }
  }
  if (options.pairing_settle < std::chrono::milliseconds(0) ||
      options.pairing_settle > std::chrono::minutes(1)) {
    throw ConfigError("Equipment: pairing_settle " +
                      std::to_string(options.pairing_settle.count()) + " ms outside 0..60000 ms");
  }
  if (options.device_name.empty()) options.device_name = options.device_uuid;
  // Callbacks stay on the executor thread unless inline_steps; set before
  // any thread could read it.
  impl_->defer_reports = !options.inline_steps && !options.steps_on_executor;
  // Only inline_steps' callbacks promise never to block: they alone may hold
  // back the step's writes until they return.
  impl_->writes_wait_for_callbacks = options.pack_callback_writes;
  impl_->options = std::move(options);
  impl_->callbacks = std::move(callbacks);
}

Equipment::~Equipment() {
  impl_->shutdown();
}

InterfaceSlot& EquipmentImpl::interface_slot(const std::string& id) const {
  for (const auto& itf : interfaces) {
    if (itf->config.id == id) return *itf;
  }
  throw ConfigError("Equipment " + options.device_uuid + ": no interface \"" + id + "\"");
}

void Equipment::add_interface(InterfaceConfig config) {
  if (impl_->started) throw ConfigError("add_interface after start()");
  if (auto problem = topics::check_interface_id(config.id)) throw ConfigError(*problem);
  if (impl_->interfaces.size() >= kMaxInterfacesPerDevice) {
    throw ConfigError("interface \"" + config.id + "\": an equipment has at most " +
                      std::to_string(kMaxInterfacesPerDevice) +
                      " interfaces (its announcement's bound on the wire)");
  }
  for (const auto& itf : impl_->interfaces) {
    if (itf->config.id == config.id) {
      throw ConfigError("interface \"" + config.id + "\" declared twice");
    }
  }
  if (!config.counterpart.device_uuid.empty()) {
    if (auto problem = topics::check_device_uuid(config.counterpart.device_uuid)) {
      throw ConfigError("counterpart of " + config.id + ": " + *problem);
    }
    if (config.counterpart.device_uuid == impl_->options.device_uuid) {
      throw ConfigError("interface " + config.id + " cannot pair with its own device");
    }
  }
  if (config.timing) {
    try {
      qos::validate(*config.timing);
    } catch (const std::invalid_argument& e) {
      throw ConfigError("interface " + config.id + ": " + e.what());
    }
  }
  if (config.name.empty()) config.name = config.id;
  auto itf = std::make_unique<InterfaceSlot>();
  itf->state_item.id = topics::interface_state_item_id(config.id);
  detail::for_door_and_chuck([&](auto tag) {
    using State = typename decltype(tag)::type;
    using Traits = detail::DoorChuck<State>;
    auto& dc = itf->door_chuck_item<State>();
    dc.published = Traits::published(config);
    dc.state = Traits::initial(config);
    dc.item.id = Traits::item_id(config.id);
    // A door/chuck this equipment does not control never blocks its
    // services (UNLATCHED permits both directions).
    Traits::apply(itf->hook, dc.published ? dc.state : State::Unlatched);
  });
  itf->config = std::move(config);
  impl_->interfaces.push_back(std::move(itf));
}

std::size_t EquipmentImpl::add_slot(const std::string& interface_id, core::Service service,
                                    core::Role role, const ServiceOptions& opts) {
  if (started) throw ConfigError("add_requester/add_responder after start()");
  auto& itf = interface_slot(interface_id);
  for (auto index : itf.services) {
    if (slots[index]->service == service && slots[index]->role == role) {
      throw ConfigError("interface " + interface_id + " already has the " +
                        std::string(core::to_string(role)) + " of " +
                        std::string(core::to_string(service)));
    }
  }
  auto slot = std::make_unique<ServiceSlot>();
  slot->interface_index =
      static_cast<std::size_t>(std::find_if(interfaces.begin(), interfaces.end(),
                                            [&](const auto& p) { return p.get() == &itf; }) -
                               interfaces.begin());
  slot->service = service;
  slot->role = role;
  const auto side =
      role == core::Role::Requester ? core::SubType::Request : core::SubType::Response;
  slot->topic = detail::interaction_index(side, service);
  slot->options = opts;
  slot->item.id = topics::interaction_item_id(interface_id, service, side);
  const auto index = slots.size();
  itf.services.push_back(index);
  slots.push_back(std::move(slot));
  return index;
}

Requester& Equipment::add_requester(const std::string& interface_id, core::Service service,
                                    ServiceOptions options) {
  const auto index = impl_->add_slot(interface_id, service, core::Role::Requester, options);
  auto& slot = *impl_->slots[index];
  slot.handle.reset(new Requester(*impl_, index));
  return static_cast<Requester&>(*slot.handle);
}

Responder& Equipment::add_responder(const std::string& interface_id, core::Service service,
                                    ResponderCallbacks callbacks, ServiceOptions options) {
  const auto index = impl_->add_slot(interface_id, service, core::Role::Responder, options);
  auto& slot = *impl_->slots[index];
  slot.responder_callbacks = std::move(callbacks);
  slot.handle.reset(new Responder(*impl_, index));
  return static_cast<Responder&>(*slot.handle);
}

void Equipment::start() {
  if (impl_->started) throw ConfigError("Equipment::start() called twice");
  if (impl_->interfaces.empty()) {
    throw ConfigError("Equipment " + impl_->options.device_uuid + ": no interface declared");
  }
  // Callbacks run on the executor as soon as create_entities() has started
  // it (the pairing with a configured counterpart, the first samples) and
  // may call this Equipment back, so it counts as started from here on.
  impl_->started = true;
  impl_->name_configured_counterparts();  // the first samples name them
  try {
    impl_->create_entities();
  } catch (...) {
    impl_->started = false;
    throw;
  }
}

std::future<void> Equipment::set_interface_state(const std::string& interface_id,
                                                 core::InterfaceState state) {
  auto* impl = impl_.get();
  auto* itf = &impl->interface_slot(interface_id);
  return impl->run<void>([impl, itf, state] {
    const auto now = SteadyClock::now();
    const auto batch = itf->model_to_change().set_interface_state(state, now);
    impl->publish_interface_state(*itf, topics::realtime_ns());
    impl->handle_batch(*itf, batch);
  });
}

// The new state moves the responders' precondition hook, is published as a
// change, and may turn READY responders NOT_READY or back (reevaluate).
template <typename State>
std::future<void> EquipmentImpl::set_door_chuck(const std::string& interface_id, State state) {
  auto* itf = &interface_slot(interface_id);
  if (!itf->door_chuck_item<State>().published) {
    throw ConfigError("interface " + interface_id + " does not publish " +
                      std::string(detail::DoorChuck<State>::kItemType));
  }
  return run<void>([this, itf, state] {
    itf->door_chuck_item<State>().state = state;
    detail::DoorChuck<State>::apply(itf->hook, state);
    publish_door_chuck<State>(*itf, topics::realtime_ns());
    handle_batch(*itf, itf->model_to_change().reevaluate(SteadyClock::now()));
  });
}

std::future<void> Equipment::set_door_state(const std::string& interface_id,
                                            core::DoorState state) {
  return impl_->set_door_chuck(interface_id, state);
}

std::future<void> Equipment::set_chuck_state(const std::string& interface_id,
                                             core::ChuckState state) {
  return impl_->set_door_chuck(interface_id, state);
}

void Equipment::post(std::function<void()> task) {
  auto* impl = impl_.get();
  if (impl->defer_reports && impl->started.load()) {
    // Application code, in order with the callbacks.
    impl->report("posted task", std::move(task));
    return;
  }
  impl->run<void>([impl, task = std::move(task)] { impl->guard_callback("posted task", task); });
}

Requester* Equipment::requester(const std::string& interface_id,
                                core::Service service) const noexcept {
  for (const auto& s : impl_->slots) {
    if (s->service == service && s->role == core::Role::Requester &&
        impl_->interfaces[s->interface_index]->config.id == interface_id) {
      return static_cast<Requester*>(s->handle.get());
    }
  }
  return nullptr;
}

Responder* Equipment::responder(const std::string& interface_id,
                                core::Service service) const noexcept {
  for (const auto& s : impl_->slots) {
    if (s->service == service && s->role == core::Role::Responder &&
        impl_->interfaces[s->interface_index]->config.id == interface_id) {
      return static_cast<Responder*>(s->handle.get());
    }
  }
  return nullptr;
}

LinkState Equipment::link_state(const std::string& interface_id) const {
  return impl_->interface_slot(interface_id).link.load();
}

std::optional<CounterpartSpec> Equipment::counterpart(const std::string& interface_id) const {
  auto& itf = impl_->interface_slot(interface_id);
  std::lock_guard<std::mutex> lock(impl_->binding_mutex);
  if (itf.cp_uuid.empty() || itf.cp_interface.empty()) return std::nullopt;
  return CounterpartSpec{itf.cp_uuid, itf.cp_interface};
}

const EquipmentOptions& Equipment::options() const noexcept {
  return impl_->options;
}
Middleware Equipment::middleware() const noexcept {
  return impl_->participant ? impl_->participant->middleware() : impl_->options.middleware;
}
bool Equipment::started() const noexcept {
  return impl_->started;
}

Traffic Equipment::traffic() const {
  Traffic t;
  t.values_written = impl_->values_written.load(std::memory_order_relaxed);
  t.heartbeats_written = impl_->heartbeats_written.load(std::memory_order_relaxed);
  t.reannounce_passes = impl_->reannounce_passes.load(std::memory_order_relaxed);
  t.endpoints_reannounced = impl_->endpoints_reannounced.load(std::memory_order_relaxed);
  if (!impl_->started) return t;
  for (const auto& g : impl_->groups) {
    if (!g->tap) continue;
    const auto counts = g->tap->counts();
    t.values_received += counts.values;
    t.heartbeats_received += counts.heartbeats;
  }
  return t;
}

}  // namespace mtc::dds
