#include "equipment_options.hpp"

namespace mtc::cli {

namespace {

std::string all_service_names() {
  std::string text;
  for (auto s : core::kAllServices) {
    text += (text.empty() ? "" : ", ") + std::string(core::to_string(s));
  }
  return text;
}

std::string required(const ParsedArgs& args, const std::string& name) {
  auto v = args.value(name);
  if (!v || v->empty()) {
    throw UsageError("--" + name + " is required");
  }
  return *v;
}

// "loopback, loopback-udp, test<last>network", from qos's spellings.
std::string transport_names(const std::string& last) {
  std::string text;
  for (std::size_t i = 0; i < qos::kAllTransports.size(); ++i) {
    if (i > 0) text += i + 1 == qos::kAllTransports.size() ? last : ", ";
    text += std::string(qos::to_string(qos::kAllTransports[i]));
  }
  return text;
}

// --transport, else the transport of a participant --qos-profile, else the
// network (the runtime's default).
qos::Transport transport_option(const ParsedArgs& args, const CommonOptions& common) {
  const auto text = args.value("transport");
  if (!text) {
    return common.profile_transport.value_or(qos::Transport::Network);
  }
  const auto parsed = qos::parse_transport(*text);
  if (!parsed) {
    throw UsageError("--transport expects " + transport_names(" or ") + ", got '" + *text + "'");
  }
  return *parsed;
}

// --middleware: "fastdds" (the default) or "cyclone", when this build has it.
void add_middleware_option(CommandSpec& spec) {
  spec.options.push_back({"middleware", "NAME",
                          "DDS implementation: fastdds, or cyclone (every transport but test, no "
                          "security yet; a cell may mix the two)",
                          "fastdds"});
}

dds::Middleware middleware_option(const ParsedArgs& args) {
  const auto text = args.value("middleware");
  if (!text) return dds::Middleware::FastDds;
  auto choice = dds::choose_middleware(*text);
  if (!choice.middleware) throw UsageError("--middleware: " + choice.problem);
  return *choice.middleware;
}

// --heartbeat-ms / --missed-heartbeats over the qos::Timing defaults.
void add_timing_options(CommandSpec& spec, const std::string& heartbeat_help,
                        const std::string& missed_help) {
  const qos::Timing defaults;
  spec.options.push_back(
      {"heartbeat-ms", "MS", heartbeat_help, std::to_string(defaults.heartbeat.count())});
  spec.options.push_back(
      {"missed-heartbeats", "N", missed_help, std::to_string(defaults.missed_heartbeats)});
}

void parse_timing_options(const ParsedArgs& args, qos::Timing& timing) {
  if (auto h = args.value("heartbeat-ms")) {
    timing.heartbeat = std::chrono::milliseconds(to_int("heartbeat-ms", *h, 1, 60000));
  }
  if (auto m = args.value("missed-heartbeats")) {
    timing.missed_heartbeats = static_cast<int>(to_int("missed-heartbeats", *m, 2, 100));
  }
}

// --counterpart UUID and/or --peer UUID/INTERFACE (same uuid when both).
void parse_counterpart(const ParsedArgs& args, bool counterpart_required, EquipmentConfig& c) {
  c.counterpart = args.value_or("counterpart", "");
  if (auto peer = args.value("peer")) {
    const auto slash = peer->find('/');
    if (slash == std::string::npos || slash == 0 || slash + 1 == peer->size() ||
        peer->find('/', slash + 1) != std::string::npos) {
      throw UsageError("--peer expects UUID/INTERFACE, e.g. machine-1/mh, got '" + *peer + "'");
    }
    const std::string uuid = peer->substr(0, slash);
    if (!c.counterpart.empty() && c.counterpart != uuid) {
      throw UsageError("--peer " + *peer + " names another device than --counterpart " +
                       c.counterpart);
    }
    c.counterpart = uuid;
    c.counterpart_interface = peer->substr(slash + 1);
  }
  if (counterpart_required && c.counterpart.empty()) {
    throw UsageError("--counterpart (or --peer) is required");
  }
}

}  // namespace

std::vector<core::Service> parse_services(const std::string& text, bool many) {
  if (many && text == "all") {
    return {core::kAllServices.begin(), core::kAllServices.end()};
  }
  const auto names = split_list(text);
  if (names.empty()) {
    throw UsageError("--service needs a service name (" + all_service_names() + ")");
  }
  if (!many && names.size() > 1) {
    throw UsageError("--service takes exactly one service here");
  }
  std::vector<core::Service> services;
  for (const auto& n : names) {
    auto s = core::parse_service(n);
    if (!s) {
      throw UsageError("unknown service '" + n + "' (known: " + all_service_names() + ")");
    }
    services.push_back(*s);
  }
  return services;
}

core::InterfaceType default_interface_type(core::Service service) {
  switch (service) {
    case core::Service::MaterialFeed:
    case core::Service::MaterialChange:
    case core::Service::MaterialRetract:
      return core::InterfaceType::BarFeeder;
    case core::Service::OpenDoor:
    case core::Service::CloseDoor:
      return core::InterfaceType::Door;
    case core::Service::OpenChuck:
    case core::Service::CloseChuck:
      return core::InterfaceType::Chuck;
    default:
      return core::InterfaceType::MaterialHandler;
  }
}

std::vector<std::chrono::milliseconds> parse_action_ms(const std::string& text) {
  std::vector<std::chrono::milliseconds> out;
  for (const auto& item : split_list(text)) {
    out.emplace_back(to_int("action-ms", item, 0, std::int64_t{24} * 3600 * 1000));
  }
  if (out.empty()) {
    throw UsageError("--action-ms expects milliseconds, e.g. 500 or 60000,10");
  }
  return out;
}

void add_observer_options(CommandSpec& spec) {
  spec.options.push_back({"transport", "KIND",
                          "network (UDP on every interface + SHM: the cell's hosts), loopback "
                          "(UDP 127.0.0.1 + SHM: this host only), loopback-udp, test",
                          "network"});
  add_middleware_option(spec);
  add_timing_options(spec, "heartbeat period of the watched devices",
                     "missed heartbeats before items read UNAVAILABLE (>= the devices' value, "
                     "or their items do not match)");
}

ObserverSettings parse_observer_options(const ParsedArgs& args, const CommonOptions& common) {
  ObserverSettings s;
  s.transport = transport_option(args, common);
  s.middleware = middleware_option(args);
  parse_timing_options(args, s.timing);
  return s;
}

void add_equipment_options(CommandSpec& spec, bool many_services) {
  spec.options.push_back({"device", "UUID", "this equipment's device uuid (required)", ""});
  spec.options.push_back({"name", "NAME", "device name announced for probes", "the uuid"});
  spec.options.push_back(
      {"interface", "ID", "interface id, shared with the counterpart (required)", ""});
  spec.options.push_back({"interface-type", "TYPE", "BAR_FEEDER, MATERIAL_HANDLER, DOOR or CHUCK",
                          "from the service"});
  spec.options.push_back({"service", "NAME",
                          many_services ? "service(s): a name, a comma list or 'all' (required)"
                                        : "service to request, e.g. MATERIAL_LOAD (required)",
                          ""});
  spec.options.push_back(
      {"counterpart", "UUID",
       many_services ? "device uuid of the requester" : "device uuid of the responder (required)",
       many_services ? "any" : ""});
  spec.options.push_back({"peer", "UUID/INTERFACE",
                          "the counterpart's device uuid and interface id (instead of "
                          "--counterpart): pair with exactly that interface",
                          ""});
  spec.options.push_back({"pairing-settle", "TIME",
                          "without --counterpart/--peer: wait this long after the first candidate "
                          "is announced, then pair with the lowest DEVICE/INTERFACE announced",
                          "500ms"});
  spec.options.push_back({"transport", "KIND",
                          "network (UDP on every interface + SHM: the cell's hosts), loopback "
                          "(UDP 127.0.0.1 + SHM: this host only), loopback-udp, test",
                          "network"});
  add_middleware_option(spec);
  add_timing_options(spec, "heartbeat period of every data item",
                     "heartbeats missed before the peer counts as lost");
  spec.options.push_back({"fail-ack-timeout", "TIME",
                          "leave FAIL without the counterpart's acknowledgement after this long",
                          "2s"});
  spec.options.push_back({"profile", "VERSION",
                          "Part 5 edition: 1.6 (also 1.8) or 1.3 (FAIL back to READY on its own, "
                          "requester READY after a responder FAIL)",
                          "1.6"});
  spec.options.push_back({"disabled", "",
                          "publish INTERFACE_STATE DISABLED: every service of the interface "
                          "NOT_READY, nothing requested or served",
                          ""});
  spec.options.push_back({"drop-percent", "P", "test transport: drop P% of sent DATA", "", true});
}

core::Profile parse_profile(const std::string& text) {
  if (text == "1.6" || text == "1.8") return core::Profile::V1_6;
  if (text == "1.3") return core::Profile::V1_3;
  throw UsageError("--profile expects 1.6, 1.8 or 1.3, got '" + text + "'");
}

EquipmentConfig parse_equipment_options(const ParsedArgs& args, bool many_services,
                                        bool counterpart_required) {
  EquipmentConfig c;
  c.common = parse_common_options(args);
  c.services = parse_services(required(args, "service"), many_services);
  c.device_uuid = required(args, "device");
  c.interface_id = required(args, "interface");
  c.device_name = args.value_or("name", c.device_uuid);
  parse_counterpart(args, counterpart_required, c);
  c.interface_type = default_interface_type(c.services.front());
  if (auto t = args.value("interface-type")) {
    auto parsed = core::parse_interface_type(*t);
    if (!parsed) {
      throw UsageError("unknown interface type '" + *t +
                       "' (BAR_FEEDER, MATERIAL_HANDLER, DOOR, CHUCK)");
    }
    c.interface_type = *parsed;
  }
  c.transport = transport_option(args, c.common);
  c.middleware = middleware_option(args);
  parse_timing_options(args, c.timing);
  if (auto f = args.value("fail-ack-timeout")) {
    c.fail_ack_timeout = to_duration("fail-ack-timeout", *f);
  }
  if (auto s = args.value("pairing-settle")) {
    c.pairing_settle = to_duration("pairing-settle", *s);
    if (c.pairing_settle > std::chrono::minutes(1)) {
      throw UsageError("--pairing-settle must be at most 1m, got '" + *s + "'");
    }
  }
  if (auto p = args.value("profile")) {
    c.profile = parse_profile(*p);
  }
  c.disabled = args.has("disabled");
  if (auto d = args.value("drop-percent")) {
    c.drop_percent = static_cast<int>(to_int("drop-percent", *d, 0, 100));
  }
  return c;
}

void add_fail_options(CommandSpec& spec, bool responder) {
  spec.options.push_back(
      {"fail-at", "STEP",
       responder ? "go FAIL at: accept (instead of ACTIVE), active (mid-action), complete"
                 : "go FAIL at: active (while the responder is ACTIVE)",
       "none"});
  spec.options.push_back(
      {"fail-on", "N[,M...]", "handshake numbers the failure applies to", "every one"});
  if (responder) {
    spec.options.push_back({"fail-rate", "P", "fail each handshake with probability P (0-1)", "0"});
    spec.options.push_back(
        {"seed", "N", "random seed for --fail-rate (same seed, same failures)", "1"});
  }
}

FailPlan parse_fail_options(const ParsedArgs& args, bool responder) {
  FailStep step = FailStep::None;
  if (auto s = args.value("fail-at")) {
    auto parsed = parse_fail_step(*s);
    const bool allowed =
        parsed && (responder || *parsed == FailStep::Active || *parsed == FailStep::None);
    if (!allowed) {
      throw UsageError(std::string("--fail-at expects ") +
                       (responder ? "accept, active or complete" : "active") + ", got '" + *s +
                       "'");
    }
    step = *parsed;
  }
  std::vector<std::uint64_t> only_on;
  if (auto on = args.value("fail-on")) {
    for (const auto& n : split_list(*on)) {
      only_on.push_back(static_cast<std::uint64_t>(to_int("fail-on", n, 1, INT64_MAX)));
    }
  }
  double rate = 0;
  std::uint64_t seed = 1;
  if (auto r = args.value("fail-rate")) {
    rate = to_double("fail-rate", *r, 0.0, 1.0);
  }
  if (auto s = args.value("seed")) {
    seed = static_cast<std::uint64_t>(to_int("seed", *s, 0, INT64_MAX));
  }
  return FailPlan(step, std::move(only_on), rate, seed);
}

}  // namespace mtc::cli
