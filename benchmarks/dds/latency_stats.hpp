// Latency samples and their summary (percentiles in microseconds), shared by
// every series of the DDS latency benchmark so they print the same way.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

namespace mtc::bench {

// One measured series: what was timed, over which path, and the samples.
struct Series {
  std::string name;            // e.g. "raw_fastdds_round_trip"
  std::string layer;           // "raw_fastdds" or "mtc_equipment"
  std::string metric;          // "round_trip", "transition", "handshake"
  std::string transport;       // "udp_loopback" or "shm_udp"
  int processes = 1;           // 1: both ends in this process; 2: forked peer
  std::string stepping = "-";  // equipment series: default, executor or inline
  std::vector<double> samples_us;
  std::size_t timeouts = 0;  // iterations that got no answer in time
  // CPU time (user + system) of every process taking part, per timed
  // operation; negative when not measured.
  double cpu_us_per_op = -1;
  // Parts of each sample where the series can tell them apart (a
  // transition: the middleware's transit, the runtime's step, the write),
  // printed as p50s: where the time goes.
  std::map<std::string, std::vector<double>> legs_us;
};

struct Summary {
  std::size_t count = 0;
  double min = 0, mean = 0, p50 = 0, p90 = 0, p99 = 0, p999 = 0, max = 0;
};

// Nearest-rank percentiles: every figure is a latency that really occurred.
inline Summary summarize(std::vector<double> samples) {
  Summary s;
  if (samples.empty()) return s;
  std::sort(samples.begin(), samples.end());
  auto rank = [&](double p) {
    auto index = static_cast<std::size_t>(p * static_cast<double>(samples.size()) + 0.999999);
    index = std::clamp<std::size_t>(index, 1, samples.size());
    return samples[index - 1];
  };
  double total = 0;
  for (double v : samples) total += v;
  s.count = samples.size();
  s.min = samples.front();
  s.mean = total / static_cast<double>(samples.size());
  s.p50 = rank(0.50);
  s.p90 = rank(0.90);
  s.p99 = rank(0.99);
  s.p999 = rank(0.999);
  s.max = samples.back();
  return s;
}

// Appends `legs` (leg name -> samples) to a series' legs.
inline void append_legs(Series& into, const std::map<std::string, std::vector<double>>& legs) {
  for (const auto& [leg, samples] : legs) {
    auto& to = into.legs_us[leg];
    to.insert(to.end(), samples.begin(), samples.end());
  }
}

inline double to_us(std::chrono::steady_clock::duration d) {
  return std::chrono::duration<double, std::micro>(d).count();
}

// One JSON object per series; names are fixed identifiers, no escaping needed.
inline std::string to_json(const Series& series) {
  const Summary s = summarize(series.samples_us);
  char cpu[32] = "null";
  if (series.cpu_us_per_op >= 0) {
    std::snprintf(cpu, sizeof cpu, "%.1f", series.cpu_us_per_op);
  }
  char buf[768];
  std::snprintf(buf, sizeof buf,
                "{\"name\":\"%s\",\"layer\":\"%s\",\"metric\":\"%s\",\"transport\":\"%s\","
                "\"processes\":%d,\"stepping\":\"%s\",\"unit\":\"us\",\"count\":%zu,"
                "\"timeouts\":%zu,"
                "\"min\":%.1f,\"mean\":%.1f,\"p50\":%.1f,\"p90\":%.1f,\"p99\":%.1f,"
                "\"p999\":%.1f,\"max\":%.1f,\"cpu_us_per_op\":%s}",
                series.name.c_str(), series.layer.c_str(), series.metric.c_str(),
                series.transport.c_str(), series.processes, series.stepping.c_str(), s.count,
                series.timeouts, s.min, s.mean, s.p50, s.p90, s.p99, s.p999, s.max, cpu);
  std::string json = buf;
  if (!series.legs_us.empty()) {
    json.pop_back();  // the closing brace
    json += ",\"legs_p50_us\":{";
    for (const auto& [leg, samples] : series.legs_us) {
      std::snprintf(buf, sizeof buf, "%s\"%s\":%.1f", json.back() == '{' ? "" : ",", leg.c_str(),
                    summarize(samples).p50);
      json += buf;
    }
    json += "}}";
  }
  return json;
}

}  // namespace mtc::bench
