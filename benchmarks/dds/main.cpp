// mtc-bench-dds-latency: raw Fast DDS round trips beside the project's own
// transition and handshake latencies, measured in one run on one machine.
// Prints one JSON object on stdout (and to --out FILE); progress on stderr.
//
// Domain ids 100-106 (benchmarks and the cell own 100-119; the cell runs on
// 110, its tests on 111-113).
// Must run inside the loopback-only namespace: benchmarks/run.sh does that.
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "equipment_latency.hpp"
#include "mtc/bench/cli.hpp"
#include "mtc/qos/participant.hpp"
#include "raw_pingpong.hpp"

namespace {

using mtc::bench::PingPongOptions;
using mtc::bench::Series;
using mtc::bench::Transport;

std::atomic<bool> g_peer_stop{false};

extern "C" void on_peer_signal(int) {
  g_peer_stop.store(true);
}

struct Options {
  int samples = 2000;
  int warmup = 200;
  int handshakes = 300;
  // Every series is measured in this many rounds, interleaved with the
  // others, and the samples pooled: a noisy spell of a shared VM then
  // spreads over all series instead of skewing the one that ran during it.
  int rounds = 3;
  std::string out;
  bool raw = true;
  bool equipment = true;
  bool peer = false;            // internal: this process is the forked ponger
  bool equipment_peer = false;  // internal: the forked responder equipment
  Transport transport = Transport::UdpLoopback;
  int domain = 100;
};

constexpr const char* kAbout =
    "Raw Fast DDS round trips beside the project's own transition and handshake\n"
    "latencies, measured in one run on one machine: each series with both ends in one\n"
    "process and with the peer in a second process (this executable started again),\n"
    "over UDP loopback and over SHM+UDP; every series in --rounds rounds interleaved\n"
    "with the others, samples pooled. DDS domains 100-106: runs inside the\n"
    "loopback-only namespace (benchmarks/run.sh does that). Progress on stderr; one\n"
    "JSON object on stdout and, with --out, in FILE:\n"
    "  {\"benchmark\":\"dds_latency\",\"unit\":\"us\",...,\n"
    "   \"series\":[{name,p50,p90,p99,max,...},...]}\n"
    "(benchmarks/run.sh: bench-results/dds_latency.json, plotted to dds_latency.png).";

// Usage errors -> exit code; nullopt to run.
std::optional<int> parse_args(int argc, char** argv, Options& o) {
  std::string only;
  std::string transport = mtc::bench::to_string(o.transport);
  mtc::bench::Cli cli("mtc-bench-dds-latency", kAbout);
  cli.integer("--samples", o.samples, 1, 10000000,
              "raw round trips per series, split over the rounds")
      .integer("--warmup", o.warmup, 0, 10000000,
               "untimed round trips before each raw series in\nevery round")
      .integer("--handshakes", o.handshakes, 1, 10000000,
               "handshakes per equipment series, split over the\nrounds")
      .integer("--rounds", o.rounds, 1, 1000, "rounds the series are interleaved in")
      .choice("--only", only, {"raw", "equipment"}, "measure only these series (default both)")
      .text("--out", "FILE", o.out, "also write the JSON to FILE (default stdout only)")
      .internal_options_follow()
      .flag("--peer", o.peer, "be the raw ping-pong peer")
      .flag("--equipment-peer", o.equipment_peer, "be the responder equipment peer")
      .choice("--transport", transport, {"udp_loopback", "shm_udp", "udp", "shm"},
              "the peer's transport")
      .integer("--domain", o.domain, 0, 232, "the peer's DDS domain");
  if (const auto exit_code = cli.parse(argc, argv)) {
    return exit_code;
  }
  if (!only.empty()) {
    o.raw = only == "raw";
    o.equipment = only == "equipment";
  }
  if (!mtc::bench::parse_transport(transport, o.transport)) {
    return cli.usage_error("--transport: no such transport '" + transport + "'");
  }
  return std::nullopt;
}

int run_peer(const Options& o) {
  // The peer must not outlive the benchmark, whatever happens to it.
  prctl(PR_SET_PDEATHSIG, SIGTERM);
  std::signal(SIGTERM, on_peer_signal);
  std::signal(SIGINT, on_peer_signal);
  PingPongOptions po;
  po.domain_id = o.domain;
  po.transport = o.transport;
  try {
    mtc::bench::run_ponger(po, g_peer_stop);
  } catch (const std::exception& e) {
    std::cerr << "ponger peer: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

// Starts this executable again as the ponger peer (fork + exec: a forked copy
// of a process that already runs Fast DDS threads would be unsafe).
pid_t spawn_peer(Transport t, int domain) {
  const std::string transport = mtc::bench::to_string(t);
  const std::string dom = std::to_string(domain);
  const pid_t pid = fork();
  if (pid < 0) {
    throw std::runtime_error("fork failed");
  }
  if (pid == 0) {
    execl("/proc/self/exe", "mtc-bench-dds-latency", "--peer", "--transport", transport.c_str(),
          "--domain", dom.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  return pid;
}

Series run_raw(const Options& o, Transport t, int processes, int domain) {
  PingPongOptions po;
  po.domain_id = domain;
  po.transport = t;
  po.samples = o.samples;
  po.warmup = o.warmup;
  std::cerr << "raw fast dds round trip: " << mtc::bench::to_string(t) << ", " << processes
            << " process(es), " << o.samples << " samples\n";
  Series s;
  if (processes == 1) {
    // Raw endpoints of one process talk intra-process, as Fast DDS does by
    // default; an mtc series of the same run has turned it off (the
    // runtime does, see mtc::dds::detail::deliver_through_transports).
    mtc::qos::set_intraprocess_delivery(true);
    std::atomic<bool> stop{false};
    std::thread ponger([&] {
      try {
        mtc::bench::run_ponger(po, stop);
      } catch (const std::exception& e) {
        std::cerr << "ponger: " << e.what() << "\n";
      }
    });
    try {
      s = mtc::bench::run_pinger(po, std::chrono::seconds(10));
    } catch (...) {
      stop.store(true);
      ponger.join();
      throw;
    }
    stop.store(true);
    ponger.join();
  } else {
    const pid_t peer = spawn_peer(t, domain);
    try {
      s = mtc::bench::run_pinger(po, std::chrono::seconds(10));
    } catch (...) {
      kill(peer, SIGTERM);
      waitpid(peer, nullptr, 0);
      throw;
    }
    kill(peer, SIGTERM);
    int status = 0;
    waitpid(peer, &status, 0);
  }
  s.processes = processes;
  s.name = "raw_fastdds_round_trip_" + mtc::bench::to_string(t) + "_" + std::to_string(processes) +
           "proc";
  return s;
}

std::string to_json(const Options& o, const std::vector<Series>& all) {
  std::ostringstream json;
  json << "{\"benchmark\":\"dds_latency\",\"unit\":\"us\",\"cores\":"
       << std::thread::hardware_concurrency() << ",\"samples\":" << o.samples
       << ",\"handshakes\":" << o.handshakes << ",\"rounds\":" << o.rounds
       << ",\"qos\":\"mtc.state preset: RELIABLE, TRANSIENT_LOCAL, KEEP_LAST 1, no deadline "
          "(liveness is the heartbeat topic's); keyed InteractionSample\",\"series\":[";
  for (std::size_t i = 0; i < all.size(); ++i) {
    json << (i == 0 ? "\n  " : ",\n  ") << mtc::bench::to_json(all[i]);
  }
  json << "\n]}\n";
  return json.str();
}

// One round of every series, each with its share of the samples.
std::vector<Series> run_round(const Options& o) {
  Options share = o;
  share.samples = std::max(1, o.samples / o.rounds);
  std::vector<Series> round;
  if (o.raw) {
    round.push_back(run_raw(share, Transport::UdpLoopback, 1, 100));
    round.push_back(run_raw(share, Transport::ShmUdp, 1, 101));
    round.push_back(run_raw(share, Transport::UdpLoopback, 2, 102));
    round.push_back(run_raw(share, Transport::ShmUdp, 2, 103));
  }
  if (o.equipment) {
    mtc::bench::EquipmentBenchOptions eo;
    eo.first_domain_id = 104;  // 104-106
    eo.handshakes = std::max(1, o.handshakes / o.rounds);
    for (auto& s : mtc::bench::run_equipment_series(eo)) {
      round.push_back(std::move(s));
    }
  }
  return round;
}

int run(const Options& o) {
  std::vector<Series> all;
  for (int r = 0; r < o.rounds; ++r) {
    std::cerr << "-- round " << (r + 1) << " of " << o.rounds << "\n";
    std::vector<Series> round = run_round(o);
    if (all.empty()) {
      all = std::move(round);
      continue;
    }
    for (std::size_t i = 0; i < all.size() && i < round.size(); ++i) {
      auto& into = all[i].samples_us;
      into.insert(into.end(), round[i].samples_us.begin(), round[i].samples_us.end());
      all[i].timeouts += round[i].timeouts;
    }
  }
  const std::string json = to_json(o, all);
  std::cout << json;
  if (!o.out.empty()) {
    std::ofstream file(o.out);
    file << json;
    if (!file) {
      std::cerr << "cannot write " << o.out << "\n";
      return 1;
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (const auto exit_code = parse_args(argc, argv, o)) {
    return *exit_code;
  }
  try {
    if (o.equipment_peer) {
      return mtc::bench::run_equipment_peer(o.domain, o.transport == Transport::UdpLoopback);
    }
    return o.peer ? run_peer(o) : run(o);
  } catch (const std::exception& e) {
    std::cerr << "mtc-bench-dds-latency: " << e.what() << "\n";
    return 1;
  }
}
