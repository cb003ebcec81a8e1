// The requester side of a service (Table 5): asks for the service and
// watches the responder until COMPLETE or FAIL.
#pragma once

#include "mtc/core/machine.hpp"

namespace mtc::core {

class Requester : public ServiceMachine {
 public:
  explicit Requester(Service service, const MachineOptions& options = {},
                     const ServicePreconditions* hook = nullptr) noexcept
      : ServiceMachine(Role::Requester, service, options, hook) {}

  // READY -> ACTIVE (Table 1 step 1). Rejected unless own state READY, the
  // response READY (1.3: "the request SHOULD not become ACTIVE when the
  // response state is NOT_READY") and the hook permitting.
  StepResult request(TimePoint now) noexcept { return step(Event::Request, now); }
};

}  // namespace mtc::core
