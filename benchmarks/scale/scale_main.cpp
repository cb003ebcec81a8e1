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
// * Start-up: --startup-devices devices on one domain, half of them
//   requesters here and half responders in a child, one interface pair
//   each: time from the start until every pair is matched and READY.
// Prints progress on stderr and one JSON object on stdout (and to --out).
// DDS domains 109 (throughput) and 115 (start-up) by default (benchmarks and
// the cell own 100-119). Must run inside the loopback-only namespace:
// benchmarks/run.sh does that.
// The pairs' two processes are in pairs.cpp, the load generator in load.cpp.
#include <sys/types.h>

#include <array>
#include <chrono>
#include <fstream>
#include <future>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "../dds/latency_stats.hpp"
#include "../dds/proc_cpu.hpp"
#include "load.hpp"
#include "mtc/bench/cli.hpp"
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
  bool peer = false;  // internal: be the responder process
  int devices = 1;    // internal: responder devices in the peer
  int interfaces = 1;
};

constexpr const char* kAbout =
    "Throughput and latency with 1, 10, 100 interface pairs handshaking concurrently\n"
    "between two processes (handshakes/s, p50/p99/p99.9, CPU, RSS of an equipment with\n"
    "that many interfaces), and the start-up of N devices on one domain (time until\n"
    "every pair is matched and READY). DDS domains 109 and 115: runs inside the\n"
    "loopback-only namespace (benchmarks/run.sh does that). Progress on stderr; one JSON\n"
    "object on stdout and, with --out, in FILE:\n"
    "  {\"benchmark\":\"scale\",\"levels\":[{pairs,handshakes_per_s,p50,p99,...}],\n"
    "   \"startup\":{devices,all_ready_ms,...},\"targets\":{...}}";

std::optional<int> parse_args(int argc, char** argv, Options& o) {
  mtc::bench::Cli cli("mtc-bench-scale", kAbout);
  cli.text("--pairs", "LIST", o.pairs, "interface pairs per level, comma-separated")
      .integer("--seconds", o.seconds, 1, 3600, "seconds of handshaking per level")
      .integer("--startup-devices", o.startup_devices, 0, 200,
               "devices in the start-up measurement (even; 0: skip it)")
      .integer("--domain", o.domain, 0, 232, "DDS domain of the throughput levels")
      .integer("--startup-domain", o.startup_domain, 0, 232, "DDS domain of the start-up")
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

struct Level {
  int pairs = 0;
  double seconds = 0;
  mtc::bench::Series series;
  std::size_t failed = 0;
  double cpu_requester_s = 0, cpu_responder_s = 0;
  long requester_rss_kb = -1, responder_rss_kb = -1;
};

Level run_level(const Options& o, int pairs) {
  std::cerr << "scale: " << pairs << " pair(s), " << o.seconds << " s\n";
  const pid_t peer = spawn_peer(1, pairs, o.domain);
  Level level;
  level.pairs = pairs;
  try {
    mtc::dds::Equipment eq(equipment_options(device("req", 0), o.domain), quiet_callbacks());
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
    const double cpu_req0 = mtc::bench::cpu_seconds(0);
    const double cpu_resp0 = mtc::bench::cpu_seconds(peer);
    const auto start = Clock::now();
    Chains chains(requesters, start + std::chrono::seconds(o.seconds));
    chains.start();
    if (!chains.wait(std::chrono::seconds(o.seconds) + 30s)) {
      throw std::runtime_error("handshake chains did not stop");
    }
    level.cpu_requester_s = mtc::bench::cpu_seconds(0) - cpu_req0;
    level.cpu_responder_s = mtc::bench::cpu_seconds(peer) - cpu_resp0;
    level.seconds = mtc::bench::to_us(chains.tally().last_result - start) / 1e6;
    level.series.samples_us = std::move(chains.tally().samples_us);
    level.failed = chains.tally().failed;
    level.requester_rss_kb = rss_kb(0);
    level.responder_rss_kb = rss_kb(peer);
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

std::string level_json(const Level& l) {
  const auto sum = mtc::bench::summarize(l.series.samples_us);
  const double per_s = l.seconds > 0 ? static_cast<double>(sum.count) / l.seconds : 0;
  const double cpu = l.cpu_requester_s + l.cpu_responder_s;
  std::ostringstream json;
  json << "{\"pairs\":" << l.pairs << ",\"seconds\":" << l.seconds
       << ",\"handshakes\":" << sum.count << ",\"failed\":" << l.failed
       << ",\"handshakes_per_s\":" << per_s << ",\"p50\":" << sum.p50 << ",\"p90\":" << sum.p90
       << ",\"p99\":" << sum.p99 << ",\"p999\":" << sum.p999 << ",\"max\":" << sum.max
       << ",\"cpu_requester_pct\":" << (l.seconds > 0 ? 100 * l.cpu_requester_s / l.seconds : 0)
       << ",\"cpu_responder_pct\":" << (l.seconds > 0 ? 100 * l.cpu_responder_s / l.seconds : 0)
       << ",\"cpu_us_per_handshake\":"
       << (sum.count > 0 ? cpu * 1e6 / static_cast<double>(sum.count) : 0)
       << ",\"requester_rss_kb\":" << l.requester_rss_kb
       << ",\"responder_rss_kb\":" << l.responder_rss_kb << "}";
  return json.str();
}

// Issue 9 section 4: >= 5,000 handshakes/s at 100 pairs, p99 <= 3x the
// single pair's.
std::string targets_json(const std::vector<Level>& levels) {
  const Level* one = nullptr;
  const Level* hundred = nullptr;
  for (const auto& l : levels) {
    one = l.pairs == 1 ? &l : one;
    hundred = l.pairs == 100 ? &l : hundred;
  }
  if (one == nullptr || hundred == nullptr) {
    return "null";
  }
  const auto s1 = mtc::bench::summarize(one->series.samples_us);
  const auto s100 = mtc::bench::summarize(hundred->series.samples_us);
  const double per_s =
      hundred->seconds > 0 ? static_cast<double>(s100.count) / hundred->seconds : 0;
  const double ratio = s1.p99 > 0 ? s100.p99 / s1.p99 : 0;
  std::ostringstream json;
  json << "{\"handshakes_per_s_at_100_min\":5000,\"handshakes_per_s_at_100\":" << per_s
       << ",\"throughput_met\":" << (per_s >= 5000 ? "true" : "false")
       << ",\"p99_100_vs_1_max\":3,\"p99_100_vs_1\":" << ratio
       << ",\"p99_met\":" << (ratio > 0 && ratio <= 3 ? "true" : "false") << "}";
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
       << ",\"unit\":\"us\",\"transport\":\"shm_udp\",\"load_average_start\":"
       << load_json(load_start) << ",\"load_average_end\":" << load_json(mtc::bench::load_average())
       << ",\"latency\":\"request() to its outcome, issued as soon as the previous handshake "
          "of the pair completed\",\"levels\":[";
  for (std::size_t i = 0; i < levels.size(); ++i) {
    json << (i == 0 ? "\n  " : ",\n  ") << level_json(levels[i]);
  }
  json << "\n],\"targets\":" << targets_json(levels) << ",\"startup\":";
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
  std::cout << json.str();
  if (!o.out.empty()) {
    std::ofstream file(o.out);
    file << json.str();
    if (!file) {
      std::cerr << "cannot write " << o.out << "\n";
      return 1;
    }
  }
  return 0;
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
