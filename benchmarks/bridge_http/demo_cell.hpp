// The demo cell the HTTP benchmarks serve: helper-made MtconnectAgent loaded
// with bridge/devices/cell_1.6.xml, every Part 5 data item given a value,
// and an HttpServer in front of it on a free loopback port.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "mtc/bridge/http_server.hpp"
#include "mtc/bridge/mtconnect_agent.hpp"

namespace mtc::bridge::bench {

struct FedItem {
  std::string device_uuid;
  std::string id;
  std::vector<core::ObservedState> values;  // cycled by the feeder
};

class DemoCell {
 public:
  // `direct_stream_writes`: ServerOptions::direct_stream_writes.
  DemoCell(const std::string& devices_file, unsigned io_threads,
           std::size_t direct_stream_writes = ServerOptions{}.direct_stream_writes);
  ~DemoCell();
  DemoCell(const DemoCell&) = delete;
  DemoCell& operator=(const DemoCell&) = delete;

  MtconnectAgent& agent() { return *agent_; }
  std::uint16_t port() const { return server_->port(); }
  std::uint64_t direct_stream_parts() const { return server_->direct_stream_parts(); }
  const std::vector<FedItem>& items() const { return items_; }

  // Gives item `index % items().size()` its next value (round robin).
  void feed_next(std::size_t index);

 private:
  std::shared_ptr<MtconnectAgent> agent_;
  std::unique_ptr<HttpServer> server_;
  std::vector<FedItem> items_;
  std::vector<std::size_t> cursor_;
};

// Percentiles of a sample of durations, in microseconds.
struct LatencySummary {
  double p50_us = 0;
  double p90_us = 0;
  double p99_us = 0;
  double max_us = 0;
  double mean_us = 0;
  std::size_t samples = 0;
};
LatencySummary summarize(std::vector<std::chrono::nanoseconds> samples);
// {"samples":..,"p50":..,"p90":..,"p99":..,"max":..,"mean":..} on `out`.
void print_summary(std::ostream& out, const LatencySummary& s);

}  // namespace mtc::bridge::bench
