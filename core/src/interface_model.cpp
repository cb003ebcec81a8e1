#include "mtc/core/interface_model.hpp"

namespace mtc::core {

InterfaceModel::InterfaceModel(InterfaceType type, const MachineOptions& options,
                               const ServicePreconditions* hook) noexcept
    : type_(type), options_(options), hook_(hook) {}

bool InterfaceModel::add_requester(Service service) noexcept {
  return add_requester(service, options_);
}
bool InterfaceModel::add_responder(Service service) noexcept {
  return add_responder(service, options_);
}

bool InterfaceModel::add_requester(Service service, const MachineOptions& options) noexcept {
  const std::size_t i = index(service);
  if (i >= requesters_.size() || requesters_[i]) return false;
  requesters_[i].emplace(service, options, hook_);
  if (state_ != InterfaceState::Enabled) requesters_[i]->disable(TimePoint{});
  note_added(Role::Requester, service);
  return true;
}

bool InterfaceModel::add_responder(Service service, const MachineOptions& options) noexcept {
  const std::size_t i = index(service);
  if (i >= responders_.size() || responders_[i]) return false;
  responders_[i].emplace(service, options, hook_);
  if (state_ != InterfaceState::Enabled) responders_[i]->disable(TimePoint{});
  note_added(Role::Responder, service);
  return true;
}

void InterfaceModel::note_added(Role role, Service service) noexcept {
  const auto offset = role == Role::Requester ? 0 : kAllServices.size();
  present_[present_count_++] = static_cast<std::uint8_t>(offset + index(service));
}

const ServiceMachine& InterfaceModel::present(std::size_t k) const noexcept {
  const std::size_t code = present_[k];
  if (code < kAllServices.size()) return *requesters_[code];
  return *responders_[code - kAllServices.size()];
}

Requester* InterfaceModel::requester(Service service) noexcept {
  const std::size_t i = index(service);
  return i < requesters_.size() && requesters_[i] ? &*requesters_[i] : nullptr;
}
const Requester* InterfaceModel::requester(Service service) const noexcept {
  const std::size_t i = index(service);
  return i < requesters_.size() && requesters_[i] ? &*requesters_[i] : nullptr;
}
Responder* InterfaceModel::responder(Service service) noexcept {
  const std::size_t i = index(service);
  return i < responders_.size() && responders_[i] ? &*responders_[i] : nullptr;
}
const Responder* InterfaceModel::responder(Service service) const noexcept {
  const std::size_t i = index(service);
  return i < responders_.size() && responders_[i] ? &*responders_[i] : nullptr;
}
ServiceMachine* InterfaceModel::machine(Service service, Role role) noexcept {
  if (role == Role::Requester) return requester(service);
  return responder(service);
}
const ServiceMachine* InterfaceModel::machine(Service service, Role role) const noexcept {
  if (role == Role::Requester) return requester(service);
  return responder(service);
}

template <typename Fn>
StepBatch InterfaceModel::for_each_machine(Fn&& fn) noexcept {
  StepBatch batch;
  for (auto& m : requesters_) {
    if (m) batch.push(fn(static_cast<ServiceMachine&>(*m)));
  }
  for (auto& m : responders_) {
    if (m) batch.push(fn(static_cast<ServiceMachine&>(*m)));
  }
  return batch;
}

StepBatch InterfaceModel::set_interface_state(InterfaceState state, TimePoint now) noexcept {
  const bool enable = state == InterfaceState::Enabled;
  state_ = enable ? InterfaceState::Enabled
                  : (state == InterfaceState::Disabled ? InterfaceState::Disabled
                                                       : InterfaceState::Unavailable);
  return for_each_machine(
      [&](ServiceMachine& m) { return enable ? m.enable(now) : m.disable(now); });
}

StepBatch InterfaceModel::counterpart_lost(TimePoint now) noexcept {
  return for_each_machine([&](ServiceMachine& m) { return m.on_counterpart_lost(now); });
}

StepBatch InterfaceModel::reevaluate(TimePoint now) noexcept {
  return for_each_machine([&](ServiceMachine& m) { return m.reevaluate(now); });
}

StepBatch InterfaceModel::on_tick(TimePoint now) noexcept {
  StepBatch batch;
  auto drain = [&](ServiceMachine& m) {
    // Each call fires one limit; a machine has at most three armed.
    for (int i = 0; i < 4 && m.next_deadline() <= now; ++i) batch.push(m.on_tick(now));
  };
  for (auto& m : requesters_) {
    if (m) drain(*m);
  }
  for (auto& m : responders_) {
    if (m) drain(*m);
  }
  return batch;
}

TimePoint InterfaceModel::next_deadline() const noexcept {
  TimePoint next = kNever;
  for (std::size_t k = 0; k < present_count_; ++k) {
    next = std::min(next, present(k).next_deadline());
  }
  return next;
}

std::size_t InterfaceModel::machine_count() const noexcept {
  return present_count_;
}

}  // namespace mtc::core
