// The bridge's HTTP server under abuse, measured: while each abuse of
// issue 10 runs, a well-behaved client requests /current over and over (a
// new connection each time) and its latency is recorded; the /sample abuse
// also records the process's RSS before, during and after.
//
//   scripts/netns-run.sh build/benchmarks/mtc-bench-bridge-abuse [options]
//
// Everything runs in this process (agent, server, clients), on loopback.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "mtc/bench/cli.hpp"
#include "mtc/bridge/http_server.hpp"
#include "mtc/bridge/mtconnect_agent.hpp"

namespace {

namespace core = mtc::core;
using mtc::bridge::AgentOptions;
using mtc::bridge::HttpServer;
using mtc::bridge::make_agent;
using mtc::bridge::MtconnectAgent;
using mtc::bridge::ServerOptions;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

constexpr const char* kAbout =
    "The bridge's HTTP server (with the real agent, a 2^17 buffer) under each abuse of\n"
    "issue 10 - 300 clients sending a byte a second, 2,000 idle connections, 4 clients\n"
    "sending count() nested six deep as path, 50 streams that never read, 50 clients\n"
    "asking /sample?count=131072 of the full buffer and never reading - while a\n"
    "well-behaved client requests /current, one connection per request. One JSON line:\n"
    "  {\"benchmark\":\"bridge_abuse\",\"scenarios\":[{\"name\",\"requests\",\"failed\",\n"
    "   \"p50_ms\",\"p99_ms\",\"max_ms\"}...],\"sample_memory\":{\"rss_before_mib\",\n"
    "   \"rss_during_mib\",\"rss_after_mib\",\"answered_200\",\"answered_503\"}}\n"
    "Runs inside the loopback-only namespace (scripts/netns-run.sh).";

std::size_t resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  std::size_t pages = 0;
  std::size_t resident = 0;
  statm >> pages >> resident;
  return resident * static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
}

double mib(std::size_t bytes) {
  return static_cast<double>(bytes) / 1048576.0;
}

// A bare client socket: from a loopback source address, with a small window
// for clients that never read. -1 when the connection failed.
int connect_to(std::uint16_t port, const std::string& source = {}, int receive_buffer = 0) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return -1;
  if (receive_buffer > 0) {
    ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &receive_buffer, sizeof receive_buffer);
  }
  sockaddr_in address{};
  address.sin_family = AF_INET;
  if (!source.empty()) {
    ::inet_pton(AF_INET, source.c_str(), &address.sin_addr);
    if (::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
      ::close(fd);
      return -1;
    }
  }
  address.sin_port = htons(port);
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

bool send_all(int fd, const std::string& bytes) {
  return ::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(bytes.size());
}

std::string get(const std::string& target) {
  return "GET " + target + " HTTP/1.1\r\nHost: bench\r\n\r\n";
}

// Reads until `enough` bytes or the deadline; returns what arrived.
std::string receive(int fd, std::size_t enough, Clock::time_point deadline) {
  std::string data;
  char chunk[65536];
  while (data.size() < enough && Clock::now() < deadline) {
    pollfd p{fd, POLLIN, 0};
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    if (::poll(&p, 1, static_cast<int>(std::max<long>(1, left.count()))) <= 0) continue;
    const ssize_t n = ::recv(fd, chunk, sizeof chunk, 0);
    if (n <= 0) break;
    data.append(chunk, static_cast<std::size_t>(n));
  }
  return data;
}

// One /current on a new connection: the time to its complete 200 answer,
// or a negative value when it failed or took more than 10 s.
double timed_current(std::uint16_t port) {
  const auto start = Clock::now();
  const int fd = connect_to(port);
  if (fd < 0) return -1;
  bool ok = send_all(fd, get("/current"));
  std::string data;
  std::size_t total = std::string::npos;
  const auto deadline = start + 10s;
  while (ok && data.size() < total && Clock::now() < deadline) {
    const std::string more = receive(fd, 1, deadline);
    if (more.empty()) break;
    data += more;
    const auto head_end = data.find("\r\n\r\n");
    const auto length = data.find("Content-Length: ");
    if (head_end != std::string::npos && length != std::string::npos) {
      total = head_end + 4 + std::stoul(data.substr(length + 16));
    }
  }
  ::close(fd);
  ok = ok && data.size() == total && data.compare(9, 3, "200") == 0;
  return ok ? std::chrono::duration<double, std::milli>(Clock::now() - start).count() : -1;
}

struct Figures {
  std::string name;
  int requests = 0;
  int failed = 0;
  double p50 = 0;
  double p99 = 0;
  double max = 0;
};

// The well-behaved client, for `duration`, while the abuse runs.
Figures well_behaved(const std::string& name, std::uint16_t port, std::chrono::seconds duration) {
  Figures f;
  f.name = name;
  std::vector<double> ms;
  const auto end = Clock::now() + duration;
  while (Clock::now() < end) {
    const double t = timed_current(port);
    ++f.requests;
    if (t < 0) {
      ++f.failed;
    } else {
      ms.push_back(t);
    }
    std::this_thread::sleep_for(20ms);  // a client polling, not a flood
  }
  std::sort(ms.begin(), ms.end());
  if (!ms.empty()) {
    f.p50 = ms[ms.size() / 2];
    f.p99 = ms[std::min(ms.size() - 1, ms.size() * 99 / 100)];
    f.max = ms.back();
  }
  return f;
}

// An abuse: runs on its own thread until `stop`, cleans up after itself.
using Abuse = std::function<void(std::uint16_t port, const std::atomic<bool>& stop)>;

void slow_clients(std::uint16_t port, const std::atomic<bool>& stop) {
  std::vector<int> fds(300, -1);
  const std::string request = get("/current");
  for (std::size_t round = 0; !stop; ++round) {
    for (std::size_t i = 0; i < fds.size() && !stop; ++i) {
      if (fds[i] < 0 || !send_all(fds[i], request.substr(round % request.size(), 1))) {
        if (fds[i] >= 0) ::close(fds[i]);
        fds[i] = connect_to(port, "127.0.0." + std::to_string(2 + i % 10));
      }
    }
    for (int k = 0; k < 10 && !stop; ++k) std::this_thread::sleep_for(100ms);  // 1 byte/s
  }
  for (const int fd : fds) ::close(fd);
}

void idle_connections(std::uint16_t port, const std::atomic<bool>& stop) {
  std::vector<int> fds;
  for (int i = 0; i < 2000 && !stop; ++i) {
    fds.push_back(connect_to(port, "127.0.0." + std::to_string(2 + i % 20)));
  }
  while (!stop) std::this_thread::sleep_for(50ms);
  for (const int fd : fds) ::close(fd);
}

void costly_paths(std::uint16_t port, const std::atomic<bool>& stop) {
  const std::string path = "//*[count(//*[count(//*[count(//*[count(//*[count(//*)])])])])]";
  std::vector<std::thread> clients;
  clients.reserve(4);
  for (int c = 0; c < 4; ++c) {
    clients.emplace_back([&] {
      while (!stop) {
        const int fd = connect_to(port);
        if (fd < 0) continue;
        send_all(fd, get("/current?path=" + path));
        receive(fd, 1, Clock::now() + 10s);
        ::close(fd);
      }
    });
  }
  for (auto& t : clients) t.join();
}

void never_reading_streams(std::uint16_t port, const std::atomic<bool>& stop) {
  std::vector<int> fds;
  for (int i = 0; i < 50; ++i) {
    fds.push_back(connect_to(port, "127.0.0.30", 4096));
    send_all(fds.back(), get("/sample?interval=0&heartbeat=1000"));
  }
  while (!stop) std::this_thread::sleep_for(50ms);
  for (const int fd : fds) ::close(fd);
}

void run_scenario(const std::string& name, const Abuse& abuse, std::uint16_t port,
                  std::chrono::seconds duration, std::vector<Figures>& out) {
  std::atomic<bool> stop{false};
  std::thread abuser([&] { abuse(port, stop); });
  std::this_thread::sleep_for(1s);  // the abuse in full swing first
  out.push_back(well_behaved(name, port, duration));
  stop = true;
  abuser.join();
  std::this_thread::sleep_for(500ms);  // let the server settle between scenarios
}

struct Memory {
  std::size_t before = 0, during = 0, after = 0;
  int answered_200 = 0, answered_503 = 0;
  Figures latency;
};

// 50 clients ask the whole full buffer and never read past the status.
Memory sample_hogs(HttpServer& server, std::chrono::seconds duration) {
  Memory m;
  m.before = resident_bytes();
  std::vector<int> fds;
  for (int i = 0; i < 50; ++i) {
    fds.push_back(connect_to(server.port(), "127.0.0.40", 4096));
    send_all(fds.back(), get("/sample?count=131072"));
  }
  for (const int fd : fds) {
    const std::string status = receive(fd, 12, Clock::now() + 60s);
    (status.size() >= 12 && status.compare(9, 3, "200") == 0 ? m.answered_200 : m.answered_503)++;
  }
  m.latency = well_behaved("sample_hogs", server.port(), duration);
  m.during = resident_bytes();
  for (const int fd : fds) {
    linger reset{1, 0};
    ::setsockopt(fd, SOL_SOCKET, SO_LINGER, &reset, sizeof reset);
    ::close(fd);
  }
  for (int i = 0; i < 100 && server.connection_count() > 0; ++i) std::this_thread::sleep_for(50ms);
  std::this_thread::sleep_for(500ms);
  m.after = resident_bytes();
  return m;
}

std::shared_ptr<MtconnectAgent> full_agent(bool uncapped) {
  AgentOptions options;
  if (uncapped) options.max_document_bytes = SIZE_MAX;
  auto agent = make_agent(options);
  core::ObservedDevice device;
  device.device_uuid = "mill-1";
  device.name = "mill";
  core::ObservedInterface door{"door", "door", core::InterfaceType::Door, {}};
  door.data_items.push_back({"door_state", "", "DOOR_STATE", "", "EVENT"});
  device.interfaces = {door};
  agent->add_device(device);
  core::ObservedValue value;
  value.device_uuid = "mill-1";
  value.data_item_id = "door_state";
  for (std::size_t i = 0; i <= options.buffer_size; ++i) {
    value.state = i % 2 != 0 ? core::DoorState::Open : core::DoorState::Closed;
    agent->add_value(value);
  }
  return agent;
}

}  // namespace

int main(int argc, char** argv) try {
  int seconds = 4;
  int io_threads = 2;
  bool uncapped = false;
  mtc::bench::Cli cli("mtc-bench-bridge-abuse", kAbout);
  cli.integer("--seconds", seconds, 1, 600, "well-behaved requests per scenario, seconds")
      .integer("--io-threads", io_threads, 1, 64, "the HTTP server's io threads")
      .flag("--uncapped", uncapped,
            "no document cap nor pending-bytes limit (the behaviour before issue 10)");
  if (const auto exit_code = cli.parse(argc, argv)) return *exit_code;
  rlimit limit{};
  if (::getrlimit(RLIMIT_NOFILE, &limit) == 0) {
    limit.rlim_cur = limit.rlim_max;
    ::setrlimit(RLIMIT_NOFILE, &limit);
  }

  auto agent = full_agent(uncapped);
  ServerOptions options;
  options.port = 0;
  options.io_threads = static_cast<unsigned>(io_threads);
  if (uncapped) options.max_pending_bytes = SIZE_MAX;
  HttpServer server(agent, options);
  server.start();
  const auto duration = std::chrono::seconds(seconds);

  std::vector<Figures> scenarios;
  run_scenario(
      "none", [](std::uint16_t, const std::atomic<bool>&) {}, server.port(), duration, scenarios);
  run_scenario("slow_clients_300", slow_clients, server.port(), duration, scenarios);
  run_scenario("idle_connections_2000", idle_connections, server.port(), duration, scenarios);
  run_scenario("count_nested_six_deep", costly_paths, server.port(), duration, scenarios);
  run_scenario("streams_never_reading_50", never_reading_streams, server.port(), duration,
               scenarios);
  const Memory memory = sample_hogs(server, duration);
  scenarios.push_back(memory.latency);

  std::ostringstream json;
  json << "{\"benchmark\":\"bridge_abuse\",\"uncapped\":" << (uncapped ? "true" : "false")
       << ",\"scenarios\":[";
  for (std::size_t i = 0; i < scenarios.size(); ++i) {
    const Figures& f = scenarios[i];
    json << (i == 0 ? "" : ",") << "{\"name\":\"" << f.name << "\",\"requests\":" << f.requests
         << ",\"failed\":" << f.failed << ",\"p50_ms\":" << f.p50 << ",\"p99_ms\":" << f.p99
         << ",\"max_ms\":" << f.max << "}";
  }
  json << "],\"sample_memory\":{\"rss_before_mib\":" << mib(memory.before)
       << ",\"rss_during_mib\":" << mib(memory.during) << ",\"rss_after_mib\":" << mib(memory.after)
       << ",\"answered_200\":" << memory.answered_200 << ",\"answered_503\":" << memory.answered_503
       << "}}";
  std::cout << json.str() << std::endl;
  return 0;
} catch (const std::exception& e) {
  std::cerr << "mtc-bench-bridge-abuse: " << e.what() << "\n";
  return 1;
}
