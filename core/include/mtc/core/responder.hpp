// The responder side of a service (Table 6): performs the service when the
// request is ACTIVE and reports COMPLETE.
#pragma once

#include "mtc/core/machine.hpp"

namespace mtc::core {

class Responder : public ServiceMachine {
 public:
  explicit Responder(Service service, const MachineOptions& options = {},
                     const ServicePreconditions* hook = nullptr) noexcept
      : ServiceMachine(Role::Responder, service, options, hook) {}

  // READY -> ACTIVE (Table 1 step 3). Rejected unless the request is ACTIVE
  // (Table 6: MUST NOT go ACTIVE otherwise) and the hook permits.
  StepResult accept(TimePoint now) noexcept { return step(Event::Accept, now); }
  // ACTIVE -> COMPLETE (step 4). The response then stays COMPLETE until the
  // request returns to READY, and goes READY or NOT_READY (steps 7-8).
  StepResult complete(TimePoint now) noexcept { return step(Event::Complete, now); }
};

}  // namespace mtc::core
