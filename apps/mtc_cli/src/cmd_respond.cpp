// `mtc respond`: act as the responder of one or more services.
#include "command_session.hpp"
#include "commands.hpp"
#include "mtc/dds/middleware.hpp"
#include "respond_runner.hpp"

namespace mtc::cli {
namespace {

RespondConfig parse_respond(const ParsedArgs& args) {
  RespondConfig c;
  c.equipment = parse_equipment_options(args, true, false);
  if (auto n = args.value("count")) {
    c.count = static_cast<std::uint64_t>(to_int("count", *n, 1, 100000000));
  }
  if (auto a = args.value("action-ms")) {
    c.action = parse_action_ms(*a);
  }
  c.not_ready = args.has("not-ready");
  c.equipment.stay_not_ready = c.not_ready;
  if (auto d = args.value("door-state")) {
    const auto parsed = core::parse_door_state(*d);
    if (!parsed || *parsed == core::DoorState::Unavailable) {
      throw UsageError("--door-state expects OPEN, UNLATCHED or CLOSED, got '" + *d + "'");
    }
    c.equipment.door_state = parsed;
  }
  if (auto d = args.value("chuck-state")) {
    const auto parsed = core::parse_chuck_state(*d);
    if (!parsed || *parsed == core::ChuckState::Unavailable) {
      throw UsageError("--chuck-state expects OPEN, UNLATCHED or CLOSED, got '" + *d + "'");
    }
    c.equipment.chuck_state = parsed;
  }
  c.fail_plan = parse_fail_options(args, true);
  return c;
}

std::string service_list_json(const std::vector<core::Service>& services) {
  std::string out = "[";
  for (std::size_t i = 0; i < services.size(); ++i) {
    out += (i > 0 ? "," : "") + json_quote(core::to_string(services[i]));
  }
  return out + "]";
}

int run_respond(const ParsedArgs& args, Context& context) {
  RespondConfig config = parse_respond(args);
  const auto& eq = config.equipment;
  const std::string middleware(dds::to_string(eq.middleware));
  StartNotice notice;
  notice.json.field("event", "ready")
      .field("device", eq.device_uuid)
      .field("interface", eq.interface_id)
      .raw_field("services", service_list_json(eq.services))
      .field("profile", eq.profile == core::Profile::V1_3 ? "1.3" : "1.6")
      .field("interface_state", eq.disabled ? "DISABLED" : "ENABLED")
      .field("domain", eq.common.domain)
      .field("middleware", middleware);
  notice.text = "responding as " + eq.device_uuid + "/" + eq.interface_id + " on domain " +
                std::to_string(eq.common.domain) + " over " + middleware + " (Ctrl-C to stop)";
  return run_with_equipment(eq, core::Role::Responder, notice, context,
                            [&](EquipmentLink& link, EventQueue& events) {
                              return RespondRunner(std::move(config), context, link, events).run();
                            });
}

}  // namespace

Command respond_command() {
  CommandSpec spec;
  spec.name = "respond";
  spec.summary = "act as responder, with configurable action time and injected failures";
  spec.description =
      "Joins the domain as device --device with interface --interface, as the RESPONDER\n"
      "of --service (one, a comma list or 'all'). Each time the request goes ACTIVE it\n"
      "accepts (response ACTIVE), performs the action for --action-ms, completes\n"
      "(COMPLETE) and returns to READY when the requester acknowledges. Failures can\n"
      "be injected to drive the Part 5 section 5.1 scenarios from the other side:\n"
      "  --fail-at accept      FAIL instead of ACTIVE              (scenario 1)\n"
      "  --fail-at active      FAIL half-way through the action    (scenario 2)\n"
      "  --fail-at complete    FAIL when the action would complete (scenario 2)\n"
      "  --fail-rate P --seed N   random failures at random steps, reproducible\n"
      "FAIL is cleared to READY once the requester acknowledges it. Runs until Ctrl-C /\n"
      "SIGTERM (exit 0) or until --count handshakes are closed.";
  spec.options = {
      {"action-ms", "MS[,MS...]", "action duration per handshake (the last value repeats)", "500"},
      {"count", "N", "exit after N handshakes", "until Ctrl-C"},
      {"not-ready", "", "stay NOT_READY (refuse every request)", ""},
      {"door-state", "STATE",
       "publish DOOR_STATE from OPEN|UNLATCHED|CLOSED; OPEN_DOOR/CLOSE_DOOR move it and are "
       "NOT_READY when already there",
       "not published"},
      {"chuck-state", "STATE", "same for CHUCK_STATE with OPEN_CHUCK/CLOSE_CHUCK", "not published"},
  };
  add_equipment_options(spec, true);
  add_fail_options(spec, true);
  add_common_options(spec);
  spec.examples =
      "  mtc respond --device machine-1 --interface mh --service MATERIAL_LOAD\n"
      "  mtc respond --device machine-1 --interface cell --service all --action-ms 50\n"
      "  mtc respond --device machine-1 --interface mh --service MATERIAL_LOAD \\\n"
      "      --fail-at active --fail-on 2          # 2nd handshake fails mid-action\n"
      "  mtc respond --device machine-1 --interface mh --service MATERIAL_LOAD \\\n"
      "      --fail-rate 0.1 --seed 42 --json      # soak test peer\n";
  return {spec, &run_respond};
}

}  // namespace mtc::cli
