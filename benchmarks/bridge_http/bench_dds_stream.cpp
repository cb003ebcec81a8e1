// DDS transition to streaming HTTP client: a device (mtc::dds::Equipment) in
// a process of its own toggles a responder between READY and NOT_READY; the
// bridge pieces (DomainObserver -> agent -> HttpServer, as mtc-bridge wires
// them) in this process carry each change to a /sample?interval=0 client.
// Measured from the device's state-machine step (TransitionEvent::
// step_time_ns, just before the DataWriter write) to the part's arrival at
// the client (CLOCK_REALTIME on both ends, one host). Two processes, as a
// device and mtc-bridge are in a cell: in one process Cyclone DDS would
// deliver locally, past its transports. DDS domain 110.
//
//   scripts/netns-run.sh build/benchmarks/mtc-bench-bridge-dds-stream [--samples N]
//     [--middleware fastdds|cyclone] [--inline-steps] [--observer-steps inline|dispatch]
//   (--help lists the options with their defaults)
//
// Bar (docs/benchmarks.md): p50 < 200 us, p99 < 2 ms.
#include <fcntl.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <mutex>
#include <optional>
#include <random>
#include <thread>

#include "demo_cell.hpp"
#include "mtc/bench/cli.hpp"
#include "mtc/bench/peer_process.hpp"
#include "mtc/bench/transport.hpp"
#include "mtc/dds/domain_observer.hpp"
#include "mtc/dds/equipment.hpp"
#include "mtc/dds/middleware.hpp"
#include "stream_client.hpp"

namespace {

namespace bridge = mtc::bridge;
namespace core = mtc::core;
namespace dds = mtc::dds;
using mtc::bridge::bench::print_summary;
using mtc::bridge::bench::StreamClient;
using mtc::bridge::bench::summarize;

constexpr int kDomain = 110;
constexpr const char* kArgv0 = "mtc-bench-bridge-dds-stream";

std::int64_t wall_ns(std::chrono::system_clock::time_point t) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
}

constexpr const char* kAbout =
    "Latency from a DDS transition to a streaming HTTP client: a device\n"
    "(mtc::dds::Equipment) in a second process toggles a responder between READY and\n"
    "NOT_READY, and the bridge pieces wired as mtc-bridge wires them (DomainObserver ->\n"
    "agent -> HTTP server) carry each change to a /sample?interval=0 client. Timed from\n"
    "the device's state-machine step and from its command, to the part's arrival (wall\n"
    "clock, one host); 20 warm-up toggles are not counted. DDS domain 110 over the\n"
    "loopback transports: runs inside the loopback-only namespace (scripts/netns-run.sh).\n"
    "--middleware puts the device and the observer on one DDS implementation;\n"
    "--inline-steps lets the device step a received value on the middleware's thread\n"
    "(EquipmentOptions::inline_steps); --observer-steps says where the observer hands a\n"
    "value to the agent: inline, on the middleware's thread (mtc-bridge's default,\n"
    "InlineSteps = yes), or dispatch, on its own thread (InlineSteps = no).\n"
    "One JSON line on stdout:\n"
    "  {\"benchmark\":\"bridge_http_dds_stream_latency\",\"middleware\",\"inline_steps\",\n"
    "   \"observer_steps\",\n"
    "   "
    "\"direct_stream_writes\",\"processes\":2,\"lost\",\"direct_parts\",\"from_transition_us\":{"
    "p50,p90,p99,max,mean},\n"
    "   \"from_command_us\":{...},\"legs_us\":{dds,observer_handoff,agent_to_client},\n"
    "   \"meets_bar\",...}\n"
    "(legs: the transition to the observer's listener, the listener to its dispatch\n"
    "thread calling the agent, that call to the client's arrival).\n"
    "(bar, from the transition: p50 < 200 us, p99 < 2 ms, none lost).\n"
    "benchmarks/bridge_http/run.sh collects it in <build>/benchmarks/bridge_http.json.";

// What a run was asked to measure; the last two are the device process's.
struct Setup {
  int samples = 1000;
  dds::Middleware middleware = dds::Middleware::FastDds;
  bool inline_steps = false;    // the device's
  bool observer_inline = true;  // as mtc-bridge ships (InlineSteps = yes)
  int direct_stream_writes = static_cast<int>(bridge::ServerOptions{}.direct_stream_writes);
  int command_fd = -1;  // the device reads its toggles here ('r', 'n')
  bool device = false;
};

// The device process: toggles as told on `command_fd` and writes, for each
// toggle, "<command ns> <step ns>\n" (wall clock) to stdout. Ends at EOF.
int run_device(const Setup& setup) {
  std::mutex mutex;
  std::condition_variable stepped;
  std::int64_t step_ns = 0;
  auto options = mtc::bench::loopback<dds::EquipmentOptions>();
  options.domain_id = kDomain;
  options.device_uuid = "bench-robot";
  options.middleware = setup.middleware;
  options.inline_steps = setup.inline_steps;
  dds::EquipmentCallbacks callbacks;
  callbacks.on_transition = [&](const dds::TransitionEvent& e) {
    if (e.publish_time_ns == 0) return;  // not written to DDS
    std::lock_guard<std::mutex> lock(mutex);
    step_ns = e.step_time_ns;
    stepped.notify_all();
  };
  dds::Equipment robot(options, callbacks);
  robot.add_interface({"mh1", core::InterfaceType::MaterialHandler, "", {}});
  auto& load = robot.add_responder("mh1", core::Service::MaterialLoad, dds::ResponderCallbacks{});
  robot.start();
  char command = 0;
  while (::read(setup.command_fd, &command, 1) == 1) {
    std::unique_lock<std::mutex> lock(mutex);
    const std::int64_t before = step_ns;
    lock.unlock();
    const std::int64_t command_ns = wall_ns(std::chrono::system_clock::now());
    load.set_ready(command == 'r').get();
    lock.lock();
    stepped.wait_for(lock, std::chrono::seconds(2), [&] { return step_ns != before; });
    std::printf("%lld %lld\n", static_cast<long long>(command_ns),
                static_cast<long long>(step_ns == before ? 0 : step_ns));
    std::fflush(stdout);
  }
  return 0;
}

struct Latencies {
  std::vector<std::chrono::nanoseconds> from_step;
  std::vector<std::chrono::nanoseconds> from_command;
  // The same path in three legs, to tell where the time goes: the step to
  // the observer's DDS listener (reception time), the listener to the
  // observer's dispatch thread calling the agent, that call to the client.
  std::vector<std::chrono::nanoseconds> dds, handoff, bridge;
  int lost = 0;
};

// Wall-clock times (ns) of the latest value the observer handed over:
// taken by its listener, and handed to the agent.
struct Handover {
  std::atomic<std::int64_t> received{0};
  std::atomic<std::int64_t> dispatched{0};
};

// The device process, from this side: its toggles go down one pipe, its
// command and step times come back up another.
class Device {
 public:
  explicit Device(const Setup& setup) {
    int commands[2];
    int reports[2];
    // Close-on-exec but for the device's end of its toggles: the device
    // must not hold this side's ends, or it would never see the EOF.
    if (::pipe2(commands, O_CLOEXEC) != 0 || ::pipe2(reports, O_CLOEXEC) != 0 ||
        ::fcntl(commands[0], F_SETFD, 0) != 0) {
      throw std::runtime_error("pipe failed");
    }
    std::vector<std::string> args{"--device", "--command-fd", std::to_string(commands[0]),
                                  "--middleware", std::string(dds::to_string(setup.middleware))};
    if (setup.inline_steps) args.emplace_back("--inline-steps");
    pid_ = mtc::bench::exec_self(kArgv0, args, reports[1]);
    ::close(commands[0]);
    ::close(reports[1]);
    commands_ = commands[1];
    reports_ = ::fdopen(reports[0], "r");
    if (reports_ == nullptr) throw std::runtime_error("fdopen failed");
  }
  ~Device() {
    ::close(commands_);  // EOF: the device ends
    std::fclose(reports_);
    mtc::bench::stop_child(pid_, std::chrono::seconds(5));
  }
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  void toggle(bool ready) {
    const char c = ready ? 'r' : 'n';
    if (::write(commands_, &c, 1) != 1) throw std::runtime_error("the device process is gone");
  }
  // The command and step times (wall ns) of the last toggle; step 0: none.
  std::pair<std::int64_t, std::int64_t> report() {
    std::array<char, 64> line{};
    if (std::fgets(line.data(), static_cast<int>(line.size()), reports_) == nullptr) {
      throw std::runtime_error("the device process did not report its toggle");
    }
    char* rest = nullptr;
    const long long command = std::strtoll(line.data(), &rest, 10);
    char* end = nullptr;
    const long long step = std::strtoll(rest, &end, 10);
    if (end == rest || (*end != '\n' && *end != '\0')) {
      throw std::runtime_error("the device process reported '" + std::string(line.data()) + "'");
    }
    return {command, step};
  }

 private:
  pid_t pid_ = -1;
  int commands_ = -1;
  std::FILE* reports_ = nullptr;
};

// Toggles the device `samples` times, after 20 warm-up toggles that are not
// counted, and times the arrival of each change at `client`.
Latencies measure(StreamClient& client, Device& device, const Handover& handover, int samples) {
  std::mt19937 random(11);
  std::uniform_int_distribution<int> gap_us(500, 1500);
  Latencies m;
  const int warmup = 20;
  for (int k = 0; k < samples + warmup; ++k) {
    const bool ready = k % 2 == 1;
    client.expect(ready ? ">READY<" : ">NOT_READY<");
    device.toggle(ready);
    const auto arrival = client.wait(std::chrono::seconds(2));
    const auto [command, step] = device.report();
    if (!arrival || step == 0) {
      ++m.lost;
      continue;
    }
    if (k >= warmup) {
      const std::int64_t arrived = wall_ns(arrival->wall);
      m.from_step.emplace_back(arrived - step);
      m.from_command.emplace_back(arrived - command);
      m.dds.emplace_back(handover.received.load() - step);
      m.handoff.emplace_back(handover.dispatched.load() - handover.received.load());
      m.bridge.emplace_back(arrived - handover.dispatched.load());
    }
    std::this_thread::sleep_for(std::chrono::microseconds(gap_us(random)));  // pacing
  }
  return m;
}

// The JSON line on stdout: both latencies and whether they meet the bar.
// `direct_parts`: parts the server wrote on the observer's thread
// (ServerOptions::direct_stream_writes).
void print_result(const Setup& setup, const Latencies& m, std::uint64_t direct_parts) {
  const int lost = m.lost;
  const auto step = summarize(m.from_step);
  std::cout << "{\"benchmark\":\"bridge_http_dds_stream_latency\",\"transport\":\"loopback\","
            << "\"middleware\":\"" << dds::to_string(setup.middleware)
            << "\",\"inline_steps\":" << (setup.inline_steps ? "true" : "false")
            << ",\"observer_steps\":\"" << (setup.observer_inline ? "inline" : "dispatch") << '"'
            << ",\"direct_stream_writes\":" << setup.direct_stream_writes
            << ",\"processes\":2,\"lost\":" << lost << ",\"direct_parts\":" << direct_parts
            << ",\"from_transition_us\":";
  print_summary(std::cout, step);
  std::cout << ",\"from_command_us\":";
  print_summary(std::cout, summarize(m.from_command));
  std::cout << ",\"legs_us\":{\"dds\":";
  print_summary(std::cout, summarize(m.dds));
  std::cout << ",\"observer_handoff\":";
  print_summary(std::cout, summarize(m.handoff));
  std::cout << ",\"agent_to_client\":";
  print_summary(std::cout, summarize(m.bridge));
  std::cout << "}";
  std::cout << ",\"bar\":{\"max_p50_us\":200,\"max_p99_us\":2000},\"meets_bar\":"
            << ((lost == 0 && step.p50_us < 200 && step.p99_us < 2000) ? "true" : "false") << "}"
            << std::endl;
}

// The bridge side: observer, agent and server, the device process and the
// streaming client; prints the JSON line.
int run_bridge(const Setup& setup) {
  std::shared_ptr<bridge::MtconnectAgent> agent = bridge::make_agent(bridge::AgentOptions{});
  bridge::ServerOptions server_options;
  server_options.port = 0;
  server_options.direct_stream_writes = static_cast<std::size_t>(setup.direct_stream_writes);
  bridge::HttpServer server(agent, server_options);
  server.start();
  auto observer_options = mtc::bench::loopback<dds::DomainObserverOptions>();
  observer_options.domain_id = kDomain;
  observer_options.middleware = setup.middleware;
  observer_options.inline_steps = setup.observer_inline;
  dds::DomainObserverCallbacks callbacks;
  callbacks.on_device = [&](const dds::ObservedDevice& d) { agent->add_device(d); };
  Handover handover;
  callbacks.on_value = [&](const dds::ObservedValue& v) {
    handover.received = v.reception_time_ns;
    handover.dispatched = wall_ns(std::chrono::system_clock::now());
    agent->add_value(v);
  };
  callbacks.on_items_lost = [&](const std::string& uuid, const std::vector<std::string>& ids) {
    agent->items_lost(uuid, ids);
  };
  dds::DomainObserver observer(observer_options, callbacks);

  Device device(setup);
  StreamClient client(server.port());
  client.expect(">READY<");  // the bridge has seen the device once this arrives
  if (!client.wait(std::chrono::seconds(20))) {
    throw std::runtime_error("device never reached the bridge");
  }
  const Latencies latencies = measure(client, device, handover, setup.samples);
  print_result(setup, latencies, server.direct_stream_parts());
  return 0;
}

// The options, or the exit code of --help or of a bad option.
std::optional<int> parse(int argc, char** argv, Setup& setup) {
  std::string middleware = "fastdds";
  std::string observer_steps = "inline";
  mtc::bench::Cli cli(kArgv0, kAbout);
  cli.integer("--samples", setup.samples, 1, 10000000, "READY/NOT_READY toggles timed")
      .choice("--middleware", middleware, {"fastdds", "cyclone"},
              "DDS implementation of the device and the observer")
      .flag("--inline-steps", setup.inline_steps,
            "the device steps a received value on the middleware's thread")
      .choice("--observer-steps", observer_steps, {"inline", "dispatch"},
              "where the observer hands a value to the agent (mtc-bridge's InlineSteps)")
      .integer("--direct-stream-writes", setup.direct_stream_writes, 0, 1000,
               "the server's ServerOptions::direct_stream_writes (0: parts from its io thread)")
      .internal_options_follow()
      .flag("--device", setup.device, "run as the device process")
      .integer("--command-fd", setup.command_fd, 0, 1 << 20, "the device's toggles");
  if (const auto exit_code = cli.parse(argc, argv)) {
    return exit_code;
  }
  const auto choice = dds::choose_middleware(middleware);
  if (!choice.middleware) {
    std::cerr << kArgv0 << ": " << choice.problem << "\n";
    return 2;
  }
  setup.middleware = *choice.middleware;
  setup.observer_inline = observer_steps == "inline";
  return std::nullopt;
}

}  // namespace

int main(int argc, char** argv) try {
  Setup setup;
  if (const auto exit_code = parse(argc, argv, setup)) {
    return *exit_code;
  }
  return setup.device ? run_device(setup) : run_bridge(setup);
} catch (const std::exception& error) {
  std::cerr << kArgv0 << ": " << error.what() << "\n";
  return 1;
}
