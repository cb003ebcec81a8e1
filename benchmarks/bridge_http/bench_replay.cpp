// The bridge's memory over hours of a cell's traffic, replayed fast: does
// its RSS stay flat once the observation buffer has wrapped (issue 9,
// section 4)? The demo cell's agent and HTTP server (as mtc-bridge wires
// them, without DDS: the observer's own memory is the endurance run's
// business) take `--hours` of the cell's traffic, `--per-hour` changes an
// hour round robin over every Part 5 item of the demo cell, as fast as a
// streaming client (/sample?interval=0) keeps up: each batch is fed, then
// the client must have received the part of its last change before the
// next batch. Every `--poll-every` changes a dashboard's requests run too
// (/current, and a /sample page of 1,000 from the oldest buffered change).
// The agent keeps the bridge's default 2^17 observations, so at the default
// rate the buffer wraps after about 75 minutes of traffic; RSS is sampled
// every `--sample-every` changes.
//
//   scripts/netns-run.sh build/benchmarks/mtc-bench-bridge-replay [options]
#include <algorithm>
#include <chrono>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include "demo_cell.hpp"
#include "mtc/bench/cli.hpp"
#include "mtc/bench/proc_cpu.hpp"
#include "stream_client.hpp"

namespace {

using mtc::bridge::bench::Clock;
using mtc::bridge::bench::DemoCell;
using mtc::bridge::bench::StreamClient;

constexpr const char* kAbout =
    "The bridge's resident memory over hours of the demo cell's traffic replayed as\n"
    "fast as a streaming client (/sample?interval=0) keeps up, with a dashboard's\n"
    "/current and /sample requests every --poll-every changes: does RSS stay flat\n"
    "once the observation buffer (2^17, the bridge's default) has wrapped? The\n"
    "default rate, 105,000 changes an hour, is what the 4-minute endurance run's\n"
    "streaming client received (7,017 in 240 s). Runs inside the loopback-only\n"
    "namespace (scripts/netns-run.sh). One JSON line on stdout:\n"
    "  {\"benchmark\":\"bridge_replay\",\"changes\",\"hours\",\"buffer_size\",\n"
    "   \"changes_per_s\",\"rss_kb\":{\"start\",\"at_wrap\",\"end\",\"max_after_wrap\"},\n"
    "   \"growth_after_wrap_kb\",\"series\":[[changes,rss_kb],...],\"stream_lost\",\n"
    "   \"polls\",\"bar\":{...},\"meets_bar\"}\n"
    "(bar: RSS after the wrap never more than max(1 MiB, 2 %) above its value at the\n"
    "wrap; the streaming client never fell behind).";

struct Settings {
  int hours = 4;
  int per_hour = 105000;
  int batch = 500;
  int poll_every = 5000;
  int sample_every = 10000;
};

struct Replay {
  std::vector<std::pair<long, long>> series;  // changes fed, RSS KiB
  long changes = 0;
  int stream_lost = 0;
  int polls = 0;
  int poll_errors = 0;
  double seconds = 0;
};

// A dashboard's two requests, straight through the agent's router (the
// HTTP server's own path is the streaming client's).
void poll(DemoCell& cell, std::size_t buffer_size, Replay& replay) {
  const auto current = cell.agent().route("GET", "/current");
  const std::uint64_t next = cell.agent().next_sequence();
  const std::uint64_t oldest = next > buffer_size ? next - buffer_size : 1;
  const auto page =
      cell.agent().route("GET", "/sample?from=" + std::to_string(oldest) + "&count=1000");
  ++replay.polls;
  for (const auto* answer : {&current, &page}) {
    if (!answer->response || answer->response->status != 200) {
      ++replay.poll_errors;
    }
  }
}

Replay replay(DemoCell& cell, StreamClient& client, const Settings& s, std::size_t buffer_size) {
  Replay r;
  const long total = static_cast<long>(s.hours) * s.per_hour;
  const auto t0 = Clock::now();
  r.series.emplace_back(0, mtc::bench::rss_kb());
  std::size_t item = 0;
  while (r.changes < total) {
    const long n = std::min<long>(s.batch, total - r.changes);
    const std::uint64_t last = cell.agent().next_sequence() + static_cast<std::uint64_t>(n) - 1;
    client.expect("sequence=\"" + std::to_string(last) + "\"");
    for (long k = 0; k < n; ++k) {
      cell.feed_next(item++);
      ++r.changes;
      if (r.changes % s.poll_every == 0) {
        poll(cell, buffer_size, r);
      }
      if (r.changes % s.sample_every == 0) {
        r.series.emplace_back(r.changes, mtc::bench::rss_kb());
      }
    }
    if (!client.wait(std::chrono::milliseconds(5000))) {
      ++r.stream_lost;  // the stream fell behind or ended: said in the JSON
    }
  }
  r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  r.series.emplace_back(r.changes, mtc::bench::rss_kb());
  return r;
}

void print(const Replay& r, const Settings& s, std::size_t buffer_size) {
  // The first sample at or after the wrap, and the highest one after it.
  long at_wrap = -1;
  long max_after = -1;
  for (const auto& [changes, rss] : r.series) {
    if (changes < static_cast<long>(buffer_size)) {
      continue;
    }
    if (at_wrap < 0) {
      at_wrap = rss;
    }
    max_after = std::max(max_after, rss);
  }
  const long allowed = at_wrap < 0 ? 0 : std::max(1024L, at_wrap / 50);
  const bool wrapped = at_wrap >= 0;
  const bool meets =
      wrapped && r.stream_lost == 0 && r.poll_errors == 0 && max_after - at_wrap <= allowed;
  std::cout << "{\"benchmark\":\"bridge_replay\",\"changes\":" << r.changes
            << ",\"hours\":" << s.hours << ",\"per_hour\":" << s.per_hour
            << ",\"buffer_size\":" << buffer_size << ",\"seconds\":" << r.seconds
            << ",\"changes_per_s\":" << static_cast<double>(r.changes) / r.seconds
            << ",\"rss_kb\":{\"start\":" << r.series.front().second << ",\"at_wrap\":" << at_wrap
            << ",\"end\":" << r.series.back().second << ",\"max_after_wrap\":" << max_after
            << "},\"growth_after_wrap_kb\":" << (wrapped ? max_after - at_wrap : -1)
            << ",\"stream_lost\":" << r.stream_lost << ",\"polls\":" << r.polls
            << ",\"poll_errors\":" << r.poll_errors << ",\"series\":[";
  for (std::size_t i = 0; i < r.series.size(); ++i) {
    std::cout << (i == 0 ? "" : ",") << "[" << r.series[i].first << "," << r.series[i].second
              << "]";
  }
  std::cout << "],\"bar\":{\"max_growth_after_wrap_kb\":" << allowed
            << ",\"wrapped\":" << (wrapped ? "true" : "false")
            << "},\"meets_bar\":" << (meets ? "true" : "false") << "}" << std::endl;
}

}  // namespace

int main(int argc, char** argv) try {
  Settings s;
  std::string devices = MTC_DEMO_DEVICES;
  mtc::bench::Cli cli("mtc-bench-bridge-replay", kAbout);
  cli.integer("--hours", s.hours, 1, 1000, "hours of the cell's traffic to replay")
      .integer("--per-hour", s.per_hour, 1, 100000000, "changes an hour of traffic holds")
      .integer("--batch", s.batch, 1, 100000, "changes fed before waiting for the stream")
      .integer("--poll-every", s.poll_every, 1, 100000000, "changes between dashboard polls")
      .integer("--sample-every", s.sample_every, 1, 100000000, "changes between RSS samples")
      .text("--devices", "FILE", devices, "MTConnect Devices file of the demo cell");
  if (const auto exit_code = cli.parse(argc, argv)) {
    return *exit_code;
  }
  DemoCell cell(devices, 1);
  StreamClient client(cell.port());
  const std::size_t buffer_size = mtc::bridge::AgentOptions{}.buffer_size;  // DemoCell's
  const Replay r = replay(cell, client, s, buffer_size);
  print(r, s, buffer_size);
  return 0;
} catch (const std::exception& error) {
  std::cerr << "mtc-bench-bridge-replay: " << error.what() << "\n";
  return 1;
}
