// mtc-bench-core: nanoseconds per state-machine step and per whole Table 1
// handshake in mtc::core. Prints Google Benchmark's table and always ends
// with one JSON summary line (Google Benchmark's own JSON goes to the file
// named by --benchmark_out=FILE):
//   {"benchmark":"core","transition_ns":...,"observation_ns":...,
//    "handshake_ns":...,"fail_recover_ns":...,"interface_tick_ns":...}
#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <string>

#include "mtc/bench/gbench_cli.hpp"
#include "mtc/core/interface_model.hpp"

namespace {

using mtc::core::InteractionState;
using mtc::core::InterfaceModel;
using mtc::core::InterfaceType;
using mtc::core::kAllServices;
using mtc::core::MachineOptions;
using mtc::core::Requester;
using mtc::core::Responder;
using mtc::core::Service;
using mtc::core::TimePoint;

constexpr TimePoint kNow{};

// One application command: READY <-> NOT_READY, two transitions per loop.
void BM_Transition(benchmark::State& state) {
  Requester rq(Service::MaterialLoad);
  rq.on_counterpart(InteractionState::Ready, kNow);
  for ([[maybe_unused]] auto _ : state) {
    benchmark::DoNotOptimize(rq.set_not_ready(kNow));
    benchmark::DoNotOptimize(rq.set_ready(kNow));
  }
  state.counters["steps_per_iteration"] = 2;
}
BENCHMARK(BM_Transition);

// One counterpart observation (guards + table lookup), two per loop.
void BM_Observation(benchmark::State& state) {
  Responder rs(Service::MaterialLoad);
  rs.on_counterpart(InteractionState::Ready, kNow);
  for ([[maybe_unused]] auto _ : state) {
    benchmark::DoNotOptimize(rs.on_counterpart(InteractionState::Active, kNow));
    benchmark::DoNotOptimize(rs.on_counterpart(InteractionState::Ready, kNow));
  }
  state.counters["steps_per_iteration"] = 2;
}
BENCHMARK(BM_Observation);

// Table 1 steps 1-8 between a requester and a responder (8 steps).
void BM_Handshake(benchmark::State& state) {
  Requester rq(Service::MaterialLoad);
  Responder rs(Service::MaterialLoad);
  rq.on_counterpart(rs.state(), kNow);
  rs.on_counterpart(rq.state(), kNow);
  for ([[maybe_unused]] auto _ : state) {
    rq.request(kNow);
    rs.on_counterpart(rq.state(), kNow);
    rs.accept(kNow);
    rq.on_counterpart(rs.state(), kNow);
    rs.complete(kNow);
    rq.on_counterpart(rs.state(), kNow);
    rs.on_counterpart(rq.state(), kNow);
    benchmark::DoNotOptimize(rq.on_counterpart(rs.state(), kNow));
  }
  if (rq.state() != InteractionState::Ready || rs.state() != InteractionState::Ready) {
    state.SkipWithError("handshake did not return to READY");
  }
}
BENCHMARK(BM_Handshake);

// Scenario 2 and recovery: responder fails mid-service, both recover.
void BM_FailRecover(benchmark::State& state) {
  Requester rq(Service::MaterialLoad);
  Responder rs(Service::MaterialLoad);
  rq.on_counterpart(rs.state(), kNow);
  rs.on_counterpart(rq.state(), kNow);
  for ([[maybe_unused]] auto _ : state) {
    rq.request(kNow);
    rs.on_counterpart(rq.state(), kNow);
    rs.accept(kNow);
    rq.on_counterpart(rs.state(), kNow);
    rs.fail(kNow);
    rq.on_counterpart(rs.state(), kNow);
    rs.on_counterpart(rq.state(), kNow);
    rq.recover(InteractionState::Ready, kNow);
    rs.recover(InteractionState::Ready, kNow);
    rs.on_counterpart(rq.state(), kNow);
    benchmark::DoNotOptimize(rq.on_counterpart(rs.state(), kNow));
  }
  if (rq.state() != InteractionState::Ready || rs.state() != InteractionState::Ready) {
    state.SkipWithError("recovery did not return to READY");
  }
}
BENCHMARK(BM_FailRecover);

// A runtime's timer callback on an interface with all ten services, nothing due.
void BM_InterfaceTickIdle(benchmark::State& state) {
  MachineOptions o;
  o.limits.response = std::chrono::seconds(5);
  InterfaceModel m(InterfaceType::MaterialHandler, o);
  for (const auto s : kAllServices) m.add_requester(s);
  for ([[maybe_unused]] auto _ : state) {
    benchmark::DoNotOptimize(m.next_deadline());
    benchmark::DoNotOptimize(m.on_tick(kNow));
  }
}
BENCHMARK(BM_InterfaceTickIdle);

// Console output as usual, plus the per-item figures for the summary line.
class SummaryReporter : public benchmark::ConsoleReporter {
 public:
  SummaryReporter() : ConsoleReporter(OO_Tabular) {}  // no colour codes in logs
  // CPU time per iteration (the machine is shared, so wall time is noisy),
  // divided by the steps per iteration where a benchmark does several.
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const auto& run : runs) {
      if (run.iterations == 0 || run.error_occurred) continue;
      double ns = run.GetAdjustedCPUTime();
      const auto steps = run.counters.find("steps_per_iteration");
      if (steps != run.counters.end() && steps->second.value > 0) ns /= steps->second.value;
      ns_[run.benchmark_name()] = ns;
    }
  }
  double ns(const std::string& name) const {
    const auto it = ns_.find(name);
    return it == ns_.end() ? -1.0 : it->second;
  }

 private:
  std::map<std::string, double> ns_;
};

constexpr const char* kAbout =
    "CPU time of the pure interaction model (mtc::core, no DDS): one state-machine\n"
    "transition, one counterpart observation, a whole Table 1 handshake (8 steps),\n"
    "a failure and its recovery, an idle tick of an interface with ten services.\n"
    "Output on stdout: Google Benchmark's table, then one JSON summary line\n"
    "  {\"benchmark\":\"core\",\"transition_ns\":...,\"observation_ns\":...,\n"
    "   \"handshake_ns\":...,\"fail_recover_ns\":...,\"interface_tick_ns\":...}\n"
    "in CPU ns per step for transition and observation, per whole loop for the\n"
    "others, -1 for one that did not run. benchmarks/run.sh keeps the library's\n"
    "JSON (--benchmark_out) in bench-results/core.json.";

}  // namespace

int main(int argc, char** argv) {
  if (const auto exit_code =
          mtc::bench::initialize_google_benchmark(&argc, argv, "mtc-bench-core", kAbout)) {
    return *exit_code;
  }
  SummaryReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  std::printf(
      "{\"benchmark\":\"core\",\"transition_ns\":%.1f,\"observation_ns\":%.1f,"
      "\"handshake_ns\":%.1f,\"fail_recover_ns\":%.1f,\"interface_tick_ns\":%.1f}\n",
      reporter.ns("BM_Transition"), reporter.ns("BM_Observation"), reporter.ns("BM_Handshake"),
      reporter.ns("BM_FailRecover"), reporter.ns("BM_InterfaceTickIdle"));
  benchmark::Shutdown();
  return 0;
}
