// mtc-bench-detection: comms-loss detection time as a distribution. A
// watcher Equipment (MATERIAL_LOAD requester) pairs with a responder in a
// child process; once the link is up and a random fraction of a heartbeat
// has passed, the child is SIGKILLed or SIGSTOPped and the time until the
// watcher's executor reports the link LOST is recorded. Rounds alternate the
// two signals; the child is restarted under the same uuid for every round (a
// controller restarting), so stale news of a previous incarnation would show
// up as a false alarm. Two timings: the default (100 ms x 3) and a short one.
// Prints progress on stderr and one JSON object on stdout (and to --out).
// Exit 1 on a false alarm, a loss never detected, or (with --max-ratio) a
// detection slower than that many leases.
//
// DDS domain 117 by default (benchmarks and the cell own 100-119). Must run
// inside the loopback-only namespace (scripts/netns-run.sh).
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "mtc/bench/cli.hpp"
#include "mtc/dds/equipment.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

struct Options {
  int rounds = 20;  // per signal and timing
  int short_heartbeat_ms = 20;
  int missed = 3;
  int domain = 117;
  std::string transport = "loopback-udp";
  int drop_percent = 0;         // both sides, Fast DDS test transport: every n-th
  int random_drop_percent = 0;  // both sides, each DATA at random
  int quiet_s = 0;              // healthy link watched for false alarms, per timing
  std::string max_ratio;        // empty: no bound on the exit code
  std::string out;
  // Internal: the child process.
  bool child = false;
  int child_heartbeat_ms = 100;
};

constexpr const char* kAbout =
    "Comms-loss detection time: a watcher equipment pairs with a responder in a child\n"
    "process, which is then SIGKILLed or SIGSTOPped at a random phase of its heartbeat;\n"
    "the time until the watcher reports the link LOST is recorded. --rounds of each signal\n"
    "at the default timing (100 ms x 3) and at --short-heartbeat-ms x --missed; the child\n"
    "restarts under the same uuid each round. JSON on stdout (and in --out): p50/p99/max\n"
    "per series against lease + 25 %, false alarms. Exit 1 on a false alarm, an undetected\n"
    "loss, or a detection over --max-ratio leases. --drop-percent loses that share of DATA\n"
    "submessages in both directions; --quiet-seconds first watches a healthy link for false\n"
    "alarms. Runs inside the loopback-only namespace (scripts/netns-run.sh).";

std::optional<int> parse_args(int argc, char** argv, Options& o) {
  mtc::bench::Cli cli("mtc-bench-detection", kAbout);
  cli.integer("--rounds", o.rounds, 1, 1000, "rounds per signal and timing")
      .integer("--short-heartbeat-ms", o.short_heartbeat_ms, 5, 1000,
               "heartbeat of the short timing")
      .integer("--missed", o.missed, 2, 100, "missed heartbeats of the short timing")
      .integer("--domain", o.domain, 0, 232, "DDS domain id")
      .choice("--transport", o.transport, {"loopback", "loopback-udp"},
              "loopback = SHM + UDP; loopback-udp leaves no SHM segments behind killed children")
      .integer("--drop-percent", o.drop_percent, 0, 90,
               "DATA submessages dropped by both sides, every n-th (Fast DDS test transport)")
      .integer("--random-drop-percent", o.random_drop_percent, 0, 90,
               "DATA submessages dropped by both sides at random (bursts happen)")
      .integer("--quiet-seconds", o.quiet_s, 0, 3600,
               "per timing, first watch a healthy link this long and count false alarms")
      .text("--max-ratio", "R", o.max_ratio, "exit 1 when a detection exceeds R x the lease")
      .text("--out", "FILE", o.out, "also write the JSON summary there")
      .internal_options_follow()
      .flag("--child", o.child, "run the responder side until killed")
      .integer("--child-heartbeat-ms", o.child_heartbeat_ms, 5, 1000, "its heartbeat");
  return cli.parse(argc, argv);
}

constexpr const char* kWatcher = "det-watcher";
constexpr const char* kResponder = "det-responder";

void set_transport(const Options& o, mtc::dds::EquipmentOptions& eo) {
  if (o.drop_percent > 0 || o.random_drop_percent > 0) {
    eo.transport = mtc::qos::Transport::LoopbackTest;
    eo.faults.drop_data_percent = static_cast<std::uint8_t>(o.drop_percent);
    eo.faults.random_drop_data_percent = static_cast<std::uint8_t>(o.random_drop_percent);
    return;
  }
  eo.transport =
      o.transport == "loopback" ? mtc::qos::Transport::Loopback : mtc::qos::Transport::LoopbackUdp;
}

mtc::qos::Timing timing(int heartbeat_ms, int missed) {
  mtc::qos::Timing t;
  t.heartbeat = milliseconds(heartbeat_ms);
  t.missed_heartbeats = missed;
  return t;
}

// The child: the responder side until killed (or its parent dies).
int run_child(const Options& o) {
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  mtc::dds::EquipmentOptions eo;
  eo.domain_id = o.domain;
  eo.device_uuid = kResponder;
  set_transport(o, eo);
  eo.timing = timing(o.child_heartbeat_ms, o.missed);
  mtc::dds::Equipment eq(eo);
  eq.add_interface({"mh1", mtc::core::InterfaceType::MaterialHandler, "", {kWatcher, "mh1"}});
  mtc::dds::ResponderCallbacks rc;
  rc.on_request = [](mtc::dds::Responder& r) { r.complete(); };
  eq.add_responder("mh1", mtc::core::Service::MaterialLoad, rc);
  eq.start();
  for (;;) pause();  // until a signal ends the process
}

// The watcher's view of its one link, filled by the executor's callbacks.
class LinkWatch {
 public:
  void on_link(const mtc::dds::LinkEvent& e) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (e.current == mtc::dds::LinkState::Up) {
      up_ = true;
    } else if (e.current == mtc::dds::LinkState::Lost) {
      up_ = false;
      if (armed_) {
        lost_at_ = Clock::now();
        armed_ = false;
      } else {
        ++false_alarms_;
        std::cerr << "  false alarm: " << e.cause << "\n";
      }
    }
    cv_.notify_all();
  }
  bool wait_up(Clock::duration timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    return cv_.wait_for(lock, timeout, [this] { return up_; });
  }
  // Arms the watch for the loss about to be caused; returns its instant.
  Clock::time_point arm() {
    std::lock_guard<std::mutex> lock(mutex_);
    armed_ = true;
    lost_at_.reset();
    return Clock::now();
  }
  std::optional<Clock::time_point> wait_lost(Clock::duration timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    cv_.wait_for(lock, timeout, [this] { return lost_at_.has_value(); });
    armed_ = false;
    return lost_at_;
  }
  int false_alarms() {
    std::lock_guard<std::mutex> lock(mutex_);
    return false_alarms_;
  }

 private:
  std::mutex mutex_;
  std::condition_variable cv_;
  bool up_ = false;
  bool armed_ = false;
  std::optional<Clock::time_point> lost_at_;
  int false_alarms_ = 0;
};

struct Series {
  int heartbeat_ms = 0;
  int missed = 0;
  int signal = SIGKILL;
  std::vector<double> detections_ms;
  int undetected = 0;
};

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<std::size_t>(std::llround(p * static_cast<double>(v.size() - 1)));
  return v[std::min(rank, v.size() - 1)];
}

// Starts the child with the same binary (fork, then exec at once: the
// watcher's DDS threads do not survive a fork, the exec'd child starts clean).
pid_t spawn_child(const Options& o, int heartbeat_ms) {
  const std::vector<std::string> args = {"/proc/self/exe",
                                         "--child",
                                         "--child-heartbeat-ms",
                                         std::to_string(heartbeat_ms),
                                         "--missed",
                                         std::to_string(o.missed),
                                         "--domain",
                                         std::to_string(o.domain),
                                         "--transport",
                                         o.transport,
                                         "--drop-percent",
                                         std::to_string(o.drop_percent),
                                         "--random-drop-percent",
                                         std::to_string(o.random_drop_percent)};
  std::vector<char*> argv;
  argv.reserve(args.size() + 1);
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    execv(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

void reap(pid_t pid) {
  kill(pid, SIGKILL);  // a stopped child too
  int status = 0;
  waitpid(pid, &status, 0);
}

// A healthy link for --quiet-seconds: every loss reported meanwhile is a
// false alarm (LinkWatch counts it). False when the child never came up.
bool watch_quietly(const Options& o, LinkWatch& watch, int heartbeat_ms, int missed) {
  const pid_t child = spawn_child(o, heartbeat_ms);
  if (child < 0 || !watch.wait_up(std::chrono::seconds(30))) {
    if (child > 0) reap(child);
    return false;
  }
  const int before = watch.false_alarms();
  std::this_thread::sleep_for(std::chrono::seconds(o.quiet_s));  // the observation window
  std::cerr << "  " << heartbeat_ms << " ms x " << missed << "  quiet " << o.quiet_s << " s at "
            << o.drop_percent + o.random_drop_percent
            << " % loss: " << watch.false_alarms() - before << " false alarms\n";
  watch.arm();  // the loss the reap causes is not a false alarm
  reap(child);
  watch.wait_lost(std::chrono::seconds(10));
  return true;
}

// One timing: a watcher for all its rounds, a child per round. Returns the
// false alarms seen, or -1 when a child never came up.
int run_timing(const Options& o, int heartbeat_ms, int missed, std::vector<Series>& out,
               std::mt19937& random) {
  LinkWatch watch;
  mtc::dds::EquipmentOptions eo;
  eo.domain_id = o.domain;
  eo.device_uuid = kWatcher;
  set_transport(o, eo);
  eo.timing = timing(heartbeat_ms, missed);
  mtc::dds::EquipmentCallbacks cb;
  cb.on_link = [&watch](const mtc::dds::LinkEvent& e) { watch.on_link(e); };
  mtc::dds::Equipment watcher(eo, cb);
  watcher.add_interface(
      {"mh1", mtc::core::InterfaceType::MaterialHandler, "", {kResponder, "mh1"}});
  watcher.add_requester("mh1", mtc::core::Service::MaterialLoad);
  watcher.start();
  const auto lease = eo.timing.lease();
  Series kill_series{heartbeat_ms, missed, SIGKILL, {}, 0};
  Series stop_series{heartbeat_ms, missed, SIGSTOP, {}, 0};
  std::uniform_int_distribution<int> phase_us(0, heartbeat_ms * 1000 - 1);
  if (o.quiet_s > 0 && !watch_quietly(o, watch, heartbeat_ms, missed)) return -1;
  for (int round = 0; round < 2 * o.rounds; ++round) {
    auto& series = round % 2 == 0 ? kill_series : stop_series;
    const pid_t child = spawn_child(o, heartbeat_ms);
    if (child < 0 || !watch.wait_up(std::chrono::seconds(30))) {
      std::cerr << "mtc-bench-detection: the responder did not come up\n";
      if (child > 0) reap(child);
      return -1;
    }
    // A few heartbeats of steady state, then a random phase of one: a
    // benchmark's schedule, not a synchronisation.
    std::this_thread::sleep_for(3 * eo.timing.heartbeat +
                                std::chrono::microseconds(phase_us(random)));
    const auto t0 = watch.arm();
    kill(child, series.signal);
    const auto lost = watch.wait_lost(10 * lease + std::chrono::seconds(5));
    if (lost) {
      series.detections_ms.push_back(std::chrono::duration<double, std::milli>(*lost - t0).count());
    } else {
      ++series.undetected;
    }
    reap(child);
    std::cerr << "  " << heartbeat_ms << " ms x " << missed << "  "
              << (series.signal == SIGKILL ? "SIGKILL" : "SIGSTOP") << "  round " << round / 2 + 1
              << ": "
              << (lost ? std::to_string(series.detections_ms.back()) + " ms" : "not detected")
              << "\n";
  }
  out.push_back(kill_series);
  out.push_back(stop_series);
  return watch.false_alarms();
}

std::string series_json(const Series& s, double max_ratio) {
  const double lease = s.heartbeat_ms * s.missed;
  const double bound = 1.25 * lease;
  const auto within = std::count_if(s.detections_ms.begin(), s.detections_ms.end(),
                                    [bound](double d) { return d <= bound; });
  std::ostringstream j;
  j.setf(std::ios::fixed);
  j.precision(1);
  j << "{\"signal\":\"" << (s.signal == SIGKILL ? "SIGKILL" : "SIGSTOP")
    << "\",\"heartbeat_ms\":" << s.heartbeat_ms << ",\"missed_heartbeats\":" << s.missed
    << ",\"lease_ms\":" << lease << ",\"bound_ms\":" << bound << ",\"n\":" << s.detections_ms.size()
    << ",\"undetected\":" << s.undetected << ",\"p50_ms\":" << percentile(s.detections_ms, 0.5)
    << ",\"p99_ms\":" << percentile(s.detections_ms, 0.99) << ",\"max_ms\":"
    << (s.detections_ms.empty() ? 0
                                : *std::max_element(s.detections_ms.begin(), s.detections_ms.end()))
    << ",\"min_ms\":"
    << (s.detections_ms.empty() ? 0
                                : *std::min_element(s.detections_ms.begin(), s.detections_ms.end()))
    << ",\"within_bound\":" << within;
  if (max_ratio > 0) j << ",\"max_ratio\":" << max_ratio;
  j << ",\"detections_ms\":[";
  for (std::size_t i = 0; i < s.detections_ms.size(); ++i) {
    j << (i > 0 ? "," : "") << s.detections_ms[i];
  }
  j << "]}";
  return j.str();
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (const auto exit_code = parse_args(argc, argv, o)) return *exit_code;
  if (o.child) return run_child(o);
  double max_ratio = 0;
  if (!o.max_ratio.empty()) {
    char* end = nullptr;
    max_ratio = std::strtod(o.max_ratio.c_str(), &end);
    if (*end != '\0' || !(max_ratio > 0)) {
      std::cerr << "mtc-bench-detection: --max-ratio expects a positive number, got '"
                << o.max_ratio << "'\n";
      return 2;
    }
  }
  std::mt19937 random(12345);
  std::vector<Series> series;
  int false_alarms = 0;
  const mtc::qos::Timing defaults;
  for (const auto& [hb, missed] : {std::pair<int, int>{static_cast<int>(defaults.heartbeat.count()),
                                                       defaults.missed_heartbeats},
                                   std::pair<int, int>{o.short_heartbeat_ms, o.missed}}) {
    const int alarms = run_timing(o, hb, missed, series, random);
    if (alarms < 0) return 1;
    false_alarms += alarms;
  }
  bool pass = false_alarms == 0;
  std::ostringstream json;
  json << "{\"benchmark\":\"detection\",\"transport\":\""
       << (o.drop_percent + o.random_drop_percent > 0 ? "test" : o.transport)
       << "\",\"drop_percent\":" << o.drop_percent
       << ",\"random_drop_percent\":" << o.random_drop_percent << ",\"quiet_seconds\":" << o.quiet_s
       << ",\"rounds\":" << o.rounds << ",\"false_alarms\":" << false_alarms << ",\"series\":[";
  for (std::size_t i = 0; i < series.size(); ++i) {
    const auto& s = series[i];
    json << (i > 0 ? "," : "") << series_json(s, max_ratio);
    pass = pass && s.undetected == 0;
    const double lease = s.heartbeat_ms * s.missed;
    for (double d : s.detections_ms) pass = pass && (max_ratio <= 0 || d <= max_ratio * lease);
    std::cerr << (s.signal == SIGKILL ? "SIGKILL" : "SIGSTOP") << " lease " << lease << " ms: p50 "
              << percentile(s.detections_ms, 0.5) << " ms, p99 "
              << percentile(s.detections_ms, 0.99) << " ms (bound " << 1.25 * lease
              << " ms), undetected " << s.undetected << "\n";
  }
  json << "],\"pass\":" << (pass ? "true" : "false") << "}\n";
  std::cout << json.str();
  if (!o.out.empty()) std::ofstream(o.out) << json.str();
  return pass ? 0 : 1;
}
