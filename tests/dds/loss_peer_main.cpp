// mtc-test-loss-peer: the counterpart process of test_loss_detection. Runs a
// responder Equipment ("peer-ld", interface mh1, MATERIAL_LOAD, paired with
// "watch-ld") on the given domain with a 100 ms x 5 heartbeat over UDP
// loopback until a signal ends it; dies with its parent.
//
// usage: mtc-test-loss-peer DOMAIN
#include <signal.h>
#include <sys/prctl.h>
#include <unistd.h>

#include <cstdlib>
#include <iostream>
#include <string>

#include "mtc/dds/equipment.hpp"

int main(int argc, char** argv) {
  if (argc != 2 || std::string(argv[1]) == "--help") {
    std::cerr << "usage: mtc-test-loss-peer DOMAIN\n";
    return argc == 2 ? 0 : 2;
  }
  char* end = nullptr;
  const long domain = std::strtol(argv[1], &end, 10);
  if (end == argv[1] || *end != '\0' || domain < 0 || domain > 232) {
    std::cerr << "mtc-test-loss-peer: DOMAIN must be a number from 0 to 232\n";
    return 2;
  }
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  mtc::dds::EquipmentOptions o;
  o.domain_id = static_cast<int>(domain);
  o.device_uuid = "peer-ld";
  o.transport = mtc::qos::Transport::LoopbackUdp;
  o.timing.missed_heartbeats = 5;
  mtc::dds::Equipment peer(o);
  peer.add_interface({"mh1", mtc::core::InterfaceType::MaterialHandler, "", {"watch-ld", "mh1"}});
  mtc::dds::ResponderCallbacks rc;
  rc.on_request = [](mtc::dds::Responder& r) { r.complete(); };
  peer.add_responder("mh1", mtc::core::Service::MaterialLoad, rc);
  peer.start();
  for (;;) pause();  // until a signal ends the process
}
