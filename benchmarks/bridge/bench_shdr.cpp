// The SHDR adapter's figures: how many observation lines a second reach an
// agent reading as fast as it can, and how long an agent's (re)connect
// takes until it holds the whole state (connect to last line of the dump).
// Loopback TCP, no DDS: the agent is fed directly, as the DDS observer does.
//
// Prints one JSON line:
//   {"benchmark":"bridge_shdr","items","changes","lines_per_s","connect_ms_median",
//    "connect_ms_max","reconnects"}
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <iostream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "mtc/bench/cli.hpp"
#include "mtc/bridge/shdr_adapter.hpp"

namespace {

namespace core = mtc::core;
using Clock = std::chrono::steady_clock;

constexpr const char* kAbout =
    "Feeds the bridge's agent and reads its SHDR adapter as an MTConnect agent would over\n"
    "loopback TCP: observation lines per second to one reader, and the time from connect\n"
    "to the whole initial state over repeated reconnects. One JSON line on stdout.";

// A connected reader counting lines.
class Reader {
 public:
  explicit Reader(std::uint16_t port) : fd_(::socket(AF_INET, SOCK_STREAM, 0)) {
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(port);
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
      throw std::runtime_error("cannot connect to the SHDR port");
    }
  }
  // Owns the socket: a copy would close it twice.
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;
  ~Reader() { ::close(fd_); }
  // Reads until `count` lines in all have arrived; false at EOF.
  bool read_lines(std::size_t count) {
    char chunk[65536];
    while (lines_ < count) {
      const ssize_t n = ::recv(fd_, chunk, sizeof chunk, 0);
      if (n <= 0) return false;
      lines_ += static_cast<std::size_t>(std::count(chunk, chunk + n, '\n'));
    }
    return true;
  }

 private:
  int fd_ = -1;
  std::size_t lines_ = 0;
};

std::shared_ptr<mtc::bridge::MtconnectAgent> make_cell_agent(int devices) {
  mtc::bridge::AgentOptions options;
  options.buffer_size = std::size_t{1} << 20;
  std::shared_ptr<mtc::bridge::MtconnectAgent> agent = mtc::bridge::make_agent(options);
  for (int i = 0; i < devices; ++i) {
    core::ObservedDevice d;
    d.device_uuid = "mill-" + std::to_string(i);
    d.name = d.device_uuid;
    core::ObservedInterface mh{"mh", "mh", core::InterfaceType::MaterialHandler, {}};
    for (const char* type : {"MATERIAL_LOAD", "MATERIAL_UNLOAD"}) {
      core::ObservedDataItem di;
      di.id = std::string(type) + "_req";
      di.type = type;
      di.sub_type = "REQUEST";
      di.category = "EVENT";
      mh.data_items.push_back(di);
    }
    d.interfaces = {mh};
    agent->add_device(d);
  }
  return agent;
}

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) try {
  int changes = 200000;
  int devices = 50;
  int reconnects = 20;
  mtc::bench::Cli cli("mtc-bench-bridge-shdr", kAbout);
  cli.integer("--changes", changes, 1, 10000000, "observations fed for the throughput run")
      .integer("--devices", devices, 1, 10000, "announced devices (5 items each)")
      .integer("--reconnects", reconnects, 1, 10000, "connects timed");
  if (const auto exit_code = cli.parse(argc, argv)) return *exit_code;

  auto agent = make_cell_agent(devices);
  mtc::bridge::ShdrOptions options;
  options.port = 0;
  mtc::bridge::ShdrAdapter adapter(agent, options);
  adapter.start();
  std::uint64_t next = 0;
  const std::size_t items = agent->latest_observations(next).size();

  std::vector<double> connect_ms;
  for (int i = 0; i < reconnects; ++i) {
    const auto start = Clock::now();
    Reader reader(adapter.port());
    if (!reader.read_lines(items)) throw std::runtime_error("dump cut short");
    connect_ms.push_back(ms_since(start));
  }
  std::sort(connect_ms.begin(), connect_ms.end());

  Reader reader(adapter.port());
  if (!reader.read_lines(items)) throw std::runtime_error("dump cut short");
  const auto start = Clock::now();
  std::thread feeder([&] {
    for (int i = 0; i < changes; ++i) {
      core::ObservedValue v;
      v.device_uuid = "mill-" + std::to_string(i % devices);
      v.data_item_id = "MATERIAL_LOAD_req";
      v.state =
          (i / devices) % 2 != 0 ? core::InteractionState::Active : core::InteractionState::Ready;
      v.source_time_ns = 1;
      agent->add_value(v);
    }
  });
  const bool complete = reader.read_lines(items + static_cast<std::size_t>(changes));
  const double elapsed_ms = ms_since(start);
  feeder.join();
  if (!complete) throw std::runtime_error("the adapter closed the reader");

  std::cout << "{\"benchmark\":\"bridge_shdr\",\"items\":" << items << ",\"changes\":" << changes
            << ",\"lines_per_s\":" << static_cast<long long>(changes / (elapsed_ms / 1000.0))
            << ",\"connect_ms_median\":" << connect_ms[connect_ms.size() / 2]
            << ",\"connect_ms_max\":" << connect_ms.back() << ",\"reconnects\":" << reconnects
            << ",\"dropped\":" << adapter.stats().dropped << "}" << std::endl;
  adapter.stop();
  return 0;
} catch (const std::exception& e) {
  std::cerr << "mtc-bench-bridge-shdr: " << e.what() << "\n";
  return 1;
}
