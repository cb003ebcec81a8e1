// Agent render/ingest benchmark. Prints Google Benchmark's table, then one
// JSON summary line: {"benchmark":"bridge_agent","results":[{name,
// ns_per_op, ops_per_s}...]}.
//
// The cell: 3 devices, 28 data items (the demo cell), 1.6 documents.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <string>
#include <vector>

#include "mtc/bench/gbench_cli.hpp"
#include "mtc/bridge/mtconnect_agent.hpp"

namespace {

namespace core = mtc::core;
using mtc::bridge::AgentOptions;
using mtc::bridge::MtconnectAgent;
using mtc::bridge::SchemaVersion;

core::ObservedDataItem item(std::string id, std::string type, std::string sub = "") {
  core::ObservedDataItem d;
  d.id = std::move(id);
  d.type = std::move(type);
  d.sub_type = std::move(sub);
  d.category = "EVENT";
  return d;
}

std::unique_ptr<MtconnectAgent> make_cell() {
  AgentOptions o;
  o.schema_version = SchemaVersion::V1_6;
  o.buffer_size = 131072;
  auto agent = make_agent(o);
  const char* names[] = {"mill", "robot", "feeder"};
  for (const char* n : names) {
    core::ObservedDevice d;
    d.device_uuid = std::string(n) + "-uuid";
    d.name = n;
    core::ObservedInterface mh;
    mh.id = std::string(n) + "_mh";
    mh.type = core::InterfaceType::MaterialHandler;
    const std::string p = std::string(n) + ".";
    mh.data_items = {item(p + "state", "INTERFACE_STATE"),
                     item(p + "load", "MATERIAL_LOAD", "REQUEST"),
                     item(p + "unload", "MATERIAL_UNLOAD", "REQUEST"),
                     item(p + "open_door", "OPEN_DOOR", "RESPONSE"),
                     item(p + "close_door", "CLOSE_DOOR", "RESPONSE"),
                     item(p + "open_chuck", "OPEN_CHUCK", "RESPONSE"),
                     item(p + "close_chuck", "CLOSE_CHUCK", "RESPONSE"),
                     item(p + "feed", "MATERIAL_FEED", "REQUEST")};
    d.interfaces = {mh};
    agent->add_device(d);
  }
  return agent;
}

core::ObservedValue value(int i) {
  core::ObservedValue v;
  v.device_uuid = "mill-uuid";
  v.data_item_id = "mill.load";
  v.state = i % 2 != 0 ? core::InteractionState::Active : core::InteractionState::Ready;
  v.source_time_ns = 1'700'000'000'000'000'000 + i;
  return v;
}

void BM_CurrentCached(benchmark::State& state) {
  auto agent = make_cell();
  for ([[maybe_unused]] auto _ : state) benchmark::DoNotOptimize(agent->route("GET", "/current"));
}
BENCHMARK(BM_CurrentCached);

// Every request after a change: the full render cost.
void BM_CurrentAfterChange(benchmark::State& state) {
  auto agent = make_cell();
  int i = 0;
  for ([[maybe_unused]] auto _ : state) {
    agent->add_value(value(i++));
    benchmark::DoNotOptimize(agent->route("GET", "/current"));
  }
}
BENCHMARK(BM_CurrentAfterChange);

void BM_CurrentPathAfterChange(benchmark::State& state) {
  auto agent = make_cell();
  int i = 0;
  for ([[maybe_unused]] auto _ : state) {
    agent->add_value(value(i++));
    benchmark::DoNotOptimize(
        agent->route("GET", "/mill/current?path=//DataItem[@type='MATERIAL_LOAD']"));
  }
}
BENCHMARK(BM_CurrentPathAfterChange);

void BM_Sample100(benchmark::State& state) {
  auto agent = make_cell();
  for (int i = 0; i < 1000; ++i) agent->add_value(value(i));
  for ([[maybe_unused]] auto _ : state) {
    benchmark::DoNotOptimize(agent->route("GET", "/sample?count=100"));
  }
}
BENCHMARK(BM_Sample100);

// /current?at= in the middle of a full 131072-entry buffer: checkpoint
// lookup plus at most 1024 replayed observations.
void BM_CurrentAtMidBuffer(benchmark::State& state) {
  auto agent = make_cell();
  for (int i = 0; i < 200000; ++i) agent->add_value(value(i));
  const std::string target = "/current?at=" + std::to_string(agent->next_sequence() - 65000);
  for ([[maybe_unused]] auto _ : state) benchmark::DoNotOptimize(agent->route("GET", target));
}
BENCHMARK(BM_CurrentAtMidBuffer);

void BM_ProbeCached(benchmark::State& state) {
  auto agent = make_cell();
  for ([[maybe_unused]] auto _ : state) benchmark::DoNotOptimize(agent->route("GET", "/probe"));
}
BENCHMARK(BM_ProbeCached);

void BM_IngestChange(benchmark::State& state) {
  auto agent = make_cell();
  int i = 0;
  for ([[maybe_unused]] auto _ : state) agent->add_value(value(i++));
}
BENCHMARK(BM_IngestChange);

// The last known value handed over again after a device's heartbeats came
// back: unchanged, so it adds nothing to the buffer.
void BM_IngestRedelivered(benchmark::State& state) {
  auto agent = make_cell();
  agent->add_value(value(0));
  core::ObservedValue v = value(0);
  v.redelivered = true;
  for ([[maybe_unused]] auto _ : state) agent->add_value(v);
}
BENCHMARK(BM_IngestRedelivered);

// A change reaching 1,000 streams of the same /sample?interval=0: the
// agent's side of the HTTP fan-out (mtc-bench-bridge-fanout), per part.
void BM_StreamPartsAfterChange(benchmark::State& state) {
  auto agent = make_cell();
  const mtc::bridge::Routed routed = agent->route("GET", "/sample?interval=0");
  std::vector<mtc::bridge::StreamPlan> plans(1000, *routed.stream);
  for (auto& plan : plans) benchmark::DoNotOptimize(agent->next_part(plan));
  int i = 0;
  for ([[maybe_unused]] auto _ : state) {
    state.PauseTiming();
    agent->add_value(value(i++));
    state.ResumeTiming();
    for (auto& plan : plans) benchmark::DoNotOptimize(agent->next_part(plan));
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(plans.size()));
}
BENCHMARK(BM_StreamPartsAfterChange);

class SummaryReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& r : runs) {
      if (r.iterations == 0) continue;
      const double ns = r.real_accumulated_time * 1e9 / static_cast<double>(r.iterations);
      results_.emplace_back(r.benchmark_name(), ns);
    }
  }
  void print_json() const {
    std::printf("{\"benchmark\":\"bridge_agent\",\"schema\":\"1.6\",\"items\":28,\"results\":[");
    for (std::size_t i = 0; i < results_.size(); ++i) {
      std::printf("%s{\"name\":\"%s\",\"ns_per_op\":%.0f,\"ops_per_s\":%.0f}", i > 0 ? "," : "",
                  results_[i].first.c_str(), results_[i].second, 1e9 / results_[i].second);
    }
    std::printf("]}\n");
  }

 private:
  std::vector<std::pair<std::string, double>> results_;
};

constexpr const char* kAbout =
    "Render and ingest cost of the bridge's MTConnect agent alone (no HTTP, no DDS), on\n"
    "a cell of 3 devices with one MaterialHandler interface each (1.6 documents):\n"
    "/current cached and after a change, /current?path=, /sample?count=100,\n"
    "/current?at= in a full buffer, /probe, ingest of a change and of an unchanged\n"
    "value handed over again after a loss, the next part of 1,000 streams of one\n"
    "/sample?interval=0 after a change (per 1,000 parts).\n"
    "Output on stdout: Google Benchmark's table, then one JSON summary line\n"
    "  {\"benchmark\":\"bridge_agent\",...,\n"
    "   \"results\":[{\"name\",\"ns_per_op\",\"ops_per_s\"},...]}\n"
    "in wall-clock ns per operation. benchmarks/run.sh keeps the library's JSON\n"
    "(--benchmark_out) in bench-results/bridge_agent.json.";

}  // namespace

int main(int argc, char** argv) {
  if (const auto exit_code =
          mtc::bench::initialize_google_benchmark(&argc, argv, "mtc-bench-bridge-agent", kAbout)) {
    return *exit_code;
  }
  SummaryReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.print_json();
  benchmark::Shutdown();
  return 0;
}
