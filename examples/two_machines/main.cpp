// One robot tending two machines (issue 12, pairing made explicit): the
// robot has one interface per machine, each paired explicitly with that
// machine's interface (CounterpartSpec: device uuid + interface id), and
// serves MATERIAL_LOAD on both. Each machine requests loads on its own
// thread, both at once, for --cycles rounds. Three devices, one process.
//
// Usage: mtc-example-two-machines [--domain D] [--cycles N] [--hold-ms MS]
//   --hold-ms: stay up this long after the last cycle (so a bridge can be
//   asked about the devices while they are alive); default 0.
// Exit 0 when every load of both machines completed, 1 otherwise, 2 on a
// usage error.
#include <chrono>
#include <cstdlib>
#include <future>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include "mtc/dds/equipment.hpp"

namespace {

using namespace std::chrono_literals;
namespace core = mtc::core;
namespace dds = mtc::dds;

struct Options {
  int domain = 0;
  int cycles = 3;
  int hold_ms = 0;
};

void usage(std::ostream& out) {
  out << "usage: mtc-example-two-machines [--domain D] [--cycles N] [--hold-ms MS]\n"
         "One robot (robot-1) serves MATERIAL_LOAD to machine-a and machine-b through two\n"
         "interfaces, mh-a and mh-b, each paired explicitly with one machine's interface mh.\n";
}

bool parse(int argc, char** argv, Options& o, int& exit_code) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "-h" || arg == "--help") {
      usage(std::cout);
      exit_code = 0;
      return false;
    }
    int* target = arg == "--domain"    ? &o.domain
                  : arg == "--cycles"  ? &o.cycles
                  : arg == "--hold-ms" ? &o.hold_ms
                                       : nullptr;
    if (target == nullptr || i + 1 >= argc) {
      std::cerr << "mtc-example-two-machines: unknown option or missing value '" << arg << "'\n";
      usage(std::cerr);
      exit_code = 2;
      return false;
    }
    char* end = nullptr;
    const long value = std::strtol(argv[++i], &end, 10);
    if (*end != '\0' || value < 0 || value > 100000) {
      std::cerr << "mtc-example-two-machines: bad value for " << arg << "\n";
      exit_code = 2;
      return false;
    }
    *target = static_cast<int>(value);
  }
  return true;
}

dds::EquipmentOptions equipment(int domain, const std::string& uuid) {
  dds::EquipmentOptions o;
  o.domain_id = domain;
  o.device_uuid = uuid;
  // The three devices share this process and host; the bridge that watches
  // them (run_two_machines.sh) is told --transport loopback as well.
  o.transport = mtc::qos::Transport::Loopback;
  return o;
}

// One machine: requests MATERIAL_LOAD `cycles` times; returns the completed count.
int run_machine(dds::Requester& load, const std::string& name, int cycles) {
  int completed = 0;
  dds::RequestOptions wait;
  wait.wait_for_ready = 10s;
  for (int n = 1; n <= cycles; ++n) {
    const dds::RequestResult r = load.request(wait).get();
    std::cout << name << " MATERIAL_LOAD #" << n << ": " << dds::to_string(r.outcome) << "\n";
    if (r.outcome == dds::Outcome::Completed) ++completed;
  }
  return completed;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  int exit_code = 0;
  if (!parse(argc, argv, o, exit_code)) return exit_code;

  dds::Equipment robot(equipment(o.domain, "robot-1"));
  dds::Equipment machine_a(equipment(o.domain, "machine-a"));
  dds::Equipment machine_b(equipment(o.domain, "machine-b"));
  const auto mh = core::InterfaceType::MaterialHandler;
  robot.add_interface({"mh-a", mh, "to machine A", {"machine-a", "mh"}});
  robot.add_interface({"mh-b", mh, "to machine B", {"machine-b", "mh"}});
  machine_a.add_interface({"mh", mh, "", {"robot-1", "mh-a"}});
  machine_b.add_interface({"mh", mh, "", {"robot-1", "mh-b"}});
  dds::ResponderCallbacks serve;
  serve.on_request = [](dds::Responder& r) { r.complete(); };
  robot.add_responder("mh-a", core::Service::MaterialLoad, serve);
  robot.add_responder("mh-b", core::Service::MaterialLoad, serve);
  auto& load_a = machine_a.add_requester("mh", core::Service::MaterialLoad);
  auto& load_b = machine_b.add_requester("mh", core::Service::MaterialLoad);
  robot.start();
  machine_a.start();
  machine_b.start();

  auto a = std::async(std::launch::async, run_machine, std::ref(load_a), "machine-a", o.cycles);
  auto b = std::async(std::launch::async, run_machine, std::ref(load_b), "machine-b", o.cycles);
  const int done = a.get() + b.get();
  std::cout << "two machines: " << done << " of " << 2 * o.cycles << " loads COMPLETE\n"
            << std::flush;
  std::this_thread::sleep_for(std::chrono::milliseconds(o.hold_ms));
  return done == 2 * o.cycles ? 0 : 1;
}
