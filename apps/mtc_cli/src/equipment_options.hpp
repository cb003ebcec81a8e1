// Options shared by `mtc request` and `mtc respond`: who this process is on
// the domain (device, interface), who its counterpart is, the transport and
// heartbeat timing, and the failure-injection flags.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "commands.hpp"
#include "fail_injection.hpp"
#include "mtc/core/profile.hpp"
#include "mtc/core/vocabulary.hpp"
#include "mtc/dds/middleware.hpp"
#include "mtc/qos/participant.hpp"
#include "mtc/qos/timing.hpp"

namespace mtc::cli {

struct EquipmentConfig {
  CommonOptions common;
  std::string device_uuid;
  std::string device_name;
  std::string interface_id;
  core::InterfaceType interface_type = core::InterfaceType::MaterialHandler;
  std::vector<core::Service> services;
  std::string counterpart;  // device uuid of the other side; may be empty for respond
  // --peer UUID/INTERFACE: also the counterpart's interface id (empty: the
  // first of its interfaces that complements ours).
  std::string counterpart_interface;
  qos::Transport transport = qos::Transport::Network;
  dds::Middleware middleware = dds::Middleware::FastDds;  // --middleware
  qos::Timing timing;                                     // --heartbeat-ms, --missed-heartbeats
  int drop_percent = 0;  // hidden test knob: Fast DDS test transport drops DATA
  std::chrono::milliseconds fail_ack_timeout{2000};
  std::chrono::milliseconds pairing_settle{500};  // dds::EquipmentOptions::pairing_settle
  // --profile: the edition of Part 5 the machines follow (1.6 also covers 1.8).
  core::Profile profile = core::Profile::V1_6;
  // --disabled: publish INTERFACE_STATE DISABLED, which makes every
  // interaction item of the interface NOT_READY (Part 5: "MUST be set to
  // NOT_READY"); nothing can be requested or served until it is ENABLED.
  bool disabled = false;
  // Responder --not-ready: start NOT_READY and clear every FAIL to NOT_READY.
  bool stay_not_ready = false;
  // Responder --door-state / --chuck-state: this equipment controls the door
  // (chuck), publishes DOOR_STATE (CHUCK_STATE) from this initial value, and
  // OPEN_/CLOSE_ services move it.
  std::optional<core::DoorState> door_state;
  std::optional<core::ChuckState> chuck_state;
};

// add_*: declare the flags; parse_*: read them (UsageError on bad values).
void add_equipment_options(CommandSpec& spec, bool many_services);
EquipmentConfig parse_equipment_options(const ParsedArgs& args, bool many_services,
                                        bool counterpart_required);

void add_fail_options(CommandSpec& spec, bool responder);
FailPlan parse_fail_options(const ParsedArgs& args, bool responder);

// --transport / --heartbeat-ms / --missed-heartbeats for `watch` and `list`
// (an observer only needs the transport and the lease it accepts).
void add_observer_options(CommandSpec& spec);
// Fills transport and timing of a DomainObserverOptions-like struct.
struct ObserverSettings {
  qos::Transport transport = qos::Transport::Network;
  dds::Middleware middleware = dds::Middleware::FastDds;  // --middleware
  qos::Timing timing;                                     // --heartbeat-ms, --missed-heartbeats
};
ObserverSettings parse_observer_options(const ParsedArgs& args, const CommonOptions& common);

// "1.6" (or "1.8") / "1.3" -> Profile; UsageError otherwise.
core::Profile parse_profile(const std::string& text);

// "MATERIAL_LOAD" -> Service; "all" or a comma list when many is true.
std::vector<core::Service> parse_services(const std::string& text, bool many);
// The interface type a service usually lives on (door services on a door ...).
core::InterfaceType default_interface_type(core::Service service);

// Per-handshake durations from "500" or "60000,10" (the last one repeats).
std::vector<std::chrono::milliseconds> parse_action_ms(const std::string& text);

}  // namespace mtc::cli
