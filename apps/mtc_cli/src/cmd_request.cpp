// `mtc request`: act as the requester of one service and run handshakes.
#include "command_session.hpp"
#include "commands.hpp"
#include "mtc/dds/middleware.hpp"
#include "request_runner.hpp"

namespace mtc::cli {
namespace {

RequestConfig parse_request(const ParsedArgs& args) {
  RequestConfig c;
  c.equipment = parse_equipment_options(args, false, true);
  if (auto n = args.value("count")) {
    c.count = static_cast<std::uint64_t>(to_int("count", *n, 1, 100000000));
  }
  if (auto t = args.value("timeout")) {
    c.timeout = to_duration("timeout", *t);
  }
  c.keep_going = args.has("keep-going");
  c.fail_plan = parse_fail_options(args, false);
  return c;
}

int run_request(const ParsedArgs& args, Context& context) {
  RequestConfig config = parse_request(args);
  const auto& eq = config.equipment;
  const std::string service(core::to_string(eq.services.front()));
  const std::string middleware(dds::to_string(eq.middleware));
  StartNotice notice;
  notice.json.field("event", "started")
      .field("device", eq.device_uuid)
      .field("interface", eq.interface_id)
      .field("service", service)
      .field("counterpart", eq.counterpart)
      .field("profile", eq.profile == core::Profile::V1_3 ? "1.3" : "1.6")
      .field("interface_state", eq.disabled ? "DISABLED" : "ENABLED")
      .field("domain", eq.common.domain)
      .field("middleware", middleware);
  notice.text = "requesting " + service + " from " + eq.counterpart + " on domain " +
                std::to_string(eq.common.domain) + " over " + middleware;
  return run_with_equipment(eq, core::Role::Requester, notice, context,
                            [&](EquipmentLink& link, EventQueue& events) {
                              return RequestRunner(std::move(config), context, link, events).run();
                            });
}

}  // namespace

Command request_command() {
  CommandSpec spec;
  spec.name = "request";
  spec.summary = "act as requester: run handshakes and print each step's latency";
  spec.description =
      "Joins the domain as device --device with interface --interface, as the REQUESTER\n"
      "of --service, and asks --counterpart (the responder's device uuid) for the\n"
      "service: waits until the response is READY, sets the request ACTIVE, and follows\n"
      "the handshake (response ACTIVE -> COMPLETE, request READY, response READY),\n"
      "printing every transition with its time since the request and the source ->\n"
      "reception latency of the counterpart's samples, then the outcome. A FAIL is\n"
      "recovered to READY (once the responder acknowledged it) before the next one.\n"
      "A responder interface serves one requester interface (its pairing, named in its\n"
      "samples): when it is paired with another, this one is EXCLUDED and told with whom\n"
      "(stderr: 'robot-2/mh: machine-1/mh is paired with robot-1/mh').\n"
      "Exit: 0 all COMPLETE, 3 FAIL, 4 timeout, 5 counterpart lost, 6 counterpart\n"
      "NOT_READY, 7 excluded (the responder is paired with another requester; neither a\n"
      "FAIL nor a protocol violation), 130 interrupted (first non-COMPLETE outcome decides).";
  spec.options = {
      {"count", "N", "number of handshakes, one after the other", "1"},
      {"timeout", "TIME", "per handshake, including waiting for the responder", "10s"},
      {"keep-going", "", "continue after a failed handshake (recover, then next)", ""},
  };
  add_equipment_options(spec, false);
  add_fail_options(spec, false);
  add_common_options(spec);
  spec.examples =
      "  mtc request --device robot-1 --interface mh --service MATERIAL_LOAD --counterpart "
      "machine-1\n"
      "  mtc request --domain 5 --device robot-1 --interface door --service OPEN_DOOR \\\n"
      "      --counterpart machine-1 --count 100 --json > handshakes.jsonl\n"
      "  # scenario 3: the requester fails while the responder is ACTIVE\n"
      "  mtc request --device robot-1 --interface mh --service MATERIAL_LOAD \\\n"
      "      --counterpart machine-1 --fail-at active\n";
  return {spec, &run_request};
}

}  // namespace mtc::cli
