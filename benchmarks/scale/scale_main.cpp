// mtc-bench-scale: how the runtime scales with the number of interfaces.
// * Throughput: 1, 10, 100 (--pairs) interface pairs between two processes
//   (a requester equipment here, a responder equipment with the matching
//   interfaces in a forked child), every pair handshaking concurrently for
//   --seconds: each request is issued from the previous one's result
//   callback, so every pair always has one handshake in flight. Handshakes
//   per second, latency percentiles (request() to its outcome: it waits for
//   the responder's return to READY after the previous handshake, so it
//   covers a whole handshake), CPU of both processes, and the RSS of each
//   equipment (the responder is a fresh process per level: its RSS is the
//   cost of an equipment with that many interfaces).
// * Paced (--paced RATE, after each level's closed loop, as long): the same
//   pairs offered RATE handshakes/s in total, each pair asking at
//   RATE/pairs per second on a fixed schedule (an open loop, see load.hpp),
//   latency from each scheduled instant. A closed loop's latency is set by
//   Little's law (pairs in flight / throughput); the paced series says what a
//   load below capacity costs.
// * Start-up: --startup-devices devices on one domain, half of them
//   requesters here and half responders in a child, one interface pair
//   each: time from the start until every pair is matched and READY.
// Prints progress on stderr and one JSON object on stdout (and to --out).
// DDS domains 109 (throughput) and 115 (start-up) by default (benchmarks and
// the cell own 100-119). Must run inside the loopback-only namespace:
// benchmarks/run.sh does that.
// The pairs' two processes are in pairs.cpp, the load generators in load.cpp.
#include <sys/types.h>

#include <array>
#include <chrono>
#include <future>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "../dds/latency_stats.hpp"
#include "load.hpp"
#include "mtc/bench/cli.hpp"
#include "mtc/bench/json_out.hpp"
#include "mtc/bench/proc_cpu.hpp"
#include "mtc/dds/equipment.hpp"
#include "pairs.hpp"

namespace mtc::bench::scale {
namespace {

using namespace std::chrono_literals;
using mtc::core::Service;

struct Options {
  std::string pairs = "1,10,100";
  int seconds = 3;
  int startup_devices = 20;
  int domain = 109;
  int startup_domain = 115;
  std::string out;
  int paced = 0;  // handshakes/s offered in total by the paced series; 0: none
  bool steps_on_executor = false;
  bool inline_steps = false;
  bool pack_callback_writes = false;
  std::string middleware = "fastdds";
  bool peer = false;  // internal: be the responder process
  int devices = 1;    // internal: responder devices in the peer
  int interfaces = 1;
};

constexpr const char* kAbout =
    "Throughput and latency with 1, 10, 100 interface pairs handshaking concurrently\n"
    "between two processes (handshakes/s, p50/p99/p99.9, CPU, RSS of an equipment with\n"
    "that many interfaces), and the start-up of N devices on one domain (time until\n"
    "every pair is matched and READY). Each level is a closed loop (every pair asks\n"
    "again as soon as its last handshake ended); with --paced RATE it is followed by an\n"
    "open loop as long, offering RATE handshakes/s in total (RATE/pairs per pair, phases\n"
    "staggered), latency timed from each request's scheduled instant. Both processes on\n"
    "one DDS implementation (--middleware): Fast DDS over shared memory and UDP, or\n"
    "Cyclone DDS over UDP. DDS domains 109 and 115: runs inside the loopback-only\n"
    "namespace (benchmarks/run.sh does that).\n"
    "Progress on stderr; one JSON object on stdout and, with --out, in FILE:\n"
    "  {\"benchmark\":\"scale\",\"middleware\",\"levels\":[{pairs,handshakes_per_s,p50,p99,...,\n"
    "     \"paced\":{offered_per_s,achieved_per_s,failed,p50,p99,...} or null}],\n"
    "   \"startup\":{devices,all_ready_ms,...},\"targets\":{...}}";

std::optional<int> parse_args(int argc, char** argv, Options& o) {
  mtc::bench::Cli cli("mtc-bench-scale", kAbout);
  cli.text("--pairs", "LIST", o.pairs, "interface pairs per level, comma-separated")
      .integer("--seconds", o.seconds, 1, 3600, "seconds of handshaking per level")
      .integer("--startup-devices", o.startup_devices, 0, 200,
               "devices in the start-up measurement (even; 0: skip it)")
      .integer("--domain", o.domain, 0, 232, "DDS domain of the throughput levels")
      .integer("--startup-domain", o.startup_domain, 0, 232, "DDS domain of the start-up")
      .integer("--paced", o.paced, 0, 1000000,
               "handshakes/s offered in total after each closed loop (0: none)")
      .flag("--steps-on-executor", o.steps_on_executor,
            "both processes step on the executor thread (EquipmentOptions::steps_on_executor)")
      .flag("--inline-steps", o.inline_steps,
            "both processes step and call back on the thread that brought the step")
      .flag("--pack-callback-writes", o.pack_callback_writes,
            "with --inline-steps: a step's writes leave with what its callbacks wrote\n"
            "(EquipmentOptions::pack_callback_writes)")
      .choice("--middleware", o.middleware, {"fastdds", "cyclone"},
              "DDS implementation of both processes")
      .text("--out", "FILE", o.out, "also write the JSON to FILE")
      .internal_options_follow()
      .flag("--peer", o.peer, "be the responder process")
      .integer("--devices", o.devices, 1, 1000, "responder devices in the peer")
      .integer("--interfaces", o.interfaces, 1, 1000, "interfaces per responder device");
  if (const auto exit_code = cli.parse(argc, argv)) {
    return exit_code;
  }
  if (o.startup_devices % 2 != 0) {
    return cli.usage_error("--startup-devices must be even (requester/responder pairs)");
  }
  if (o.steps_on_executor && o.inline_steps) {
    return cli.usage_error("--steps-on-executor and --inline-steps exclude each other");
  }
  const auto stepping =
      mtc::bench::stepping_from_flags(o.steps_on_executor, o.inline_steps, o.pack_callback_writes);
  if (!stepping) {
    return cli.usage_error(mtc::bench::kPackNeedsInlineSteps);
  }
  set_stepping(*stepping);
  const auto choice = mtc::dds::choose_middleware(o.middleware);
  if (!choice.middleware) {
    std::cerr << "mtc-bench-scale: " << choice.problem << "\n";
    return 2;
  }
  set_middleware(*choice.middleware);
  return std::nullopt;
}

std::vector<int> parse_pairs(const std::string& text) {
  std::vector<int> pairs;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    const int n = std::stoi(item);
    if (n < 1 || n > 1000) {
      throw std::invalid_argument("--pairs: each level must be 1-1000");
    }
    pairs.push_back(n);
  }
  return pairs;
}

// One timed series of a level: its handshakes and the CPU both processes
// spent meanwhile.
struct Run {
  double seconds = 0;  // first request (or instant) to the last result
  Tally tally;
  double cpu_requester_s = 0, cpu_responder_s = 0;
  double offered_per_s = 0;    // paced only
  std::size_t not_issued = 0;  // paced only: dropped when the backlog did not drain
};

struct Level {
  int pairs = 0;
  Run closed;
  std::optional<Run> paced;
  long requester_rss_kb = -1, responder_rss_kb = -1;
};

// CPU seconds of this process and the peer from construction to close().
class CpuWindow {
 public:
  explicit CpuWindow(pid_t peer)
      : peer_(peer),
        requester0_(mtc::bench::cpu_seconds(0)),
        responder0_(mtc::bench::cpu_seconds(peer)) {}
  void close(Run& run) const {
    run.cpu_requester_s = mtc::bench::cpu_seconds(0) - requester0_;
    run.cpu_responder_s = mtc::bench::cpu_seconds(peer_) - responder0_;
  }

 private:
  pid_t peer_;
  double requester0_, responder0_;
};

Run run_closed(const Options& o, pid_t peer, const std::vector<mtc::dds::Requester*>& requesters) {
  const CpuWindow cpu(peer);
  const auto start = Clock::now();
  Chains chains(requesters, start + std::chrono::seconds(o.seconds));
  chains.start();
  if (!chains.wait(std::chrono::seconds(o.seconds) + 30s)) {
    throw std::runtime_error("handshake chains did not stop");
  }
  Run run;
  cpu.close(run);
  run.tally = std::move(chains.tally());
  run.seconds = mtc::bench::to_us(run.tally.last_result - start) / 1e6;
  return run;
}

Run run_paced(const Options& o, pid_t peer, const std::vector<mtc::dds::Requester*>& requesters) {
  std::cerr << "scale: " << requesters.size() << " pair(s) paced, " << o.paced << "/s, "
            << o.seconds << " s\n";
  // The closed loop's last handshakes may still be returning to READY.
  if (!wait_all_ready(requesters, 10s)) {
    throw std::runtime_error("not every pair READY again within 10 s");
  }
  const CpuWindow cpu(peer);
  Pacer pacer(requesters, o.paced, std::chrono::seconds(o.seconds));
  const auto start = pacer.start();
  if (!pacer.wait(std::chrono::seconds(o.seconds) + 30s)) {
    throw std::runtime_error("paced requests did not end");
  }
  Run run;
  cpu.close(run);
  run.tally = std::move(pacer.tally());
  run.seconds = mtc::bench::to_us(run.tally.last_result - start) / 1e6;
  run.offered_per_s = o.paced;
  run.not_issued = pacer.not_issued();
  if (run.not_issued > 0) {
    std::cerr << "scale: " << run.not_issued << " paced requests never issued (counted failed)\n";
  }
  return run;
}

// The requester equipment with `pairs` interfaces, every pair READY and warmed up.
std::vector<mtc::dds::Requester*> prepare(mtc::dds::Equipment& eq, int pairs) {
  add_pairing(eq, device("resp", 0), pairs);
  std::vector<mtc::dds::Requester*> requesters;
  requesters.reserve(static_cast<std::size_t>(pairs));
  for (int k = 0; k < pairs; ++k) {
    requesters.push_back(&eq.add_requester(interface_id(k), Service::MaterialLoad));
  }
  eq.start();
  if (!wait_all_ready(requesters, 30s)) {
    throw std::runtime_error("not every pair READY within 30 s");
  }
  for (auto* r : requesters) {  // warm-up: one handshake per pair
    auto done = r->request(mtc::dds::RequestOptions{2000ms});
    if (done.wait_for(30s) != std::future_status::ready) {
      throw std::runtime_error("warm-up handshake not done within 30 s");
    }
  }
  return requesters;
}

Level run_level(const Options& o, int pairs) {
  std::cerr << "scale: " << pairs << " pair(s), " << o.seconds << " s\n";
  const pid_t peer = spawn_peer(1, pairs, o.domain);
  Level level;
  level.pairs = pairs;
  try {
    mtc::dds::Equipment eq(equipment_options(device("req", 0), o.domain), quiet_callbacks());
    const auto requesters = prepare(eq, pairs);
    level.closed = run_closed(o, peer, requesters);
    level.requester_rss_kb = rss_kb(0);
    level.responder_rss_kb = rss_kb(peer);
    if (o.paced > 0) {
      level.paced = run_paced(o, peer, requesters);
    }
  } catch (...) {
    stop_peer(peer);
    throw;
  }
  stop_peer(peer);
  return level;
}

struct Startup {
  int devices = 0;
  double started_ms = -1;  // this process's devices all started (start() returned)
  double first_ready_ms = -1, all_ready_ms = -1;
  bool complete = false;
};

// Half the devices here (requesters), half in a child (responders), one
// interface pair each; timed from before the child is started.
Startup run_startup(const Options& o) {
  const int pairs = o.startup_devices / 2;
  std::cerr << "startup: " << o.startup_devices << " devices, " << pairs << " pairs\n";
  Startup s;
  s.devices = o.startup_devices;
  const auto t0 = Clock::now();
  const pid_t peer = spawn_peer(pairs, 1, o.startup_domain);
  try {
    std::vector<std::unique_ptr<mtc::dds::Equipment>> devices;
    std::vector<mtc::dds::Requester*> requesters;
    for (int d = 0; d < pairs; ++d) {
      auto e = std::make_unique<mtc::dds::Equipment>(
          equipment_options(device("req", d), o.startup_domain), quiet_callbacks());
      add_pairing(*e, device("resp", d), 1);
      requesters.push_back(&e->add_requester(interface_id(0), Service::MaterialLoad));
      e->start();
      devices.push_back(std::move(e));
    }
    // Readiness is polled from here on: start() of the devices here is
    // itself most of the start-up, so this time says how much.
    s.started_ms = mtc::bench::to_us(Clock::now() - t0) / 1000;
    const auto deadline = t0 + 60s;
    std::vector<bool> ready(requesters.size(), false);
    std::size_t count = 0;
    while (count < requesters.size() && Clock::now() < deadline) {
      for (std::size_t i = 0; i < requesters.size(); ++i) {
        if (!ready[i] && requesters[i]->counterpart_state() == mtc::core::InteractionState::Ready) {
          ready[i] = true;
          const double ms = mtc::bench::to_us(Clock::now() - t0) / 1000;
          s.first_ready_ms = count++ == 0 ? ms : s.first_ready_ms;
          s.all_ready_ms = ms;
        }
      }
      std::this_thread::sleep_for(1ms);
    }
    s.complete = count == requesters.size();
  } catch (...) {
    stop_peer(peer);
    throw;
  }
  stop_peer(peer);
  return s;
}

double per_second(const Run& r) {
  return r.seconds > 0 ? static_cast<double>(r.tally.samples_us.size()) / r.seconds : 0;
}

double cpu_us_per_handshake(const Run& r) {
  const auto n = r.tally.samples_us.size();
  return n > 0 ? (r.cpu_requester_s + r.cpu_responder_s) * 1e6 / static_cast<double>(n) : 0;
}

std::string paced_json(const Run& r) {
  const auto sum = mtc::bench::summarize(r.tally.samples_us);
  const auto delay = mtc::bench::summarize(r.tally.issue_delay_us);
  std::ostringstream json;
  json << "{\"offered_per_s\":" << r.offered_per_s << ",\"achieved_per_s\":" << per_second(r)
       << ",\"seconds\":" << r.seconds << ",\"handshakes\":" << sum.count
       << ",\"failed\":" << r.tally.failed << ",\"not_issued\":" << r.not_issued
       << ",\"p50\":" << sum.p50 << ",\"p90\":" << sum.p90 << ",\"p99\":" << sum.p99
       << ",\"p999\":" << sum.p999 << ",\"max\":" << sum.max
       << ",\"issue_delay\":{\"p50\":" << delay.p50 << ",\"p99\":" << delay.p99
       << ",\"p999\":" << delay.p999 << ",\"max\":" << delay.max << "}"
       << ",\"cpu_us_per_handshake\":" << cpu_us_per_handshake(r) << "}";
  return json.str();
}

std::string level_json(const Level& l) {
  const Run& c = l.closed;
  const auto sum = mtc::bench::summarize(c.tally.samples_us);
  std::ostringstream json;
  json << "{\"pairs\":" << l.pairs << ",\"seconds\":" << c.seconds
       << ",\"handshakes\":" << sum.count << ",\"failed\":" << c.tally.failed
       << ",\"handshakes_per_s\":" << per_second(c) << ",\"p50\":" << sum.p50
       << ",\"p90\":" << sum.p90 << ",\"p99\":" << sum.p99 << ",\"p999\":" << sum.p999
       << ",\"max\":" << sum.max
       << ",\"cpu_requester_pct\":" << (c.seconds > 0 ? 100 * c.cpu_requester_s / c.seconds : 0)
       << ",\"cpu_responder_pct\":" << (c.seconds > 0 ? 100 * c.cpu_responder_s / c.seconds : 0)
       << ",\"cpu_us_per_handshake\":" << cpu_us_per_handshake(c)
       << ",\"requester_rss_kb\":" << l.requester_rss_kb
       << ",\"responder_rss_kb\":" << l.responder_rss_kb
       << ",\"paced\":" << (l.paced ? paced_json(*l.paced) : "null") << "}";
  return json.str();
}

// The paced comparison: the paced 100-pair p99 over the single pair's
// closed-loop p99. One pair in a closed loop has one handshake in flight
// and nothing queued: its latency is the runtime's unloaded one. A single
// pair offered the whole paced rate is no such basis: one pair can do only
// ~2,000 handshakes/s, near any rate worth offering 100 pairs.
std::string paced_targets_json(double closed_p99_1, const Level& hundred) {
  std::ostringstream json;
  json << ",\"p99_basis\":\"closed-loop single pair p99\"";
  if (!hundred.paced || closed_p99_1 <= 0) {
    json << ",\"p99_paced_100_vs_1\":null,\"p99_paced_met\":null";
    return json.str();
  }
  const auto s = mtc::bench::summarize(hundred.paced->tally.samples_us);
  const double ratio = s.p99 / closed_p99_1;
  json << ",\"paced_offered_per_s\":" << hundred.paced->offered_per_s
       << ",\"p99_paced_100_vs_1\":" << ratio
       << ",\"p99_paced_met\":" << (ratio > 0 && ratio <= 3 ? "true" : "false");
  return json.str();
}

// Issue 9 section 4: >= 5,000 handshakes/s at 100 pairs over Fast DDS,
// >= 20,000 over Cyclone DDS; p99 <= 3x the single pair's (closed loop:
// p99_met; paced: p99_paced_met).
std::string targets_json(const std::vector<Level>& levels, const Options& o) {
  const Level* one = nullptr;
  const Level* hundred = nullptr;
  for (const auto& l : levels) {
    one = l.pairs == 1 ? &l : one;
    hundred = l.pairs == 100 ? &l : hundred;
  }
  if (one == nullptr || hundred == nullptr) {
    return "null";
  }
  const auto s1 = mtc::bench::summarize(one->closed.tally.samples_us);
  const auto s100 = mtc::bench::summarize(hundred->closed.tally.samples_us);
  const double per_s = per_second(hundred->closed);
  const double ratio = s1.p99 > 0 ? s100.p99 / s1.p99 : 0;
  const double min_per_s = o.middleware == "cyclone" ? 20000 : 5000;
  std::ostringstream json;
  json << "{\"handshakes_per_s_at_100_min\":" << min_per_s
       << ",\"handshakes_per_s_at_100\":" << per_s
       << ",\"throughput_met\":" << (per_s >= min_per_s ? "true" : "false")
       << ",\"p99_100_vs_1_max\":3,\"p99_100_vs_1\":" << ratio
       << ",\"p99_met\":" << (ratio > 0 && ratio <= 3 ? "true" : "false")
       << paced_targets_json(s1.p99, *hundred) << "}";
  return json.str();
}

std::string load_json(const std::array<double, 3>& load) {
  std::ostringstream json;
  json << "[" << load[0] << "," << load[1] << "," << load[2] << "]";
  return json.str();
}

int run(const Options& o) {
  const auto load_start = mtc::bench::load_average();
  std::vector<Level> levels;
  for (int pairs : parse_pairs(o.pairs)) {
    levels.push_back(run_level(o, pairs));
  }
  std::optional<Startup> startup;
  if (o.startup_devices > 0) {
    startup = run_startup(o);
  }
  std::ostringstream json;
  json << "{\"benchmark\":\"scale\",\"cores\":" << std::thread::hardware_concurrency()
       << ",\"unit\":\"us\",\"middleware\":\"" << o.middleware << "\",\"transport\":\""
       << transport_name() << "\",\"stepping\":\"" << to_string(stepping())
       << "\",\"load_average_start\":" << load_json(load_start)
       << ",\"load_average_end\":" << load_json(mtc::bench::load_average())
       << ",\"latency\":\"request() to its outcome, issued as soon as the previous handshake "
          "of the pair completed\",\"paced_latency\":\"scheduled instant to the outcome "
          "(the issue's delay plus request() to outcome)\",\"levels\":[";
  for (std::size_t i = 0; i < levels.size(); ++i) {
    json << (i == 0 ? "\n  " : ",\n  ") << level_json(levels[i]);
  }
  json << "\n],\"targets\":" << targets_json(levels, o) << ",\"startup\":";
  if (startup) {
    json << "{\"devices\":" << startup->devices << ",\"pairs\":" << startup->devices / 2
         << ",\"complete\":" << (startup->complete ? "true" : "false")
         << ",\"started_ms\":" << startup->started_ms
         << ",\"first_ready_ms\":" << startup->first_ready_ms
         << ",\"all_ready_ms\":" << startup->all_ready_ms << "}";
  } else {
    json << "null";
  }
  json << "}\n";
  return mtc::bench::emit_json(json.str(), o.out, "mtc-bench-scale");
}

}  // namespace
}  // namespace mtc::bench::scale

int main(int argc, char** argv) {
  namespace scale = mtc::bench::scale;
  scale::Options o;
  if (const auto exit_code = scale::parse_args(argc, argv, o)) {
    return *exit_code;
  }
  try {
    return o.peer ? scale::run_peer(o.devices, o.interfaces, o.domain) : scale::run(o);
  } catch (const std::exception& e) {
    std::cerr << "mtc-bench-scale: " << e.what() << "\n";
    return 1;
  }
}
