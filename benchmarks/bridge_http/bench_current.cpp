// /current throughput and latency of the bridge's HTTP server in front of
// the real agent serving the demo cell, driven by wrk over keep-alive
// connections while a feeder changes values (so /current is re-rendered,
// not only served from the agent's cache).
//
//   scripts/netns-run.sh build/benchmarks/mtc-bench-bridge-current [options]
//   (--help lists them with their defaults)
//
// Bar (docs/benchmarks.md): >= 20,000 req/s on 2 cores with `wrk -t1 -c8`, p99 < 1 ms.
#include <sys/resource.h>

#include <array>
#include <atomic>
#include <cstdio>
#include <iostream>
#include <regex>
#include <sstream>
#include <thread>

#include "demo_cell.hpp"
#include "mtc/bench/cli.hpp"

namespace {

using mtc::bridge::bench::DemoCell;

// "123.45us" / "1.20ms" / "2.00s" -> microseconds.
double to_us(const std::string& number, const std::string& unit) {
  const double value = std::stod(number);
  if (unit == "ms") {
    return value * 1000.0;
  }
  if (unit == "s") {
    return value * 1000000.0;
  }
  return value;
}

struct WrkResult {
  double requests_per_second = 0;
  double p50_us = 0, p75_us = 0, p90_us = 0, p99_us = 0;
  long long requests = 0;
  long long non_2xx = 0;
  std::string socket_errors = "none";
};

WrkResult parse_wrk(const std::string& output) {
  WrkResult r;
  std::smatch m;
  const std::regex rps(R"(Requests/sec:\s+([0-9.]+))");
  if (std::regex_search(output, m, rps)) {
    r.requests_per_second = std::stod(m[1]);
  }
  const std::regex total(R"((\d+) requests in)");
  if (std::regex_search(output, m, total)) {
    r.requests = std::stoll(m[1]);
  }
  const std::regex non2xx(R"(Non-2xx or 3xx responses:\s+(\d+))");
  if (std::regex_search(output, m, non2xx)) {
    r.non_2xx = std::stoll(m[1]);
  }
  const std::regex errors(R"(Socket errors:\s+([^\n]+))");
  if (std::regex_search(output, m, errors)) {
    r.socket_errors = m[1];
  }
  const std::array<std::pair<const char*, double*>, 4> quantiles{
      {{"50", &r.p50_us}, {"75", &r.p75_us}, {"90", &r.p90_us}, {"99", &r.p99_us}}};
  for (const auto& [q, out] : quantiles) {
    const std::regex line(std::string(R"(\s)") + q + R"(%\s+([0-9.]+)(us|ms|s)\b)");
    if (std::regex_search(output, m, line)) {
      *out = to_us(m[1], m[2]);
    }
  }
  return r;
}

// CPU time (user + system) this process has used (RUSAGE_SELF): the
// server's cost, independent of how busy the rest of the machine is; or
// that of its waited-for children (RUSAGE_CHILDREN): wrk's, the client's
// cost, which bounds what one wrk thread can ask for on the same machine.
double cpu_seconds(int who = RUSAGE_SELF) {
  rusage usage{};
  if (::getrusage(who, &usage) != 0) return 0;
  auto seconds = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_usec) / 1e6;
  };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

std::string run(const std::string& command) {
  std::string output;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) {
    throw std::runtime_error("cannot run: " + command);
  }
  std::array<char, 4096> buffer{};
  while (std::fgets(buffer.data(), buffer.size(), pipe) != nullptr) {
    output += buffer.data();
  }
  if (::pclose(pipe) != 0) {
    throw std::runtime_error("failed: " + command + "\n" + output);
  }
  return output;
}

struct Options {
  int duration = 10;
  int connections = 8;
  int wrk_threads = 1;
  int io_threads = 1;
  int feed_hz = 100;
  std::string target = "/current";
  std::string devices = MTC_DEMO_DEVICES;
};

constexpr const char* kAbout =
    "Throughput and latency of the bridge's HTTP server answering GET requests (by\n"
    "default /current) for the demo cell, driven by wrk over keep-alive connections on\n"
    "loopback while a feeder changes values (so /current is re-rendered, not only\n"
    "served from the agent's cache). Needs wrk; runs inside the loopback-only\n"
    "namespace (scripts/netns-run.sh). wrk's report goes to stderr, one JSON summary\n"
    "line to stdout:\n"
    "  {\"benchmark\":\"bridge_http_current\",\"requests_per_second\",\n"
    "   \"latency_us\":{p50,p75,p90,p99},\"server_cpu_us_per_request\",\n"
    "   \"client_cpu_us_per_request\" (wrk's),\"meets_bar\",...}\n"
    "(bar: >= 20,000 req/s, p99 < 1 ms, no non-2xx). benchmarks/bridge_http/run.sh\n"
    "collects it in <build>/benchmarks/bridge_http.json.";

// Usage errors -> exit code; nullopt to run.
std::optional<int> parse_options(int argc, char** argv, Options& o) {
  mtc::bench::Cli cli("mtc-bench-bridge-current", kAbout);
  cli.integer("--duration", o.duration, 1, 3600, "seconds wrk runs")
      .integer("--connections", o.connections, 1, 10000, "wrk's open connections (-c)")
      .integer("--wrk-threads", o.wrk_threads, 1, 64, "wrk's threads (-t)")
      .integer("--io-threads", o.io_threads, 1, 64, "the HTTP server's io threads")
      .integer("--feed-hz", o.feed_hz, 0, 100000, "values fed into the agent per second, 0 = none")
      .text("--target", "PATH", o.target, "the request path wrk sends")
      .text("--devices", "FILE", o.devices, "MTConnect Devices file of the demo cell");
  if (const auto exit_code = cli.parse(argc, argv)) {
    return exit_code;
  }
  if (o.target.front() != '/') {
    return cli.usage_error("--target expects a path starting with '/', got '" + o.target + "'");
  }
  if (o.connections < o.wrk_threads) {
    return cli.usage_error("--connections must be at least --wrk-threads (wrk's rule)");
  }
  return std::nullopt;
}

}  // namespace

int main(int argc, char** argv) try {
  Options o;
  if (const auto exit_code = parse_options(argc, argv, o)) {
    return *exit_code;
  }
  DemoCell cell(o.devices, static_cast<unsigned>(o.io_threads));
  std::atomic<bool> feeding{true};
  std::atomic<long long> fed{0};
  std::thread feeder([&] {
    if (o.feed_hz <= 0) {
      return;
    }
    const auto period = std::chrono::nanoseconds(1000000000LL / o.feed_hz);
    auto next = std::chrono::steady_clock::now();
    for (std::size_t i = 0; feeding; ++i) {
      cell.feed_next(i);
      ++fed;
      next += period;
      std::this_thread::sleep_until(next);  // pacing a load generator, not synchronisation
    }
  });

  std::ostringstream command;
  command << "wrk -t" << o.wrk_threads << " -c" << o.connections << " -d" << o.duration
          << "s --latency http://127.0.0.1:" << cell.port() << o.target << " 2>&1";
  const double cpu_before = cpu_seconds();
  const double client_cpu_before = cpu_seconds(RUSAGE_CHILDREN);
  const std::string output = run(command.str());
  const double cpu_used = cpu_seconds() - cpu_before;
  const double client_cpu_used = cpu_seconds(RUSAGE_CHILDREN) - client_cpu_before;
  feeding = false;
  feeder.join();
  std::cerr << output;

  const WrkResult r = parse_wrk(output);
  std::cout << "{\"benchmark\":\"bridge_http_current\",\"target\":\"" << o.target
            << "\",\"wrk_threads\":" << o.wrk_threads << ",\"connections\":" << o.connections
            << ",\"duration_s\":" << o.duration << ",\"io_threads\":" << o.io_threads
            << ",\"feed_hz\":" << o.feed_hz << ",\"values_fed\":" << fed.load()
            << ",\"data_items\":" << cell.items().size() << ",\"requests\":" << r.requests
            << ",\"requests_per_second\":" << r.requests_per_second
            << ",\"latency_us\":{\"p50\":" << r.p50_us << ",\"p75\":" << r.p75_us
            << ",\"p90\":" << r.p90_us << ",\"p99\":" << r.p99_us << "},\"non_2xx\":" << r.non_2xx
            << ",\"server_cpu_us_per_request\":"
            << (r.requests > 0 ? cpu_used * 1e6 / static_cast<double>(r.requests) : 0.0)
            << ",\"client_cpu_us_per_request\":"
            << (r.requests > 0 ? client_cpu_used * 1e6 / static_cast<double>(r.requests) : 0.0)
            << ",\"socket_errors\":\"" << r.socket_errors << "\",\"bar\":{\"min_rps\":20000,"
            << "\"max_p99_us\":1000},\"meets_bar\":"
            << ((r.requests_per_second >= 20000 && r.p99_us < 1000 && r.non_2xx == 0) ? "true"
                                                                                      : "false")
            << "}" << std::endl;
  return 0;
} catch (const std::exception& error) {
  std::cerr << "mtc-bench-bridge-current: " << error.what() << "\n";
  return 1;
}
