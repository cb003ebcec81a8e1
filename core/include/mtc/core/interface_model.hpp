// One Interface of one piece of equipment (e.g. its MaterialHandlerInterface):
// its INTERFACE_STATE and the service machines it carries, each service at
// most once per role. Operations that concern the whole interface (disable,
// enable, counterpart lost, precondition change, time) are applied to every
// machine and return one StepResult per machine in a StepBatch.
//
// Pure value type, no allocation: machines live in fixed arrays indexed by
// service. Not thread-safe; the runtime drives it from one thread.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

#include "mtc/core/requester.hpp"
#include "mtc/core/responder.hpp"

namespace mtc::core {

// Up to one result per (service, role) of an interface.
class StepBatch {
 public:
  static constexpr std::size_t kCapacity = kAllServices.size() * 2;

  void push(const StepResult& r) noexcept {
    if (size_ < kCapacity) items_[size_++] = r;
  }
  std::size_t size() const noexcept { return size_; }
  bool empty() const noexcept { return size_ == 0; }
  const StepResult& operator[](std::size_t i) const noexcept { return items_[i]; }
  const StepResult* begin() const noexcept { return items_.data(); }
  const StepResult* end() const noexcept { return items_.data() + size_; }
  // True when any result changed a published state.
  bool any_changed() const noexcept {
    return std::any_of(begin(), end(), [](const StepResult& r) { return r.changed(); });
  }

 private:
  std::array<StepResult, kCapacity> items_{};
  std::size_t size_ = 0;
};

class InterfaceModel {
 public:
  // `options` is the default for machines added without their own options.
  // `hook` (non-owning, may be null) is given to every machine.
  explicit InterfaceModel(InterfaceType type, const MachineOptions& options = {},
                          const ServicePreconditions* hook = nullptr) noexcept;

  // Adds a machine; false if that (service, role) already exists. A machine
  // added while the interface is DISABLED starts disabled.
  bool add_requester(Service service) noexcept;
  bool add_requester(Service service, const MachineOptions& options) noexcept;
  bool add_responder(Service service) noexcept;
  bool add_responder(Service service, const MachineOptions& options) noexcept;

  // nullptr when the interface does not carry that side of the service.
  Requester* requester(Service service) noexcept;
  const Requester* requester(Service service) const noexcept;
  Responder* responder(Service service) noexcept;
  const Responder* responder(Service service) const noexcept;
  ServiceMachine* machine(Service service, Role role) noexcept;
  const ServiceMachine* machine(Service service, Role role) const noexcept;

  // Own INTERFACE_STATE. DISABLED forces every machine to NOT_READY and
  // refuses their commands (Table 3); ENABLED lets them return to READY.
  // UNAVAILABLE is treated as DISABLED (the interface is not operating).
  StepBatch set_interface_state(InterfaceState state, TimePoint now) noexcept;
  InterfaceState interface_state() const noexcept { return state_; }

  // The counterpart equipment is gone (heartbeat/liveliness lost, or its
  // INTERFACE_STATE became UNAVAILABLE): every machine sees UNAVAILABLE.
  StepBatch counterpart_lost(TimePoint now) noexcept;
  // The precondition hook's answers may have changed (door/chuck moved).
  StepBatch reevaluate(TimePoint now) noexcept;
  // Fires every expired time limit of every machine.
  StepBatch on_tick(TimePoint now) noexcept;
  TimePoint next_deadline() const noexcept;

  InterfaceType type() const noexcept { return type_; }
  std::size_t machine_count() const noexcept;

 private:
  static std::size_t index(Service s) noexcept { return static_cast<std::size_t>(s); }
  template <typename Fn>
  StepBatch for_each_machine(Fn&& fn) noexcept;

  // Which machines exist, in the order they were added: (role, service)
  // coded as one byte (responders from kAllServices.size() up). The runtime
  // asks next_deadline() of every interface after every step; visiting the
  // machines that exist, not twenty optionals of a few hundred bytes each,
  // keeps that from dominating the CPU of an equipment with 100 interfaces.
  // Indices, not pointers, so that the model stays a copyable value.
  void note_added(Role role, Service service) noexcept;
  const ServiceMachine& present(std::size_t k) const noexcept;

  InterfaceType type_;
  MachineOptions options_;
  const ServicePreconditions* hook_;
  InterfaceState state_ = InterfaceState::Enabled;
  std::array<std::optional<Requester>, kAllServices.size()> requesters_{};
  std::array<std::optional<Responder>, kAllServices.size()> responders_{};
  std::array<std::uint8_t, StepBatch::kCapacity> present_{};
  std::size_t present_count_ = 0;
};

}  // namespace mtc::core
