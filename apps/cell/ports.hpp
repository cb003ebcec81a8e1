// What a station of the simulated cell needs from the runtime, and nothing
// more: raise a request and learn how it ended, take a job on and finish or
// fail it, recover, and publish door/chuck states. The station scripts
// (machine_station.cpp, robot_station.cpp, feeder_station.cpp)
// are written against these few calls only, so the same scripts run over the
// DDS Equipment runtime (equipment_link.cpp) and over an in-memory link
// (local_link.cpp, for the fast logic test).
#pragma once

#include <chrono>
#include <initializer_list>
#include <optional>
#include <string>

#include "mtc/core/vocabulary.hpp"

namespace mtc::cell {

using Millis = std::chrono::milliseconds;

// How one handshake ended, seen from the side that asked for it.
enum class Outcome : std::uint8_t {
  Completed,  // COMPLETE seen and acknowledged: both sides back to READY
  Failed,     // both sides went FAIL (any scenario of Part 5 section 5.1)
  TimedOut,   // no end within the wait; the caller treats it as a failure
  NotNeeded,  // never raised: what it asks for already holds (chuck OPEN for OPEN_CHUCK)
};

// The requesting side of one service (a REQUEST data item).
class RequestPort {
 public:
  virtual ~RequestPort() = default;
  // READY -> ACTIVE (Table 1 step 1), after waiting up to `timeout` for the
  // responder to be READY (it may still be recovering from a failure).
  // False when it could not be raised; nothing changed then.
  virtual bool raise(Millis timeout) = 0;
  // Blocks until the responder has taken the request on (ACTIVE) or the
  // handshake ended; true when the responder is ACTIVE.
  virtual bool wait_engaged(Millis timeout) = 0;
  // Blocks until the handshake ended (steps 5-8, or both FAIL).
  virtual Outcome wait_outcome(Millis timeout) = 0;
  // Fault injection, scenario 3: the requester detected a failure. False
  // when it came too late: the handshake had already ended, nothing changed.
  virtual bool fail() = 0;
  // FAIL -> READY once the responder acknowledged with FAIL; true on READY.
  virtual bool recover(Millis timeout) = 0;
  // "request READY, response FAIL": for the log when something is stuck.
  virtual std::string states() = 0;
  // Why the last handshake failed, as the runtime told it ("Failed:
  // counterpart went FAIL"); empty when the link does not say.
  virtual std::string why_failed() { return {}; }
};

// The responding side of one service (a RESPONSE data item).
class ResponsePort {
 public:
  virtual ~ResponsePort() = default;
  virtual bool accept() = 0;    // READY -> ACTIVE (step 3)
  virtual bool complete() = 0;  // ACTIVE -> COMPLETE (step 4); READY follows the ack
  // Fault injection, scenarios 1 and 2: the responder detected a failure.
  virtual void fail() = 0;
  // The requester left ACTIVE (FAIL, READY or lost) while we were working:
  // stop the job (the runtime has already answered FAIL per Table 6).
  virtual bool cancelled() = 0;
  // Back to READY after a failure (waits for the requester's FAIL ack).
  virtual bool recover(Millis timeout) = 0;
  // After complete(): Completed once the requester acknowledged (steps 6-8,
  // response idle again), Failed when the response went FAIL instead (the
  // requester failed or was lost before acknowledging).
  virtual Outcome wait_settled(Millis timeout) = 0;
  // The response is FAIL (e.g. left over from a loss while idle).
  virtual bool failed() = 0;
  // The response's current value: READY or NOT_READY after a recovery
  // (NOT_READY when the door/chuck already is where the service moves it).
  virtual core::InteractionState state() = 0;
};

// One station's equipment as the scripts see it.
class Link {
 public:
  virtual ~Link() = default;
  virtual RequestPort& requester(core::Service service) = 0;
  virtual ResponsePort& responder(core::Service service) = 0;
  // Blocks until a request for one of `services` (those this unit serves)
  // went ACTIVE; nullopt on timeout.
  virtual std::optional<core::Service> wait_job(std::initializer_list<core::Service> services,
                                                Millis timeout) = 0;
  virtual void set_door(core::DoorState state) = 0;
  virtual void set_chuck(core::ChuckState state) = 0;
  // True when what a door/chuck service would do already holds (OPEN_DOOR
  // with the door OPEN): the responder is NOT_READY for it then, so the
  // requester skips it. False for every other service.
  virtual bool holds(core::Service service) = 0;
};

// Shared by the links: does `s` have nothing left to do given these states?
inline bool door_chuck_holds(core::Service s, std::optional<core::DoorState> door,
                             std::optional<core::ChuckState> chuck) {
  switch (s) {
    case core::Service::OpenDoor:
      return door == core::DoorState::Open;
    case core::Service::CloseDoor:
      return door == core::DoorState::Closed;
    case core::Service::OpenChuck:
      return chuck == core::ChuckState::Open;
    case core::Service::CloseChuck:
      return chuck == core::ChuckState::Closed;
    default:
      return false;
  }
}

}  // namespace mtc::cell
