// DDS transition to streaming HTTP client: a device (mtc::dds::Equipment)
// toggles a responder between READY and NOT_READY; the bridge pieces
// (DomainObserver -> agent -> HttpServer, as mtc-bridge wires them) carry
// each change to a /sample?interval=0 client. Measured from the device's
// state-machine step (TransitionEvent::step_time_ns, just before the
// DataWriter write) to the part's arrival at the client (CLOCK_REALTIME on
// both ends, one host). Intra-process delivery is off, so samples travel
// over the loopback transports as between processes. DDS domain 110.
//
//   scripts/netns-run.sh build/benchmarks/mtc-bench-bridge-dds-stream [--samples N]
//   (--help lists the options with their defaults)
//
// Bar (docs/benchmarks.md): p50 < 200 us, p99 < 2 ms.
#include <atomic>
#include <iostream>
#include <random>
#include <thread>

#include "demo_cell.hpp"
#include "mtc/bench/cli.hpp"
#include "mtc/bench/transport.hpp"
#include "mtc/dds/domain_observer.hpp"
#include "mtc/dds/equipment.hpp"
#include "mtc/qos/participant.hpp"
#include "stream_client.hpp"

namespace {

namespace bridge = mtc::bridge;
namespace core = mtc::core;
namespace dds = mtc::dds;
namespace qos = mtc::qos;
using mtc::bridge::bench::print_summary;
using mtc::bridge::bench::StreamClient;
using mtc::bridge::bench::summarize;

constexpr int kDomain = 110;

std::int64_t wall_ns(std::chrono::system_clock::time_point t) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
}

constexpr const char* kAbout =
    "Latency from a DDS transition to a streaming HTTP client: a device\n"
    "(mtc::dds::Equipment) toggles a responder between READY and NOT_READY, and the\n"
    "bridge pieces wired as mtc-bridge wires them (DomainObserver -> agent -> HTTP\n"
    "server) carry each change to a /sample?interval=0 client. Timed from the device's\n"
    "state-machine step and from the command, to the part's arrival (wall clock, one\n"
    "host); 20 warm-up toggles are not counted. DDS domain 110 over the loopback\n"
    "transports, no intra-process delivery: runs inside the loopback-only namespace\n"
    "(scripts/netns-run.sh). One JSON line on stdout:\n"
    "  {\"benchmark\":\"bridge_http_dds_stream_latency\",\"lost\",\n"
    "   \"from_transition_us\":{p50,p90,p99,max,mean},\n"
    "   \"from_command_us\":{...},\"legs_us\":{dds,observer_handoff,agent_to_client},\n"
    "   \"meets_bar\",...}\n"
    "(legs: the transition to the observer's listener, the listener to its dispatch\n"
    "thread calling the agent, that call to the client's arrival).\n"
    "(bar, from the transition: p50 < 200 us, p99 < 2 ms, none lost).\n"
    "benchmarks/bridge_http/run.sh collects it in <build>/benchmarks/bridge_http.json.";

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

// Toggles `load` `samples` times, after 20 warm-up toggles that are not
// counted, and times the arrival of each change at `client` from the
// device's state-machine step (`step_ns`) and from the command.
Latencies measure(StreamClient& client, dds::Responder& load,
                  const std::atomic<std::int64_t>& step_ns, const Handover& handover, int samples) {
  std::mt19937 random(11);
  std::uniform_int_distribution<int> gap_us(500, 1500);
  Latencies m;
  const int warmup = 20;
  for (int k = 0; k < samples + warmup; ++k) {
    const bool ready = k % 2 == 1;
    client.expect(ready ? ">READY<" : ">NOT_READY<");
    const auto command = std::chrono::system_clock::now();
    load.set_ready(ready).get();
    const auto arrival = client.wait(std::chrono::seconds(2));
    if (!arrival) {
      ++m.lost;
      continue;
    }
    if (k >= warmup) {
      const std::int64_t step = step_ns.load();
      const std::int64_t arrived = wall_ns(arrival->wall);
      m.from_step.emplace_back(arrived - step);
      m.from_command.emplace_back(arrived - wall_ns(command));
      m.dds.emplace_back(handover.received.load() - step);
      m.handoff.emplace_back(handover.dispatched.load() - handover.received.load());
      m.bridge.emplace_back(arrived - handover.dispatched.load());
    }
    std::this_thread::sleep_for(std::chrono::microseconds(gap_us(random)));  // pacing
  }
  return m;
}

// The JSON line on stdout: both latencies and whether they meet the bar.
void print_result(const Latencies& m) {
  const int lost = m.lost;
  const auto step = summarize(m.from_step);
  std::cout << "{\"benchmark\":\"bridge_http_dds_stream_latency\",\"transport\":\"loopback\","
            << "\"lost\":" << lost << ",\"from_transition_us\":";
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

}  // namespace

int main(int argc, char** argv) try {
  int samples = 1000;
  mtc::bench::Cli cli("mtc-bench-bridge-dds-stream", kAbout);
  cli.integer("--samples", samples, 1, 10000000, "READY/NOT_READY toggles timed");
  if (const auto exit_code = cli.parse(argc, argv)) {
    return *exit_code;
  }
  qos::set_intraprocess_delivery(false);

  // The bridge, wired as mtc-bridge wires it.
  std::shared_ptr<bridge::MtconnectAgent> agent = bridge::make_agent(bridge::AgentOptions{});
  bridge::ServerOptions server_options;
  server_options.port = 0;
  bridge::HttpServer server(agent, server_options);
  server.start();
  auto observer_options = mtc::bench::loopback<dds::DomainObserverOptions>();
  observer_options.domain_id = kDomain;
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

  // The device.
  std::atomic<std::int64_t> step_ns{0};
  auto options = mtc::bench::loopback<dds::EquipmentOptions>();
  options.domain_id = kDomain;
  options.device_uuid = "bench-robot";
  dds::EquipmentCallbacks equipment_callbacks;
  equipment_callbacks.on_transition = [&](const dds::TransitionEvent& e) {
    if (e.publish_time_ns != 0) {
      step_ns = e.step_time_ns;
    }
  };
  dds::Equipment robot(options, equipment_callbacks);
  robot.add_interface({"mh1", core::InterfaceType::MaterialHandler, "", {}});
  auto& load = robot.add_responder("mh1", core::Service::MaterialLoad, dds::ResponderCallbacks{});
  robot.start();

  StreamClient client(server.port());
  client.expect(">READY<");  // the bridge has seen the device once this arrives
  if (!client.wait(std::chrono::seconds(20))) {
    throw std::runtime_error("device never reached the bridge");
  }

  print_result(measure(client, load, step_ns, handover, samples));
  return 0;
} catch (const std::exception& error) {
  std::cerr << "mtc-bench-bridge-dds-stream: " << error.what() << "\n";
  return 1;
}
