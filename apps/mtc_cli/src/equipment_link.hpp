// The one seam between the `mtc` commands and the DDS runtime (mtc::dds):
// one piece of equipment with one interface carrying one side (requester or
// responder) of one or more services. Runtime callbacks are turned into
// LinkEvents on an EventQueue; commands are plain calls that return why the
// runtime refused them (nullopt = done).
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "equipment_options.hpp"
#include "link_events.hpp"
#include "mtc/core/vocabulary.hpp"

namespace mtc::cli {

class EquipmentLink {
 public:
  // Creates the participant, announces the device and starts publishing.
  // Throws mtc::dds::Error (ConfigError for bad ids) on failure.
  EquipmentLink(const EquipmentConfig& config, core::Role role, EventQueue& events);
  ~EquipmentLink();
  EquipmentLink(const EquipmentLink&) = delete;
  EquipmentLink& operator=(const EquipmentLink&) = delete;

  using Refusal = std::optional<std::string>;
  // Requester: READY -> ACTIVE once the response is READY (waiting up to
  // `wait`); the outcome arrives later as a RequestDone event.
  Refusal request(core::Service s, std::chrono::milliseconds wait);
  Refusal accept(core::Service s);    // responder: READY -> ACTIVE
  Refusal complete(core::Service s);  // responder: ACTIVE -> COMPLETE
  Refusal fail(core::Service s);      // either side: -> FAIL
  Refusal recover(core::Service s);   // FAIL -> READY (once acknowledged)
  Refusal set_ready(core::Service s, bool ready);
  // Moves the door / chuck this equipment controls (--door-state, --chuck-state).
  void set_door_state(core::DoorState state);
  void set_chuck_state(core::ChuckState state);

  // Latest published own state (snapshot, any thread).
  core::InteractionState state(core::Service s) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mtc::cli
