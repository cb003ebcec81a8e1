// Transition and handshake latency through mtc::dds::Equipment.
//
// A requester device ("bench-requester") asks a responder device
// ("bench-responder") for MATERIAL_LOAD over and over; the responder accepts
// at once (auto_accept) and completes in its on_request callback, so every
// figure is protocol and middleware cost, no simulated work.
//   transition: for each change of the responder's RESPONSE (ACTIVE,
//               COMPLETE, READY), the responder's source time of the change
//               until the requester's executor applied it to its state
//               machine (TransitionEvent step_time_ns - trigger_source_time_ns;
//               both CLOCK_REALTIME on one host).
//   handshake:  request() called until the requester has seen the response
//               back at READY: Table 1 steps 1-8, both sides READY.
// The responder runs in this process (two participants; the runtime turns
// Fast DDS intra-process delivery off, so they talk through the transport)
// or in a forked peer process over SHM+UDP or UDP only.
#include "equipment_latency.hpp"

#include <unistd.h>

#include <algorithm>
#include <condition_variable>
#include <future>
#include <iostream>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "mtc/bench/peer_process.hpp"
#include "mtc/bench/proc_cpu.hpp"
#include "mtc/dds/detail/topics.hpp"
#include "mtc/dds/equipment.hpp"

namespace mtc::bench {
namespace {

using core::Service;
using namespace std::chrono_literals;

constexpr const char* kRequester = "bench-requester";
constexpr const char* kResponder = "bench-responder";

// Each round's devices get names of their own: an equipment that comes back
// under the name of one that just left (same domain, seconds later) is
// another test; here every round is a first meeting of two new devices.
std::string device_name(const char* role, int round) {
  return std::string(role) + "-" + std::to_string(round);
}
constexpr const char* kInterface = "mh";

// How both ends step (set_stepping); set before a series or peer starts.
Stepping g_stepping = Stepping::Default;
// The middleware of both ends of the series running now (the peer is told
// with --cyclone-equipment).
dds::Middleware g_middleware = dds::Middleware::FastDds;

dds::EquipmentOptions equipment_options(const std::string& uuid, int domain, qos::Transport t) {
  dds::EquipmentOptions o;
  o.domain_id = domain;
  o.device_uuid = uuid;
  o.transport = t;
  // Every FAIL (e.g. a false comms-loss alarm on a loaded machine) clears
  // itself, so one bad handshake cannot stall the run; it is counted.
  o.recovery = dds::RecoveryPolicy::Always;
  apply(g_stepping, o);
  o.middleware = g_middleware;
  return o;
}

dds::InterfaceConfig interface_to(const std::string& peer) {
  dds::InterfaceConfig c;
  c.id = kInterface;
  c.type = core::InterfaceType::MaterialHandler;
  c.counterpart = {peer, kInterface};
  return c;
}

// The responder device; completes every request from its callback.
// The runtime's notes about false loss alarms it filtered out would only
// clutter the benchmark's output; anything else still goes to stderr.
void quiet_diagnostic(const std::string& text) {
  if (text.rfind("ignored", 0) != 0) {
    std::cerr << "runtime: " << text << "\n";
  }
}

std::unique_ptr<dds::Equipment> make_responder(int domain, qos::Transport t, int round) {
  dds::EquipmentCallbacks callbacks;
  callbacks.on_diagnostic = quiet_diagnostic;
  auto e = std::make_unique<dds::Equipment>(
      equipment_options(device_name(kResponder, round), domain, t), callbacks);
  e->add_interface(interface_to(device_name(kRequester, round)));
  dds::ResponderCallbacks cb;
  // Never wait inside a callback; and no future, whose settling costs a system call.
  cb.on_request = [](dds::Responder& r) { r.complete(nullptr); };
  e->add_responder(kInterface, Service::MaterialLoad, cb);
  e->start();
  return e;
}

// What the requester's executor reports, handed to the benchmark thread.
class Probe {
 public:
  dds::EquipmentCallbacks callbacks() {
    dds::EquipmentCallbacks cb;
    cb.on_transition = [this](const dds::TransitionEvent& e) { on_transition(e); };
    cb.on_counterpart_value = [this](const dds::ObservedValue& v) { on_value(v); };
    cb.on_diagnostic = quiet_diagnostic;
    return cb;
  }

  void arm() {
    std::lock_guard<std::mutex> lock(mutex_);
    ready_seen_ns_ = 0;
    completed_ = false;
    transitions_.clear();
    legs_.clear();
  }

  // Waits for the requester to see the response back at READY after COMPLETE.
  std::int64_t wait_both_ready(std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    cv_.wait_for(lock, timeout, [&] { return ready_seen_ns_ != 0; });
    return ready_seen_ns_;
  }

  std::vector<double> take_transitions() {
    std::lock_guard<std::mutex> lock(mutex_);
    return std::move(transitions_);
  }

  std::map<std::string, std::vector<double>> take_legs() {
    std::lock_guard<std::mutex> lock(mutex_);
    return std::move(legs_);
  }

 private:
  // Response ACTIVE and COMPLETE change the requester's machine: timed from
  // its TransitionEvent.
  void on_transition(const dds::TransitionEvent& e) {
    const auto event = e.step.event;
    const bool seen = event == core::Event::SeenActive || event == core::Event::SeenComplete;
    if (!seen || e.trigger_source_time_ns == 0) {
      return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    transitions_.push_back(static_cast<double>(e.step_time_ns - e.trigger_source_time_ns) / 1000.0);
    add_legs(e);
    if (event == core::Event::SeenComplete) {
      completed_ = true;
    }
  }

  // The response's return to READY (step 8) leaves the requester's machine
  // as it is, so no TransitionEvent: it is timed when the executor hands
  // the new value to the application, the same point in the pipeline.
  void on_value(const dds::ObservedValue& v) {
    if (v.redelivered || v.state.interaction() != core::InteractionState::Ready) {
      return;
    }
    const auto now = dds::detail::topics::realtime_ns();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!completed_ || ready_seen_ns_ != 0) {
        return;
      }
      transitions_.push_back(static_cast<double>(now - v.source_time_ns) / 1000.0);
      ready_seen_ns_ = now;
    }
    cv_.notify_all();
  }

  // The responder's write until our listener had the sample (the
  // middleware: serialising, the transport, the wake-up of our receive
  // thread), then until the step, and the requester's own write of READY
  // after COMPLETE (Fast DDS or Cyclone's write call).
  void add_legs(const dds::TransitionEvent& e) {
    if (e.trigger_receive_time_ns == 0) {
      return;
    }
    auto us = [](std::int64_t from, std::int64_t to) {
      return static_cast<double>(to - from) / 1e3;
    };
    legs_["transit"].push_back(us(e.trigger_source_time_ns, e.trigger_receive_time_ns));
    legs_["step"].push_back(us(e.trigger_receive_time_ns, e.step_time_ns));
    if (e.publish_time_ns != 0) {
      legs_["write"].push_back(us(e.step_time_ns, e.publish_time_ns));
    }
  }

  std::mutex mutex_;
  std::condition_variable cv_;
  std::map<std::string, std::vector<double>> legs_;
  std::vector<double> transitions_;
  std::int64_t ready_seen_ns_ = 0;
  bool completed_ = false;
};

struct PairRun {
  Series transition;
  Series handshake;
  int stalls = 0;  // requests that never got an outcome
};

// Ends a series that cannot go on: says why on stderr and counts the
// `not_run` timed handshakes left, plus `lost` of the current one, as timeouts.
void stop_series(PairRun& run, const std::string& why, int not_run, std::size_t lost) {
  std::cerr << "equipment latency: " << why << "; " << not_run
            << " timed handshakes of this series not run\n";
  run.handshake.timeouts += static_cast<std::size_t>(not_run) + lost;
  ++run.stalls;
}

// One handshake's transitions, and their legs, into the series.
void add_transitions(Probe& probe, Series& transition) {
  for (double v : probe.take_transitions()) {
    transition.samples_us.push_back(v);
  }
  append_legs(transition, probe.take_legs());
}

// Runs `handshakes` (after a warm-up) against a responder that is already
// up (thread or peer process `peer`, whose CPU time is counted too).
PairRun run_requester(int domain, qos::Transport t, int handshakes, pid_t peer, int round) {
  Probe probe;
  dds::Equipment eq(equipment_options(device_name(kRequester, round), domain, t),
                    probe.callbacks());
  eq.add_interface(interface_to(device_name(kResponder, round)));
  auto& req = eq.add_requester(kInterface, Service::MaterialLoad);
  eq.start();
  PairRun run;
  const int warmup = 20;
  int failures_in_a_row = 0;
  double cpu0 = 0;
  for (int i = 0; i < warmup + handshakes; ++i) {
    if (i == warmup) {
      cpu0 = cpu_seconds_both(peer);
    }
    probe.arm();
    const auto t0 = dds::detail::topics::realtime_ns();
    // The first request also waits for discovery and pairing.
    auto pending = req.request(dds::RequestOptions{i == 0 ? 10000ms : 2000ms});
    if (pending.wait_for(15000ms) != std::future_status::ready) {
      // A request that never ends (no outcome 15 s on: no time limit fired
      // either) leaves the requester ACTIVE for good: give up on this series
      // rather than hang the run, and say so.
      stop_series(run, "handshake " + std::to_string(i) + " got no outcome in 15 s",
                  handshakes - std::max(0, i - warmup), 0);
      break;
    }
    const auto result = pending.get();
    const auto both_ready =
        result.outcome == dds::Outcome::Completed ? probe.wait_both_ready(5000ms) : std::int64_t{0};
    failures_in_a_row = both_ready == 0 ? failures_in_a_row + 1 : 0;
    if (failures_in_a_row == 5) {
      // Five in a row is no noise: a side is stuck. Say so, and stop here
      // instead of spending seconds on each handshake left.
      stop_series(run,
                  "5 handshakes in a row failed (last: " +
                      std::string(dds::to_string(result.outcome)) + ")",
                  handshakes - std::max(0, i + 1 - warmup), i < warmup ? 0 : 1);
      break;
    }
    if (i < warmup) {
      continue;
    }
    if (both_ready == 0) {
      ++run.handshake.timeouts;
      continue;
    }
    run.handshake.samples_us.push_back(static_cast<double>(both_ready - t0) / 1000.0);
    add_transitions(probe, run.transition);
  }
  // Idle time between handshakes (heartbeats) is counted too; there is none
  // to speak of: the next request follows at once.
  const auto timed = run.handshake.samples_us.size();
  if (timed > 0 && run.stalls == 0) {
    run.handshake.cpu_us_per_op = (cpu_seconds_both(peer) - cpu0) * 1e6 / handshakes;
  }
  return run;
}

// The series' transport as its name spells it; Cyclone's carry the
// middleware too ("cyclone_udp_loopback").
std::string transport_name(qos::Transport t) {
  const std::string name = t == qos::Transport::LoopbackUdp ? "udp_loopback" : "shm_udp";
  return g_middleware == dds::Middleware::Cyclone ? "cyclone_" + name : name;
}

pid_t spawn_peer(int domain, qos::Transport t, int round) {
  std::vector<std::string> args = {"--equipment-peer",
                                   "--transport",
                                   t == qos::Transport::LoopbackUdp ? "udp" : "shm",
                                   "--domain",
                                   std::to_string(domain),
                                   "--round",
                                   std::to_string(round)};
  append_peer_flag(g_stepping, args);
  if (g_middleware == dds::Middleware::Cyclone) {
    args.emplace_back("--cyclone-equipment");
  }
  return exec_self("mtc-bench-dds-latency", args);
}

void stop_peer(pid_t pid) {
  stop_child(pid, std::chrono::seconds(10));
}

PairRun run_config(int domain, qos::Transport t, int processes, int handshakes, int round) {
  std::cerr << "equipment latency: " << transport_name(t) << ", " << processes << " process(es), "
            << handshakes << " handshakes\n";
  PairRun run;
  if (processes == 1) {
    auto responder = make_responder(domain, t, round);
    run = run_requester(domain, t, handshakes, 0, round);
  } else {
    const pid_t peer = spawn_peer(domain, t, round);
    try {
      run = run_requester(domain, t, handshakes, peer, round);
    } catch (...) {
      stop_peer(peer);
      throw;
    }
    stop_peer(peer);
  }
  const std::string suffix = "_" + transport_name(t) + "_" + std::to_string(processes) + "proc" +
                             series_suffix(g_stepping);
  for (Series* s : {&run.transition, &run.handshake}) {
    s->layer = "mtc_equipment";
    s->transport = transport_name(t);
    s->processes = processes;
    s->stepping = to_string(g_stepping);
  }
  run.transition.metric = "transition";
  run.transition.name = "mtc_transition" + suffix;
  run.handshake.metric = "handshake";
  run.handshake.name = "mtc_handshake" + suffix;
  return run;
}

}  // namespace

std::string series_suffix(Stepping s) {
  return s == Stepping::Default ? std::string() : std::string("_") + to_string(s);
}

void set_stepping(Stepping s) {
  g_stepping = s;
}

std::vector<Series> run_equipment_series(const EquipmentBenchOptions& options) {
  std::vector<Series> all;
  const struct {
    qos::Transport transport;
    int processes;
  } configs[] = {{qos::Transport::Loopback, 1},
                 {qos::Transport::Loopback, 2},
                 {qos::Transport::LoopbackUdp, 2}};
  int domain = options.first_domain_id;
  for (const auto& c : configs) {
    PairRun run = run_config(domain++, c.transport, c.processes, options.handshakes, options.round);
    all.push_back(std::move(run.transition));
    all.push_back(std::move(run.handshake));
  }
  // Both ends on Cyclone DDS (issue 9 section 3's target), when built in:
  // UDP on loopback, as Cyclone 0.10 in Debian has no shared memory.
  if (dds::middleware_available(dds::Middleware::Cyclone)) {
    g_middleware = dds::Middleware::Cyclone;
    PairRun run = run_config(options.cyclone_domain_id, qos::Transport::LoopbackUdp, 2,
                             options.handshakes, options.round);
    g_middleware = dds::Middleware::FastDds;
    all.push_back(std::move(run.transition));
    all.push_back(std::move(run.handshake));
  }
  return all;
}

int run_equipment_peer(int domain, bool udp_only, int round, bool cyclone) {
  if (cyclone) g_middleware = dds::Middleware::Cyclone;
  const sigset_t stop_signals = block_stop_signals();  // before the runtime starts threads
  auto responder = make_responder(
      domain, udp_only ? qos::Transport::LoopbackUdp : qos::Transport::Loopback, round);
  wait_for_stop_signal(stop_signals);
  return 0;
}

}  // namespace mtc::bench
