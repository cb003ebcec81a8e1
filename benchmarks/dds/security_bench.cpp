// mtc-bench-security: what DDS-Security costs the runtime, secured beside
// unsecured in one run on one machine:
// * start-up: an Equipment's start() (participant, topics, writers,
//   readers; with security the identity, permissions and governance are
//   validated), then until it is paired with a running counterpart and sees
//   it READY (discovery, and with security the PKI-DH handshake and the key
//   exchange);
// * handshake: a MATERIAL_LOAD request() until its outcome, COMPLETED
//   (Part 5 Table 1 up to the requester seeing COMPLETE), intra-process
//   delivery off so every sample crosses UDP loopback (and with security,
//   AES-GCM); the next one starts once the responder is READY again.
// The PKI comes from scripts/security/make-pki.sh in a temporary directory.
// DDS domains 107-108. Runs inside the loopback-only namespace
// (benchmarks/run.sh does that). One JSON object on stdout (and --out FILE).

#include <stdlib.h>  // mkdtemp

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "latency_stats.hpp"
#include "mtc/bench/cli.hpp"
#include "mtc/dds/equipment.hpp"
#include "mtc/qos/participant.hpp"

namespace {

namespace fs = std::filesystem;
using mtc::bench::Series;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

constexpr const char* kAbout =
    "What DDS-Security costs the runtime, secured beside unsecured in one run:\n"
    "Equipment start() time, start until paired with a running counterpart\n"
    "(discovery + authentication), and MATERIAL_LOAD handshake latency over UDP\n"
    "loopback. The PKI comes from scripts/security/make-pki.sh (--source DIR: the\n"
    "repository). DDS domains 107-108: run inside the loopback-only namespace\n"
    "(benchmarks/run.sh). One JSON object on stdout and, with --out, in FILE:\n"
    "  {\"benchmark\":\"security\",\"unit\":\"us\",\"series\":[{name,p50,p90,p99,max,...}]}";

struct Options {
  int starts = 10;
  int handshakes = 200;
  std::string source = MTC_SOURCE_DIR;
  std::string out;
};

// The PKI of the two benchmark devices, in a temporary directory.
std::string make_pki(const std::string& source) {
  char pattern[] = "/tmp/mtc-bench-security-XXXXXX";
  const char* dir = ::mkdtemp(pattern);
  if (dir == nullptr) throw std::runtime_error("mkdtemp failed");
  std::string root = dir;
  std::ofstream(root + "/cell.txt")
      << "device bench-cnc requests=material_load reads=bench-robot\n"
         "device bench-robot provides=material_load reads=bench-cnc\n";
  const std::string command = "'" + source + "/scripts/security/make-pki.sh' --cell '" + root +
                              "/cell.txt' --out '" + root + "/pki' >/dev/null";
  // Called first thing in main, before any participant starts a thread.
  if (std::system(command.c_str()) != 0) {  // NOLINT(concurrency-mt-unsafe)
    throw std::runtime_error("make-pki.sh failed");
  }
  return root;
}

mtc::dds::EquipmentOptions options(int domain, const std::string& uuid, const std::string& pki) {
  mtc::dds::EquipmentOptions o;
  o.domain_id = domain;
  o.device_uuid = uuid;
  o.transport = mtc::qos::Transport::LoopbackUdp;
  o.timing.heartbeat = 200ms;  // a 1 s lease: no false loss on a busy machine
  o.timing.missed_heartbeats = 5;
  if (!pki.empty()) o.security_dir = pki + "/" + uuid;
  return o;
}

struct Pair {
  mtc::dds::Equipment cnc;
  mtc::dds::Equipment robot;
  mtc::dds::Requester* load = nullptr;

  Pair(int domain, const std::string& pki)
      : cnc(options(domain, "bench-cnc", pki)), robot(options(domain, "bench-robot", pki)) {
    cnc.add_interface(
        {"mh1", mtc::core::InterfaceType::MaterialHandler, "", {"bench-robot", "mh1"}});
    robot.add_interface(
        {"mh1", mtc::core::InterfaceType::MaterialHandler, "", {"bench-cnc", "mh1"}});
    load = &cnc.add_requester("mh1", mtc::core::Service::MaterialLoad);
    mtc::dds::ResponderCallbacks cb;
    cb.on_request = [](mtc::dds::Responder& r) { r.complete(); };
    robot.add_responder("mh1", mtc::core::Service::MaterialLoad, cb);
  }
};

// Polls (1 ms) until the requester sees its counterpart READY, or 30 s:
// start-up figures are in milliseconds, so the polling step is noise.
bool wait_paired(const mtc::dds::Requester& load) {
  const auto deadline = Clock::now() + 30s;
  while (load.counterpart_state() != mtc::core::InteractionState::Ready) {
    if (Clock::now() > deadline) return false;
    std::this_thread::sleep_for(1ms);
  }
  return true;
}

Series series(const std::string& name, const std::string& metric, bool secured) {
  Series s;
  s.name = name + (secured ? "_secured" : "_unsecured");
  s.layer = "mtc_equipment";
  s.metric = metric;
  s.transport = "udp_loopback";
  return s;
}

// Start-up: a fresh pair each time (the robot already running, the cnc
// timed from start() to its first READY of the robot).
void measure_starts(int domain, const std::string& pki, int count, Series& start, Series& paired) {
  for (int i = 0; i < count; ++i) {
    Pair pair(domain, pki);
    pair.robot.start();
    const auto t0 = Clock::now();
    pair.cnc.start();
    const auto t1 = Clock::now();
    start.samples_us.push_back(mtc::bench::to_us(t1 - t0));
    if (wait_paired(*pair.load)) {
      paired.samples_us.push_back(mtc::bench::to_us(Clock::now() - t0));
    } else {
      ++paired.timeouts;
    }
  }
}

void measure_handshakes(int domain, const std::string& pki, int count, Series& out) {
  Pair pair(domain, pki);
  pair.robot.start();
  pair.cnc.start();
  if (!wait_paired(*pair.load)) {
    out.timeouts = static_cast<std::size_t>(count);
    return;
  }
  mtc::dds::RequestOptions wait;
  wait.wait_for_ready = 10s;
  for (int i = 0; i < count; ++i) {
    const auto r = pair.load->request(wait).get();
    if (r.outcome == mtc::dds::Outcome::Completed) {
      out.samples_us.push_back(std::chrono::duration<double, std::micro>(r.elapsed).count());
    } else {
      ++out.timeouts;
    }
    // Untimed: the responder back to READY before the next request.
    if (!wait_paired(*pair.load)) ++out.timeouts;
  }
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  mtc::bench::Cli cli("mtc-bench-security", kAbout);
  cli.integer("--starts", o.starts, 1, 10000, "start-ups measured per mode")
      .integer("--handshakes", o.handshakes, 1, 1000000, "handshakes measured per mode")
      .text("--source", "DIR", o.source, "repository holding scripts/security/make-pki.sh")
      .text("--out", "FILE", o.out, "also write the JSON summary to FILE");
  if (const auto exit_code = cli.parse(argc, argv)) return *exit_code;
  try {
    mtc::qos::set_intraprocess_delivery(false);
    const std::string root = make_pki(o.source);
    std::vector<Series> all;
    for (const bool secured : {false, true}) {
      const std::string pki = secured ? root + "/pki" : "";
      std::cerr << "mtc-bench-security: " << (secured ? "secured" : "unsecured") << "\n";
      auto start = series("equipment_start", "start", secured);
      auto paired = series("start_until_paired", "start_until_paired", secured);
      measure_starts(107, pki, o.starts, start, paired);
      auto handshake = series("handshake", "handshake", secured);
      measure_handshakes(108, pki, o.handshakes, handshake);
      all.push_back(start);
      all.push_back(paired);
      all.push_back(handshake);
    }
    fs::remove_all(root);
    std::ostringstream json;
    json << "{\"benchmark\":\"security\",\"unit\":\"us\",\"series\":[";
    for (std::size_t i = 0; i < all.size(); ++i) json << (i > 0 ? "," : "") << to_json(all[i]);
    json << "]}\n";
    std::cout << json.str();
    if (!o.out.empty()) std::ofstream(o.out) << json.str();
  } catch (const std::exception& e) {
    std::cerr << "mtc-bench-security: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
