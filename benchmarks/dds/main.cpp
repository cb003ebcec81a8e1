// mtc-bench-dds-latency: raw Fast DDS round trips beside the project's own
// transition and handshake latencies, measured in one run on one machine.
// Prints one JSON object on stdout (and to --out FILE); progress on stderr.
//
// Domain ids 100-106, for Cyclone's ddsperf 115 (benchmarks and the cell own
// 100-119; the cell runs on 110, its tests on 111-113), and for the equipment
// series on Cyclone DDS 189 (outside that range, which is full).
// Must run inside the loopback-only namespace: benchmarks/run.sh does that.
#include <algorithm>
#include <array>
#include <chrono>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cyclone_pingpong.hpp"
#include "equipment_latency.hpp"
#include "mtc/bench/cli.hpp"
#include "mtc/bench/cpus.hpp"
#include "mtc/bench/json_out.hpp"
#include "mtc/bench/proc_cpu.hpp"
#include "ratios.hpp"
#include "raw_pingpong.hpp"
#include "raw_series.hpp"
#include "udp_pingpong.hpp"

namespace {

using mtc::bench::Series;
using mtc::bench::Transport;

struct Options {
  int samples = 2000;
  int warmup = 200;
  int handshakes = 300;
  // Every series is measured in this many rounds, interleaved with the
  // others, and the samples pooled: a noisy spell of a shared VM then
  // spreads over all series instead of skewing the one that ran during it.
  int rounds = 3;
  int cyclone_seconds = 3;
  std::string out;
  std::string samples_out;
  // The CPUs of every process of the run ("all": the machine's placement).
  std::string cpus = "all";
  bool raw = true;
  bool equipment = true;
  // The equipment series' stepping modes, each a pass of every round
  // (--step-modes, --inline-steps, --pack-callback-writes, --steps-on-executor).
  std::vector<mtc::bench::Stepping> modes{mtc::bench::Stepping::Default};
  bool peer = false;               // internal: this process is the forked ponger
  bool equipment_peer = false;     // internal: the forked responder equipment
  bool cyclone_equipment = false;  // internal: that equipment runs on Cyclone DDS
  bool listener = false;           // internal: the ponger echoes from its listener
  bool both_ends = false;          // internal: a one-process raw series, printed
  int udp_peer_fd = -1;            // internal: be the UDP echo on this socket
  int round = 1;                   // internal: the equipment peer's round
  int reply_timeout_ms = 1000;     // internal: a raw round trip's timeout
  int peer_quits_after = 0;        // internal (tests): the raw pongers' echo limit
  Transport transport = Transport::UdpLoopback;
  int domain = 100;
};

constexpr const char* kAbout =
    "The project's transition and handshake latencies beside their baselines, measured\n"
    "in one run on one machine: a raw UDP ping-pong (2 processes, blocking sockets),\n"
    "raw Fast DDS round trips (WaitSet, 1 and 2 processes; echo from the listener, 2\n"
    "processes), Cyclone DDS's round trip (ddsperf ping/pong, when installed), each\n"
    "over UDP loopback and over SHM+UDP where it applies; every series in --rounds\n"
    "rounds interleaved with the others, samples pooled. Every figure also as a ratio\n"
    "to the Fast DDS listener round trip and to the UDP round trip; CPU time per\n"
    "operation (all processes) and the load average. With Cyclone DDS built in, the\n"
    "equipment series once more with both ends on Cyclone. DDS domains 100-106, 115\n"
    "and 189: runs inside the loopback-only namespace (benchmarks/run.sh does that). Progress\n"
    "on stderr; one JSON object on stdout and, with --out, in FILE:\n"
    "  {\"benchmark\":\"dds_latency\",\"unit\":\"us\",\"load_average\":...,\n"
    "   \"series\":[{name,p50,p90,p99,p999,max,cpu_us_per_op,...},...],\n"
    "   \"cyclone\":{...},\"ratios\":[...],\"targets\":{...}}\n"
    "(benchmarks/run.sh: bench-results/dds_latency.json, plotted to dds_latency.png).";

// The flags of stepping_options, as given.
struct SteppingFlags {
  std::string modes;  // --step-modes
  bool inline_steps = false;
  bool on_executor = false;
  bool pack = false;  // --pack-callback-writes
};

// --step-modes and the single-mode flags; an error message when they do not
// go together, or when several modes have more rounds than device names allow.
std::optional<std::string> apply_step_modes(const SteppingFlags& f, Options& o) {
  using mtc::bench::Stepping;
  const auto flagged = mtc::bench::stepping_from_flags(f.on_executor, f.inline_steps, f.pack);
  if (!flagged) {
    return std::string(mtc::bench::kPackNeedsInlineSteps);
  }
  if (f.modes == "all") {
    o.modes = {Stepping::Default, Stepping::Executor, Stepping::Inline};
  } else if (f.modes == "both") {
    o.modes = {Stepping::Default, Stepping::Inline};
  } else {
    // One mode, named by --step-modes or by a flag: the later in Stepping's
    // order wins, as it does among the flags.
    o.modes = {std::max(mtc::bench::stepping_named(f.modes), *flagged)};
  }
  if (o.modes.size() > 1 && o.rounds > mtc::bench::kModeRoundOffset) {
    return "--step-modes " + f.modes + ": at most " + std::to_string(mtc::bench::kModeRoundOffset) +
           " rounds";
  }
  return std::nullopt;
}

mtc::bench::Cli& stepping_options(mtc::bench::Cli& cli, SteppingFlags& f) {
  return cli
      .flag("--inline-steps", f.inline_steps,
            "the equipment series with EquipmentOptions::inline_steps\n(both ends), as "
            "--step-modes inline")
      .flag("--pack-callback-writes", f.pack,
            "with --inline-steps: also EquipmentOptions::\npack_callback_writes (both ends), as "
            "--step-modes\ninline_packed")
      .flag("--steps-on-executor", f.on_executor,
            "the equipment series with EquipmentOptions::\nsteps_on_executor (both ends), as "
            "--step-modes executor")
      .choice("--step-modes", f.modes,
              {"default", "executor", "inline", "inline_packed", "both", "all"},
              "the equipment series with the runtime's default\nstepping, steps_on_executor, "
              "inline_steps,\ninline_steps with pack_callback_writes, both\n(default and "
              "inline) or all three but packed, one\nafter the other in every round; their "
              "series end in\n\"\", \"_executor\", \"_inline\", \"_inline_packed\" "
              "(default\ndefault)");
}

// Usage errors -> exit code; nullopt to run.
std::optional<int> parse_args(int argc, char** argv, Options& o) {
  std::string only;
  SteppingFlags stepping;
  std::string transport = mtc::bench::to_string(o.transport);
  mtc::bench::Cli cli("mtc-bench-dds-latency", kAbout);
  stepping_options(cli, stepping)
      .integer("--samples", o.samples, 1, 10000000,
               "raw round trips per series, split over the rounds")
      .integer("--warmup", o.warmup, 0, 10000000,
               "untimed round trips before each raw series in\nevery round")
      .integer("--handshakes", o.handshakes, 1, 10000000,
               "handshakes per equipment series, split over the\nrounds")
      .integer("--rounds", o.rounds, 1, 1000, "rounds the series are interleaved in")
      .integer("--cyclone-seconds", o.cyclone_seconds, 0, 3600,
               "seconds of ddsperf ping, plus 2 for its start-up\n(0: no Cyclone baseline)")
      .choice("--only", only, {"raw", "equipment"}, "measure only these series (default both)")
      .text("--cpus", "LIST", o.cpus,
            "run every process of the run on these CPUs\n(\"0\", \"0,1\", \"0-1\"; they inherit "
            "the mask):\non a VM, one vCPU spares each hand-off the\nwake-up of a halted vCPU "
            "(mtc-bench-wakeup)")
      .text("--out", "FILE", o.out, "also write the JSON to FILE (default stdout only)")
      .text("--samples-out", "FILE", o.samples_out,
            "write every series' samples, sorted, to FILE as\n{\"name\":[us,...],...} (for CDF "
            "plots)")
      .internal_options_follow()
      .flag("--peer", o.peer, "be the raw ping-pong peer")
      .flag("--equipment-peer", o.equipment_peer, "be the responder equipment peer")
      .flag("--cyclone-equipment", o.cyclone_equipment, "the equipment peer runs on Cyclone DDS")
      .flag("--listener", o.listener, "echo from the reader's listener")
      .flag("--both-ends", o.both_ends, "run a one-process raw series and print it")
      .integer("--udp-peer-fd", o.udp_peer_fd, 0, 65535, "be the UDP echo on this socket")
      .integer("--round", o.round, 1, 1000, "the equipment peer's round (its device names)")
      .integer("--reply-timeout-ms", o.reply_timeout_ms, 1, 60000,
               "a raw round trip with no echo this long is a\ntimeout")
      .integer("--peer-quits-after", o.peer_quits_after, 0, 10000000,
               "the raw pongers stop after this many echoes,\na forked one killing itself "
               "(tests)")
      .choice("--transport", transport, {"udp_loopback", "shm_udp", "udp", "shm"},
              "the peer's transport")
      .integer("--domain", o.domain, 0, 232, "the peer's DDS domain");
  if (const auto exit_code = cli.parse(argc, argv)) {
    return exit_code;
  }
  if (const auto error = apply_step_modes(stepping, o)) {
    return cli.usage_error(*error);
  }
  if (!only.empty()) {
    o.raw = only == "raw";
    o.equipment = only == "equipment";
  }
  if (!mtc::bench::parse_transport(transport, o.transport)) {
    return cli.usage_error("--transport: no such transport '" + transport + "'");
  }
  if (const auto error = mtc::bench::confine_to_cpus(o.cpus)) {
    return cli.usage_error(*error);
  }
  return std::nullopt;
}

mtc::bench::RawSeriesOptions raw_options(const Options& o) {
  mtc::bench::RawSeriesOptions r;
  r.samples = o.samples;
  r.warmup = o.warmup;
  r.reply_timeout = std::chrono::milliseconds(o.reply_timeout_ms);
  r.peer_quits_after = o.peer_quits_after;
  return r;
}

Series run_raw(const Options& o, Transport t, int processes, int domain, bool listener = false) {
  return mtc::bench::run_raw_series(raw_options(o), t, processes, domain, listener);
}

std::string load_json(const std::array<double, 3>& load) {
  std::ostringstream json;
  json << "[" << load[0] << "," << load[1] << "," << load[2] << "]";
  return json.str();
}

std::string modes_json(const std::vector<mtc::bench::Stepping>& modes) {
  std::string json = "[";
  for (const auto mode : modes) {
    json.append(json.size() > 1 ? ",\"" : "\"").append(mtc::bench::to_string(mode)).append("\"");
  }
  return json + "]";
}

struct RunContext {
  std::array<double, 3> load_start{};
  std::array<double, 3> load_end{};
  std::optional<mtc::bench::CycloneResult> cyclone;
  std::string cyclone_why;
};

std::string to_json(const Options& o, const std::vector<Series>& all, const RunContext& run) {
  std::optional<mtc::bench::Reference> cyclone;
  if (run.cyclone) {
    cyclone = mtc::bench::Reference{
        mtc::bench::cyclone_median(*run.cyclone, &mtc::bench::CycloneSecond::p50),
        mtc::bench::cyclone_median(*run.cyclone, &mtc::bench::CycloneSecond::p99)};
  }
  std::ostringstream json;
  json << "{\"benchmark\":\"dds_latency\",\"unit\":\"us\",\"cores\":"
       << std::thread::hardware_concurrency() << ",\"samples\":" << o.samples
       << ",\"handshakes\":" << o.handshakes << ",\"rounds\":" << o.rounds
       << ",\"stepping\":" << modes_json(o.modes) << ",\"cpus\":\"" << o.cpus << "\""
       << ",\"load_average_start\":" << load_json(run.load_start)
       << ",\"load_average_end\":" << load_json(run.load_end)
       << ",\"cpu_note\":\"cpu_us_per_op: user+system CPU of every process taking part "
          "(both ends), per timed round trip or handshake\""
       << ",\"qos\":\"mtc.state preset: RELIABLE, TRANSIENT_LOCAL, KEEP_LAST 1, no deadline "
          "(liveness is the heartbeat topic's); keyed InteractionSample\",\"series\":[";
  for (std::size_t i = 0; i < all.size(); ++i) {
    json << (i == 0 ? "\n  " : ",\n  ") << mtc::bench::to_json(all[i]);
  }
  json << "\n],\n\"cyclone\":" << mtc::bench::cyclone_json(run.cyclone, run.cyclone_why)
       << ",\n\"ratios\":" << mtc::bench::ratios_json(all, cyclone)
       << ",\n\"targets\":" << mtc::bench::targets_json(all, cyclone) << "}\n";
  return json.str();
}

// One round of every series, each with its share of the samples.
std::vector<Series> run_round(const Options& o, int round_number) {
  Options share = o;
  share.samples = std::max(1, o.samples / o.rounds);
  std::vector<Series> round;
  if (o.raw) {
    round.push_back(mtc::bench::run_udp_round_trips("/proc/self/exe", share.warmup, share.samples));
    round.push_back(run_raw(share, Transport::UdpLoopback, 2, 102, true));
    round.push_back(run_raw(share, Transport::ShmUdp, 2, 103, true));
    round.push_back(run_raw(share, Transport::UdpLoopback, 1, 100));
    round.push_back(run_raw(share, Transport::ShmUdp, 1, 101));
    round.push_back(run_raw(share, Transport::UdpLoopback, 2, 102));
    round.push_back(run_raw(share, Transport::ShmUdp, 2, 103));
  }
  if (o.equipment) {
    mtc::bench::EquipmentBenchOptions eo;
    eo.first_domain_id = 104;  // 104-106
    eo.round = round_number;
    eo.handshakes = std::max(1, o.handshakes / o.rounds);
    for (const auto mode : o.modes) {
      mtc::bench::set_stepping(mode);
      eo.round = mtc::bench::mode_round(mode, round_number);
      for (auto& s : mtc::bench::run_equipment_series(eo)) {
        round.push_back(std::move(s));
      }
    }
  }
  return round;
}

// {"name":[sorted samples in us],...}: what a CDF is drawn from.
bool write_samples(const std::string& path, const std::vector<Series>& all) {
  std::ofstream file(path);
  file << "{";
  for (std::size_t i = 0; i < all.size(); ++i) {
    std::vector<double> sorted = all[i].samples_us;
    std::sort(sorted.begin(), sorted.end());
    file << (i == 0 ? "\n" : ",\n") << "\"" << all[i].name << "\":[";
    for (std::size_t k = 0; k < sorted.size(); ++k) {
      file << (k == 0 ? "" : ",")
           << static_cast<double>(static_cast<long long>(sorted[k] * 10)) / 10.0;
    }
    file << "]";
  }
  file << "\n}\n";
  return static_cast<bool>(file);
}

// Pools a round's samples into the series of the earlier rounds; the CPU
// per operation becomes the mean weighted by sample count.
void pool(Series& into, const Series& more) {
  const auto before = static_cast<double>(into.samples_us.size());
  const auto added = static_cast<double>(more.samples_us.size());
  if (into.cpu_us_per_op >= 0 && more.cpu_us_per_op >= 0 && before + added > 0) {
    into.cpu_us_per_op =
        (into.cpu_us_per_op * before + more.cpu_us_per_op * added) / (before + added);
  }
  into.samples_us.insert(into.samples_us.end(), more.samples_us.begin(), more.samples_us.end());
  mtc::bench::append_legs(into, more.legs_us);
  into.timeouts += more.timeouts;
}

int run(const Options& o) {
  RunContext context;
  context.load_start = mtc::bench::load_average();
  std::vector<Series> all;
  if (o.raw && o.cyclone_seconds > 0) {
    std::cerr << "cyclone dds round trip: ddsperf ping/pong, " << o.cyclone_seconds << " s\n";
    context.cyclone =
        mtc::bench::run_cyclone_round_trips(115, o.cyclone_seconds, context.cyclone_why);
  } else {
    context.cyclone_why = "not measured (--cyclone-seconds 0 or --only equipment)";
  }
  for (int r = 0; r < o.rounds; ++r) {
    std::cerr << "-- round " << (r + 1) << " of " << o.rounds << "\n";
    std::vector<Series> round = run_round(o, r + 1);
    if (all.empty()) {
      all = std::move(round);
      continue;
    }
    for (std::size_t i = 0; i < all.size() && i < round.size(); ++i) {
      pool(all[i], round[i]);
    }
  }
  context.load_end = mtc::bench::load_average();
  if (!o.samples_out.empty() && !write_samples(o.samples_out, all)) {
    std::cerr << "cannot write " << o.samples_out << "\n";
    return 1;
  }
  return mtc::bench::emit_json(to_json(o, all, context), o.out, "mtc-bench-dds-latency");
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (const auto exit_code = parse_args(argc, argv, o)) {
    return *exit_code;
  }
  mtc::bench::set_stepping(o.modes.front());  // the peers get one mode each
  try {
    if (o.both_ends) {
      return mtc::bench::print_both_ends(raw_options(o), o.transport, o.domain);
    }
    if (o.udp_peer_fd >= 0) {
      return mtc::bench::run_udp_echo(o.udp_peer_fd);
    }
    if (o.equipment_peer) {
      return mtc::bench::run_equipment_peer(o.domain, o.transport == Transport::UdpLoopback,
                                            o.round, o.cyclone_equipment);
    }
    return o.peer ? mtc::bench::run_raw_peer(raw_options(o), o.transport, o.domain, o.listener)
                  : run(o);
  } catch (const std::exception& e) {
    std::cerr << "mtc-bench-dds-latency: " << e.what() << "\n";
    return 1;
  }
}
