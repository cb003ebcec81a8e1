// mtc-bench-wakeup: what one thread hand-off costs on this machine, the unit
// every latency of the project is made of. A handshake is a chain of them:
// a middleware receive thread woken by a peer's write, an executor woken by
// a receive thread, a client's socket woken by the server.
//
// A waker thread notifies a sleeping wakee through a mutex and condition
// variable (how the runtime's executor and Fast DDS's threads are woken),
// then sleeps until the wakee answers. Timed: from just before the notify
// until the wakee runs ("wake"), and the notify call itself ("notify", the
// waker's own cost: on a VM guest it includes the exit that sends the
// inter-processor interrupt). Both threads on one CPU, then on two; each
// after an idle gap (0: at once), since a VM guest's idle vCPU halts and
// is woken through the hypervisor (docs/benchmarks.md, "Hand-offs between
// vCPUs"). No DDS, no network. JSON on stdout and with --out.
#include <pthread.h>
#include <sched.h>

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <iostream>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "../dds/latency_stats.hpp"
#include "mtc/bench/cli.hpp"
#include "mtc/bench/json_out.hpp"

namespace {

using Clock = std::chrono::steady_clock;

struct Options {
  int samples = 2000;
  std::string out;
};

struct Result {
  std::string placement;  // "same_cpu" or "other_cpu"
  int gap_us = 0;
  std::vector<double> wake_us;
  std::vector<double> notify_us;
};

// The two ends of one hand-off: `turn` says whose move it is.
struct HandOff {
  std::mutex mutex;
  std::condition_variable to_wakee;
  std::condition_variable to_waker;
  int turn = 0;  // 0: the waker's, 1: the wakee's, -1: stop
  Clock::time_point woke{};
};

bool pin_to(int cpu) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  return pthread_setaffinity_np(pthread_self(), sizeof set, &set) == 0;
}

void wakee(HandOff& h, int cpu) {
  pin_to(cpu);
  std::unique_lock<std::mutex> lock(h.mutex);
  for (;;) {
    h.to_wakee.wait(lock, [&] { return h.turn != 0; });
    if (h.turn < 0) return;
    h.woke = Clock::now();
    h.turn = 0;
    h.to_waker.notify_one();
  }
}

double us(Clock::duration d) {
  return std::chrono::duration<double, std::micro>(d).count();
}

Result measure(int waker_cpu, int wakee_cpu, int gap_us, int samples) {
  Result r;
  r.placement = waker_cpu == wakee_cpu ? "same_cpu" : "other_cpu";
  r.gap_us = gap_us;
  HandOff h;
  std::thread other([&] { wakee(h, wakee_cpu); });
  pin_to(waker_cpu);
  const int warmup = 50;
  for (int i = 0; i < warmup + samples; ++i) {
    if (gap_us > 0) std::this_thread::sleep_for(std::chrono::microseconds(gap_us));
    Clock::time_point before;
    Clock::time_point after;
    {
      std::lock_guard<std::mutex> lock(h.mutex);
      h.turn = 1;
      before = Clock::now();
    }
    h.to_wakee.notify_one();
    after = Clock::now();
    std::unique_lock<std::mutex> lock(h.mutex);
    h.to_waker.wait(lock, [&] { return h.turn == 0; });
    if (i >= warmup) {
      r.wake_us.push_back(us(h.woke - before));
      r.notify_us.push_back(us(after - before));
    }
  }
  {
    std::lock_guard<std::mutex> lock(h.mutex);
    h.turn = -1;
  }
  h.to_wakee.notify_one();
  other.join();
  return r;
}

std::string to_json(const std::vector<Result>& results, const std::vector<int>& cpus, int samples) {
  std::ostringstream json;
  json << "{\"benchmark\":\"wakeup\",\"unit\":\"us\",\"samples\":" << samples << ",\"cpus\":[";
  for (std::size_t i = 0; i < cpus.size(); ++i) json << (i == 0 ? "" : ",") << cpus[i];
  json << "],\"series\":[";
  char buf[320];
  for (std::size_t i = 0; i < results.size(); ++i) {
    const auto& r = results[i];
    const auto wake = mtc::bench::summarize(r.wake_us);
    const auto notify = mtc::bench::summarize(r.notify_us);
    std::snprintf(buf, sizeof buf,
                  "%s\n {\"placement\":\"%s\",\"gap_us\":%d,\"wake_p50\":%.1f,\"wake_p99\":%.1f,"
                  "\"notify_p50\":%.2f,\"notify_p99\":%.2f}",
                  i == 0 ? "" : ",", r.placement.c_str(), r.gap_us, wake.p50, wake.p99, notify.p50,
                  notify.p99);
    json << buf;
  }
  json << "\n]}\n";
  return json.str();
}

// The first two CPUs this process may run on (one when it has only one).
std::vector<int> usable_cpus() {
  cpu_set_t set;
  std::vector<int> cpus;
  if (sched_getaffinity(0, sizeof set, &set) != 0) return cpus;
  for (int c = 0; c < CPU_SETSIZE && cpus.size() < 2; ++c) {
    if (CPU_ISSET(c, &set) != 0) cpus.push_back(c);
  }
  return cpus;
}

constexpr const char* kAbout =
    "What one thread hand-off costs on this machine: a thread woken through a\n"
    "condition variable, on the waker's CPU and on another, each after idle gaps\n"
    "of 0, 200 and 1000 us (a VM guest's idle vCPU halts and is woken through the\n"
    "hypervisor). p50/p99 of the wake (notify until the wakee runs) and of the\n"
    "notify call. No DDS, no network. One JSON object on stdout and, with --out,\n"
    "in FILE: {\"benchmark\":\"wakeup\",\"series\":[{placement,gap_us,wake_p50,...}]}\n"
    "(benchmarks/run.sh: bench-results/wakeup.json).";

}  // namespace

int main(int argc, char** argv) {
  Options o;
  mtc::bench::Cli cli("mtc-bench-wakeup", kAbout);
  cli.integer("--samples", o.samples, 10, 1000000, "hand-offs per placement and gap")
      .text("--out", "FILE", o.out, "also write the JSON to FILE (default stdout only)");
  if (const auto exit_code = cli.parse(argc, argv)) return *exit_code;
  const auto cpus = usable_cpus();
  if (cpus.empty()) {
    std::cerr << "mtc-bench-wakeup: cannot read this process's CPUs\n";
    return 1;
  }
  std::vector<Result> results;
  for (const int gap : {0, 200, 1000}) {
    results.push_back(measure(cpus[0], cpus[0], gap, o.samples));
    if (cpus.size() > 1) results.push_back(measure(cpus[0], cpus[1], gap, o.samples));
    for (auto it = results.end() - (cpus.size() > 1 ? 2 : 1); it != results.end(); ++it) {
      const auto wake = mtc::bench::summarize(it->wake_us);
      std::fprintf(stderr, "%-9s gap %4d us: wake p50 %6.1f p99 %6.1f us, notify p50 %5.2f us\n",
                   it->placement.c_str(), gap, wake.p50, wake.p99,
                   mtc::bench::summarize(it->notify_us).p50);
    }
  }
  if (cpus.size() < 2) std::cerr << "mtc-bench-wakeup: one CPU only, no other_cpu series\n";
  return mtc::bench::emit_json(to_json(results, cpus, o.samples), o.out, "mtc-bench-wakeup");
}
