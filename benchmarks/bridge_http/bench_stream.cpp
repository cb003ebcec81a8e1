// Streaming latency of the bridge's HTTP server: from a value being fed into
// the agent (what the DomainObserver callback does on a DDS transition) to
// the multipart part carrying it arriving at streaming HTTP clients
// (/sample?interval=0). Every client's arrival time is recorded.
//
//   scripts/netns-run.sh build/benchmarks/mtc-bench-bridge-stream [options]
//   (--help lists them with their defaults)
//
// Bar (docs/benchmarks.md): p50 < 200 us, p99 < 2 ms.
#include <iostream>
#include <random>
#include <thread>

#include "demo_cell.hpp"
#include "mtc/bench/cli.hpp"
#include "stream_client.hpp"

namespace {

using mtc::bridge::bench::Clock;
using mtc::bridge::bench::DemoCell;
using mtc::bridge::bench::print_summary;
using mtc::bridge::bench::StreamClient;
using mtc::bridge::bench::summarize;

constexpr const char* kAbout =
    "Streaming latency of the bridge's HTTP server: from a value fed into the agent\n"
    "(what the DDS observer does on a transition) to the multipart part carrying it\n"
    "arriving at each streaming client (/sample?interval=0) of the demo cell, over\n"
    "loopback; 50 warm-up feeds are not counted. Runs inside the loopback-only\n"
    "namespace (scripts/netns-run.sh). One JSON line on stdout:\n"
    "  {\"benchmark\":\"bridge_http_stream_latency\",\"lost\",\n"
    "   \"first_client_us\":{p50,p90,p99,max,mean},\"all_clients_us\":{...},\"meets_bar\",...}\n"
    "(bar, all clients: p50 < 200 us, p99 < 2 ms, none lost).\n"
    "benchmarks/bridge_http/run.sh collects it in <build>/benchmarks/bridge_http.json.";

struct Latencies {
  std::vector<std::chrono::nanoseconds> first_client;
  std::vector<std::chrono::nanoseconds> all_clients;
  int lost = 0;
};

// Feeds `samples` values, after 50 warm-up feeds that are not counted, and
// times the arrival of the part carrying each at every client.
Latencies measure(DemoCell& cell, std::vector<std::unique_ptr<StreamClient>>& clients,
                  int samples) {
  std::mt19937 random(7);
  std::uniform_int_distribution<int> gap_us(200, 1200);
  Latencies m;
  const int warmup = 50;
  for (int k = 0; k < samples + warmup; ++k) {
    const std::uint64_t sequence = cell.agent().next_sequence();
    for (auto& client : clients) {
      client->expect("sequence=\"" + std::to_string(sequence) + "\"");
    }
    const auto t0 = Clock::now();
    cell.feed_next(0);  // one item: each feed is one new observation
    for (std::size_t c = 0; c < clients.size(); ++c) {
      const auto t1 = clients[c]->wait(std::chrono::milliseconds(2000));
      if (!t1) {
        ++m.lost;
        continue;
      }
      if (k < warmup) {
        continue;
      }
      const auto latency = std::chrono::duration_cast<std::chrono::nanoseconds>(t1->steady - t0);
      m.all_clients.push_back(latency);
      if (c == 0) {
        m.first_client.push_back(latency);
      }
    }
    // Spread the feeds so each measures an idle-to-busy wake-up, as a
    // handshake transition does, not a queue draining.
    std::this_thread::sleep_for(std::chrono::microseconds(gap_us(random)));
  }
  return m;
}

}  // namespace

int main(int argc, char** argv) try {
  int samples = 2000;
  int client_count = 4;
  int io_threads = 1;
  int direct = static_cast<int>(mtc::bridge::ServerOptions{}.direct_stream_writes);
  std::string devices = MTC_DEMO_DEVICES;
  mtc::bench::Cli cli("mtc-bench-bridge-stream", kAbout);
  cli.integer("--samples", samples, 1, 10000000, "values fed and timed")
      .integer("--clients", client_count, 1, 256, "streaming clients")
      .integer("--io-threads", io_threads, 1, 64, "the HTTP server's io threads")
      .integer("--direct-stream-writes", direct, 0, 1000,
               "ServerOptions::direct_stream_writes (0: every part from the io thread)")
      .text("--devices", "FILE", devices, "MTConnect Devices file of the demo cell");
  if (const auto exit_code = cli.parse(argc, argv)) {
    return *exit_code;
  }

  DemoCell cell(devices, static_cast<unsigned>(io_threads), static_cast<std::size_t>(direct));
  std::vector<std::unique_ptr<StreamClient>> clients;
  clients.reserve(static_cast<std::size_t>(client_count));
  for (int i = 0; i < client_count; ++i) {
    clients.push_back(std::make_unique<StreamClient>(cell.port()));
  }

  const Latencies m = measure(cell, clients, samples);
  const int lost = m.lost;
  const auto one = summarize(m.first_client);
  const auto all = summarize(m.all_clients);
  std::cout << "{\"benchmark\":\"bridge_http_stream_latency\",\"clients\":" << client_count
            << ",\"io_threads\":" << io_threads << ",\"direct_stream_writes\":" << direct
            << ",\"direct_parts\":" << cell.direct_stream_parts() << ",\"lost\":" << lost
            << ",\"first_client_us\":";
  print_summary(std::cout, one);
  std::cout << ",\"all_clients_us\":";
  print_summary(std::cout, all);
  std::cout << ",\"bar\":{\"max_p50_us\":200,\"max_p99_us\":2000},\"meets_bar\":"
            << ((lost == 0 && all.p50_us < 200 && all.p99_us < 2000) ? "true" : "false") << "}"
            << std::endl;
  return 0;
} catch (const std::exception& error) {
  std::cerr << "mtc-bench-bridge-stream: " << error.what() << "\n";
  return 1;
}
