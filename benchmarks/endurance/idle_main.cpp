// mtc-bench-idle: what an idle equipment costs, and whether that cost stays
// flat. One process runs an Equipment with N MATERIAL_HANDLER interfaces,
// each with a MATERIAL_LOAD requester; a forked child runs the counterpart
// with the matching responders. Nothing is requested: both only heartbeat
// (the default 100 ms x 3). Every --interval seconds both processes are
// sampled (CPU, RSS, open fds, threads, counterpart values handed to the
// application and DDS samples written and received per second, heartbeats
// included).
// Prints progress on stderr and one JSON object on stdout (and to --out);
// benchmarks/endurance/plot.py draws it. Exit 1 when the CPU of the last
// window exceeds --cpu-ratio times the first, a link was lost, or a process
// died.
//
// DDS domain 116 by default (benchmarks and the cell own 100-119).
// Must run inside the loopback-only namespace: benchmarks/endurance/run.sh
// --idle does that.
#include <signal.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>
#include <new>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "mtc/bench/cli.hpp"
#include "mtc/bench/transport.hpp"
#include "mtc/dds/equipment.hpp"
#include "proc_sampler.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using mtc::bench::json_number;
using mtc::bench::ProcSeries;

struct Options {
  int interfaces = 100;
  int duration_s = 600;
  int interval_s = 10;
  int window_s = 60;
  double cpu_ratio = 1.5;
  int domain = 116;
  std::string out;
};

constexpr const char* kAbout =
    "An equipment with N MATERIAL_HANDLER interfaces (a MATERIAL_LOAD requester each) and,\n"
    "in a forked child, its counterpart with the responders, idling at the default 100 ms x 3\n"
    "heartbeat. Once every link is up, both processes are sampled every interval (CPU, RSS,\n"
    "open fds, threads, values delivered and DDS samples written / received per second,\n"
    "heartbeats included). Progress and figures on stderr,\n"
    "one JSON object on stdout (and in --out); benchmarks/endurance/plot.py draws it.\n"
    "Exit 1 when the CPU of the last window exceeds --cpu-ratio x the first, a link was\n"
    "lost or a process died. Runs inside the loopback-only namespace (scripts/netns-run.sh).";

// nullopt: go on with the run; otherwise the exit code (0 after --help, 2
// after a usage error, both reported).
std::optional<int> parse_args(int argc, char** argv, Options& o) {
  std::string ratio = "1.5";
  mtc::bench::Cli cli("mtc-bench-idle", kAbout);
  cli.integer("--interfaces", o.interfaces, 1, 1000, "interfaces per equipment")
      .integer("--duration", o.duration_s, 1, 86400, "seconds measured once every link is up")
      .integer("--interval", o.interval_s, 1, 3600, "sampling period, seconds")
      .integer("--window", o.window_s, 1, 86400, "first and last CPU window compared, seconds")
      .text("--cpu-ratio", "R", ratio, "largest last/first window CPU ratio that passes")
      .integer("--domain", o.domain, 0, 232, "DDS domain id")
      .text("--out", "FILE", o.out, "also write the JSON summary there");
  if (const auto exit_code = cli.parse(argc, argv)) {
    return exit_code;
  }
  char* end = nullptr;
  o.cpu_ratio = std::strtod(ratio.c_str(), &end);
  if (*end != '\0' || !(o.cpu_ratio > 1.0)) {
    return cli.usage_error("--cpu-ratio expects a number above 1, got '" + ratio + "'");
  }
  if (o.window_s < o.interval_s || o.duration_s < 2 * o.window_s) {
    return cli.usage_error("need --window >= --interval and --duration >= 2 x --window");
  }
  return std::nullopt;
}

// What one side's callbacks count, in memory shared by both processes (an
// anonymous shared mapping made before the fork; lock-free atomics are
// address-free, so they work across processes).
struct SideCounters {
  std::atomic<std::uint64_t> values{0};  // counterpart values handed to the application
  // Equipment::traffic(), copied by the side itself (state + heartbeat samples).
  std::atomic<std::uint64_t> samples_received{0};
  std::atomic<std::uint64_t> samples_written{0};
  std::atomic<std::int32_t> links_up{0};
  std::atomic<std::uint32_t> lost{0};
  std::atomic<std::int32_t> started{0};  // 1 started, -1 failed to start
};
static_assert(std::atomic<std::uint64_t>::is_always_lock_free);

struct Shared {
  SideCounters requester;
  SideCounters responder;
};

Shared* map_shared() {
  void* p =
      mmap(nullptr, sizeof(Shared), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
  return p == MAP_FAILED ? nullptr : new (p) Shared();
}

constexpr const char* kRequesterUuid = "idle-requester";
constexpr const char* kResponderUuid = "idle-responder";

std::unique_ptr<mtc::dds::Equipment> make_side(const Options& o, bool requester,
                                               SideCounters& counters) {
  auto eo = mtc::bench::loopback<mtc::dds::EquipmentOptions>();
  eo.domain_id = o.domain;
  eo.device_uuid = requester ? kRequesterUuid : kResponderUuid;
  mtc::dds::EquipmentCallbacks cb;
  cb.on_counterpart_value = [&counters](const mtc::dds::ObservedValue&) {
    counters.values.fetch_add(1, std::memory_order_relaxed);
  };
  cb.on_link = [&counters](const mtc::dds::LinkEvent& e) {
    using mtc::dds::LinkState;
    if (e.current == LinkState::Up && e.previous != LinkState::Up) {
      counters.links_up.fetch_add(1);
    } else if (e.previous == LinkState::Up && e.current != LinkState::Up) {
      counters.links_up.fetch_sub(1);
    }
    if (e.current == LinkState::Lost) {
      counters.lost.fetch_add(1);
    }
  };
  auto eq = std::make_unique<mtc::dds::Equipment>(eo, cb);
  const std::string peer = requester ? kResponderUuid : kRequesterUuid;
  for (int i = 1; i <= o.interfaces; ++i) {
    const std::string id = "mh" + std::to_string(i);
    eq->add_interface({id, mtc::core::InterfaceType::MaterialHandler, "", {peer, id}});
    if (requester) {
      eq->add_requester(id, mtc::core::Service::MaterialLoad);
    } else {
      mtc::dds::ResponderCallbacks rc;
      rc.on_request = [](mtc::dds::Responder& r) { r.complete(); };
      eq->add_responder(id, mtc::core::Service::MaterialLoad, rc);
    }
  }
  eq->start();
  return eq;
}

void publish_traffic(const mtc::dds::Equipment& eq, SideCounters& counters) {
  const auto t = eq.traffic();
  counters.samples_received.store(t.values_received + t.heartbeats_received);
  counters.samples_written.store(t.values_written + t.heartbeats_written);
}

mtc::bench::DdsCounts counts_of(const SideCounters& c) {
  return {c.values.load(), c.samples_received.load(), c.samples_written.load()};
}

// The forked child: the responder side until SIGTERM (or the parent's
// death). SIGINT stays blocked: Ctrl-C is the parent's to handle, which
// stops the child once it has its figures.
int run_responder(const Options& o, Shared& shared) {
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGTERM);
  prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (getppid() == 1) {
    return 1;
  }
  std::unique_ptr<mtc::dds::Equipment> eq;
  try {
    eq = make_side(o, false, shared.responder);
  } catch (const std::exception& e) {
    std::cerr << "mtc-bench-idle: responder: " << e.what() << "\n";
    shared.responder.started.store(-1);
    return 1;
  }
  publish_traffic(*eq, shared.responder);  // its start-up writes before any sample
  shared.responder.started.store(1);
  // Publishes its traffic for the parent's samples until told to stop.
  const timespec period{0, 200L * 1000 * 1000};
  while (sigtimedwait(&stop_signals, nullptr, &period) < 0) {
    publish_traffic(*eq, shared.responder);
  }
  eq.reset();  // leaves the domain before the process ends
  return 0;
}

// Waits up to `d` for a stop signal or a child's death; returns the signal
// or 0 when `d` passed.
int wait_signal(const sigset_t& signals, Clock::duration d) {
  if (d < Clock::duration::zero()) {
    d = Clock::duration::zero();
  }
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(d).count();
  const timespec ts{static_cast<time_t>(ns / 1000000000), static_cast<long>(ns % 1000000000)};
  const int sig = sigtimedwait(&signals, nullptr, &ts);
  return sig < 0 ? 0 : sig;
}

// Until both sides have every link up; false on a timeout, a signal or a
// failed start. Polled: the other side's counters live in shared memory.
bool wait_links_up(const Options& o, const Shared& shared, const sigset_t& signals) {
  const auto deadline = Clock::now() + std::chrono::seconds(30 + o.interfaces / 2);
  while (Clock::now() < deadline) {
    if (shared.responder.started.load() < 0) {
      return false;
    }
    if (shared.requester.links_up.load() == o.interfaces &&
        shared.responder.links_up.load() == o.interfaces) {
      return true;
    }
    if (wait_signal(signals, std::chrono::milliseconds(100)) != 0) {
      return false;
    }
  }
  return false;
}

std::string or_dash(std::optional<double> value, int decimals = 1) {
  return value ? json_number(value, decimals) : "-";
}

// The 1-minute load average: CPU figures of a busy machine are noisy.
std::optional<double> load_average() {
  double one = 0;
  std::ifstream in("/proc/loadavg");
  if (!(in >> one)) {
    return std::nullopt;
  }
  return one;
}

struct Measured {
  ProcSeries requester;
  ProcSeries responder;
  double setup_s = 0;
  std::optional<double> load_start{};
  std::optional<double> load_end{};
  std::uint32_t lost_during[2] = {0, 0};
  std::string ended = "duration reached";
  bool lived = true;
};

// Samples both processes every interval until the duration, a stop signal
// or the child's death.
void measure(const Options& o, Shared& shared, const mtc::dds::Equipment& requester,
             const sigset_t& signals, Measured& m) {
  const std::uint32_t lost0[2] = {shared.requester.lost.load(), shared.responder.lost.load()};
  const auto t0 = Clock::now();
  for (int k = 0;; ++k) {
    const auto at = t0 + std::chrono::seconds(static_cast<long>(k) * o.interval_s);
    const int sig = wait_signal(signals, at - Clock::now());
    if (sig == SIGCHLD) {
      m.ended = "the responder process died";
      m.lived = false;
      break;
    }
    if (sig != 0) {
      m.ended = "interrupted by signal " + std::to_string(sig);
      break;
    }
    const double t = std::chrono::duration<double>(Clock::now() - t0).count();
    publish_traffic(requester, shared.requester);
    m.requester.sample(t, counts_of(shared.requester));
    if (!m.responder.sample(t, counts_of(shared.responder))) {
      m.ended = "the responder process is gone";
      m.lived = false;
      break;
    }
    const auto& a = m.requester.samples().back();
    const auto& b = m.responder.samples().back();
    std::cerr << "  " << static_cast<int>(t) << " s  requester " << or_dash(a.cpu_pct) << " % "
              << a.reading.rss_kb / 1024 << " MiB, " << or_dash(a.samples_written_per_s, 0)
              << " samples/s out, " << or_dash(a.samples_received_per_s, 0) << " in; responder "
              << or_dash(b.cpu_pct) << " % " << b.reading.rss_kb / 1024 << " MiB, "
              << or_dash(b.samples_written_per_s, 0) << " out, "
              << or_dash(b.samples_received_per_s, 0) << " in\n";
    if (t >= o.duration_s - 0.5) {
      break;
    }
  }
  m.lost_during[0] = shared.requester.lost.load() - lost0[0];
  m.lost_during[1] = shared.responder.lost.load() - lost0[1];
}

struct Verdict {
  const char* name;
  bool pass;
  std::string detail;
};

std::vector<Verdict> verdicts(const Options& o, const Measured& m) {
  std::ostringstream cpu;
  bool flat = true;
  for (const ProcSeries* s : {&m.requester, &m.responder}) {
    const auto first = s->first_window_pct(o.window_s);
    const auto last = s->last_window_pct(o.window_s);
    flat = flat && first && last && *last <= o.cpu_ratio * *first;
    cpu << (s == &m.requester ? "" : "; ") << s->name() << " " << json_number(first, 2) << " -> "
        << json_number(last, 2) << " %";
  }
  const std::uint32_t lost = m.lost_during[0] + m.lost_during[1];
  return {
      {"cpu_flat", flat,
       "last <= " + json_number(o.cpu_ratio, 2) + " x first window: " + cpu.str()},
      {"no_comms_loss", lost == 0, std::to_string(lost) + " links lost while measuring"},
      {"processes_lived", m.lived, m.ended},
  };
}

bool all_pass(const std::vector<Verdict>& v) {
  return std::all_of(v.begin(), v.end(), [](const Verdict& x) { return x.pass; });
}

void write_json(std::ostream& out, const Options& o, const Measured& m) {
  const auto v = verdicts(o, m);
  out << "{\"benchmark\":\"idle\",\"title\":\"mtc-bench-idle: " << o.interfaces
      << " interfaces idling at the default heartbeat, sampled every " << o.interval_s
      << " s\",\"interfaces\":" << o.interfaces << ",\"duration_s\":" << o.duration_s
      << ",\"interval_s\":" << o.interval_s << ",\"window_s\":" << o.window_s
      << ",\"cpu_ratio_limit\":" << json_number(o.cpu_ratio, 2)
      << ",\"cores\":" << std::thread::hardware_concurrency() << ",\"domain\":" << o.domain
      << ",\"links_up_after_s\":" << json_number(m.setup_s, 2)
      << ",\"load_average_start\":" << json_number(m.load_start, 2)
      << ",\"load_average_end\":" << json_number(m.load_end, 2)
      << ",\"links_lost_while_measuring\":{\"requester\":" << m.lost_during[0]
      << ",\"responder\":" << m.lost_during[1] << "},\"ended\":\"" << m.ended
      << "\",\"processes\":[";
  m.requester.write_json(out, o.window_s);
  out << ",";
  m.responder.write_json(out, o.window_s);
  out << "],\"verdicts\":{";
  for (std::size_t i = 0; i < v.size(); ++i) {
    out << (i > 0 ? "," : "") << "\"" << v[i].name
        << "\":{\"pass\":" << (v[i].pass ? "true" : "false") << ",\"detail\":\"" << v[i].detail
        << "\"}";
  }
  out << "},\"pass\":" << (all_pass(v) ? "true" : "false") << "}\n";
}

void print_figures(const Options& o, const Measured& m) {
  for (const ProcSeries* s : {&m.requester, &m.responder}) {
    if (s->samples().empty()) {
      continue;
    }
    const auto& a = s->samples().front().reading;
    const auto& b = s->samples().back().reading;
    std::cerr << s->name() << ": CPU first " << o.window_s << " s "
              << json_number(s->first_window_pct(o.window_s), 2) << " %, last "
              << json_number(s->last_window_pct(o.window_s), 2) << " %; RSS " << a.rss_kb / 1024
              << " -> " << b.rss_kb / 1024 << " MiB; fds " << a.fds << " -> " << b.fds
              << "; threads " << a.threads << " -> " << b.threads << "; samples/s written "
              << json_number(s->samples_written_per_s(), 1) << ", received "
              << json_number(s->samples_received_per_s(), 1) << "\n";
  }
  for (const auto& v : verdicts(o, m)) {
    std::cerr << v.name << ": " << (v.pass ? "PASS" : "FAIL") << "  " << v.detail << "\n";
  }
}

int run(const Options& o, Shared& shared, pid_t child, const sigset_t& signals) {
  Measured m{ProcSeries("requester", getpid()), ProcSeries("responder", child)};
  std::unique_ptr<mtc::dds::Equipment> eq;
  try {
    eq = make_side(o, true, shared.requester);
  } catch (const std::exception& e) {
    std::cerr << "mtc-bench-idle: requester: " << e.what() << "\n";
    return 1;
  }
  const auto setup_start = Clock::now();
  if (!wait_links_up(o, shared, signals)) {
    std::cerr << "mtc-bench-idle: the " << o.interfaces << " links did not all come up (requester "
              << shared.requester.links_up.load() << ", responder "
              << shared.responder.links_up.load() << ")\n";
    return 1;
  }
  m.setup_s = std::chrono::duration<double>(Clock::now() - setup_start).count();
  std::cerr << "mtc-bench-idle: " << o.interfaces << " links up after " << json_number(m.setup_s, 2)
            << " s; measuring " << o.duration_s << " s\n";
  m.load_start = load_average();
  measure(o, shared, *eq, signals, m);
  m.load_end = load_average();
  kill(child, SIGTERM);
  eq.reset();
  int status = 0;
  waitpid(child, &status, 0);
  m.lived = m.lived && WIFEXITED(status) && WEXITSTATUS(status) == 0;
  print_figures(o, m);
  std::ostringstream json;
  write_json(json, o, m);
  std::cout << json.str();
  if (!o.out.empty()) {
    std::ofstream(o.out) << json.str();
  }
  return all_pass(verdicts(o, m)) ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (const auto exit_code = parse_args(argc, argv, o)) {
    return *exit_code;
  }
  Shared* shared = map_shared();
  if (shared == nullptr) {
    std::cerr << "mtc-bench-idle: mmap failed\n";
    return 1;
  }
  // Blocked before the fork and before any DDS thread exists, so every
  // thread of both processes inherits the mask and sigwait takes them.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGCHLD);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  std::cout.flush();
  std::cerr.flush();
  // Forked before the parent creates anything: no DDS thread to duplicate.
  const pid_t child = fork();
  if (child < 0) {
    std::cerr << "mtc-bench-idle: fork failed\n";
    return 1;
  }
  if (child == 0) {
    _exit(run_responder(o, *shared));
  }
  return run(o, *shared, child, signals);
}
