// The hook through which a service machine asks the application whether the
// equipment can take part in a service right now, e.g. whether the door is
// already open. The machines hold a non-owning pointer; nullptr = always yes.
#pragma once

#include "mtc/core/vocabulary.hpp"

namespace mtc::core {

class ServicePreconditions {
 public:
  virtual ~ServicePreconditions() = default;
  // True when this equipment can currently take part in `service` as `role`.
  // Consulted in READY / NOT_READY, on accept() / request(), on recovery and
  // after COMPLETE is acknowledged; never while a service is in progress
  // (OPEN_DOOR naturally changes the door state while ACTIVE). Must be cheap
  // and must not call back into the machine.
  virtual bool permits(Service service, Role role) const noexcept = 0;

 protected:
  ServicePreconditions() = default;
  ServicePreconditions(const ServicePreconditions&) = default;
  ServicePreconditions& operator=(const ServicePreconditions&) = default;
  ServicePreconditions(ServicePreconditions&&) = default;
  ServicePreconditions& operator=(ServicePreconditions&&) = default;
};

// 1.3 section 3.3: "If the DOOR_STATE is OPEN, the OPEN_DOOR data item will
// have the value NOT_READY since you cannot open a door when it is already
// opened." The same holds for CLOSE_DOOR while CLOSED and for the chuck.
// UNLATCHED permits both directions; UNAVAILABLE (state unknown) permits
// neither, so a door of unknown state is never moved. Services that are not
// door/chuck services are always permitted.
constexpr bool door_permits(Service service, DoorState door) noexcept {
  if (service == Service::OpenDoor) {
    return door == DoorState::Closed || door == DoorState::Unlatched;
  }
  if (service == Service::CloseDoor) {
    return door == DoorState::Open || door == DoorState::Unlatched;
  }
  return true;
}
constexpr bool chuck_permits(Service service, ChuckState chuck) noexcept {
  if (service == Service::OpenChuck) {
    return chuck == ChuckState::Closed || chuck == ChuckState::Unlatched;
  }
  if (service == Service::CloseChuck) {
    return chuck == ChuckState::Open || chuck == ChuckState::Unlatched;
  }
  return true;
}

// Ready-made hook for the equipment that controls a door and/or a chuck: it
// holds the DOOR_STATE / CHUCK_STATE the application reports and applies the
// rules above to the RESPONSE side (the side that moves the door). Requests
// are always permitted. After changing a state, call reevaluate() on the
// machines (InterfaceModel::reevaluate does all of them).
class DoorChuckPreconditions final : public ServicePreconditions {
 public:
  DoorChuckPreconditions() = default;
  DoorChuckPreconditions(DoorState door, ChuckState chuck) noexcept : door_(door), chuck_(chuck) {}

  void set_door_state(DoorState s) noexcept { door_ = s; }
  void set_chuck_state(ChuckState s) noexcept { chuck_ = s; }
  DoorState door_state() const noexcept { return door_; }
  ChuckState chuck_state() const noexcept { return chuck_; }

  bool permits(Service service, Role role) const noexcept override {
    if (role != Role::Responder) return true;
    return door_permits(service, door_) && chuck_permits(service, chuck_);
  }

 private:
  DoorState door_ = DoorState::Unavailable;
  ChuckState chuck_ = ChuckState::Unavailable;
};

}  // namespace mtc::core
