// A controller vendor's first program, and the README's vendor snippet: a
// machine tool's CNC (device "cnc-1") asks the robot (device "robot-1",
// interface "mh1") to load a blank, MATERIAL_LOAD, and reports how the
// handshake ended. The README quotes the lines between the [snippet]
// markers; the docs tests keep that copy equal to them and run this program
// against `mtc respond` playing the robot (examples/run_vendor_example.sh).
//
// Usage: mtc-example-cnc [--domain N] [--transport network|loopback]
//        exit 0 when the load COMPLETED
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <string>

#include "mtc/dds/equipment.hpp"
#include "mtc/qos/participant.hpp"

namespace {

int load_one_blank(int domain_id, mtc::qos::Transport transport) {
  // [snippet]
  mtc::dds::EquipmentOptions options;
  options.domain_id = domain_id;
  options.device_uuid = "cnc-1";  // this device: it writes in partition mtc/dev/cnc-1
  options.transport = transport;  // Network (default): any host of the cell; Loopback: this one
  mtc::dds::Equipment cnc(options);

  // One material-handler interface, paired with interface "mh1" of device "robot-1".
  cnc.add_interface({"mh1", mtc::core::InterfaceType::MaterialHandler, "", {"robot-1", "mh1"}});
  mtc::dds::Requester& load = cnc.add_requester("mh1", mtc::core::Service::MaterialLoad);
  cnc.start();  // joins the domain, publishes READY, heartbeats, watches the robot

  mtc::dds::RequestOptions wait;
  wait.wait_for_ready = std::chrono::seconds(5);  // the robot may still be starting
  const mtc::dds::RequestResult result = load.request(wait).get();  // Table 1, steps 1-8
  if (result.outcome != mtc::dds::Outcome::Completed) {  // FAILED, TIMED_OUT, COMMS_LOST, ...
    std::cerr << "MATERIAL_LOAD " << mtc::dds::to_string(result.outcome) << ": "
              << mtc::core::describe(result.reason) << "\n";
    return 1;
  }
  std::cout << "MATERIAL_LOAD COMPLETED in "
            << std::chrono::duration<double, std::milli>(result.elapsed).count() << " ms\n";
  return 0;
  // [snippet]
}

void usage(std::ostream& out) {
  out << "usage: mtc-example-cnc [--domain N] [--transport KIND]\n"
         "A CNC (device cnc-1) requests MATERIAL_LOAD from the robot (device robot-1,\n"
         "interface mh1) over DDS and prints the outcome; exit 0 when it COMPLETED.\n"
         "  --domain N        DDS domain id, 0-232 (default 0)\n"
         "  --transport KIND  network (default: Fast DDS's UDPv4 + SHM, the robot on any\n"
         "                    host of the cell) or loopback (this host only)\n"
         "Play the robot with: mtc respond --device robot-1 --interface mh1 "
         "--service MATERIAL_LOAD\n";
}

// The value of `--domain N`, or nothing when `text` is not a domain id.
std::optional<int> parse_domain(const char* text) {
  char* end = nullptr;
  const long value = std::strtol(text, &end, 10);
  if (end == text || *end != '\0' || value < 0 || value > 232) return std::nullopt;
  return static_cast<int>(value);
}

}  // namespace

int main(int argc, char** argv) {
  int domain_id = 0;
  mtc::qos::Transport transport = mtc::qos::Transport::Network;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      usage(std::cout);
      return 0;
    }
    const char* value = i + 1 < argc ? argv[++i] : "";
    const std::optional<int> domain = arg == "--domain" ? parse_domain(value) : std::nullopt;
    const std::optional<mtc::qos::Transport> kind =
        arg == "--transport" ? mtc::qos::parse_transport(value) : std::nullopt;
    if (domain) {
      domain_id = *domain;
    } else if (kind) {
      transport = *kind;
    } else {
      std::cerr << "mtc-example-cnc: bad option or value: " << arg << "\n";
      usage(std::cerr);
      return 2;
    }
  }
  try {
    return load_one_blank(domain_id, transport);
  } catch (const std::exception& e) {  // mtc::dds::Error: a DDS entity could not be created
    std::cerr << "mtc-example-cnc: " << e.what() << "\n";
    return 1;
  }
}
