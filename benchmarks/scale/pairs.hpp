// Both ends of mtc-bench-scale's interface pairs: the devices' names, their
// equipment options and interfaces, and the responder process (this binary
// run again with --peer) that completes every request at once.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <string>
#include <vector>

#include "mtc/bench/stepping.hpp"
#include "mtc/dds/equipment.hpp"

namespace mtc::bench::scale {

// "scale-<role>-<index>": requester devices are "req", responders "resp".
std::string device(const char* role, int index);
// "if<index>": interface k of a requester pairs with interface k of its responder.
std::string interface_id(int index);

// On `domain`, loopback only, recovering from every FAIL (a false alarm must
// not stall a pair); steps as set_stepping() said, on the DDS
// implementation set_middleware() chose.
mtc::dds::EquipmentOptions equipment_options(const std::string& uuid, int domain);
// How both processes step (mtc/bench/stepping.hpp; default: the runtime's
// default); the peer is started with the same.
void set_stepping(Stepping stepping);
Stepping stepping();
// Both processes' middleware (default Fast DDS over shared memory and UDP;
// Cyclone DDS 0.10 in Debian has no shared memory, so UDP on loopback); the
// peer is started with the same.
void set_middleware(mtc::dds::Middleware m);
// "shm_udp" or "udp_loopback": what the pairs' samples travel over.
const char* transport_name();
// Quiet about the filtered false-loss notes, loud about anything else.
mtc::dds::EquipmentCallbacks quiet_callbacks();
// `interfaces` material-handler interfaces, each paired with the same id on `peer_device`.
void add_pairing(mtc::dds::Equipment& e, const std::string& peer_device, int interfaces);

// The responder process: `devices` responder devices with `interfaces`
// interfaces each, completing every request; runs until SIGTERM (or until
// its parent dies).
int run_peer(int devices, int interfaces, int domain);
// Starts run_peer in a child (fork + exec of this binary with --peer).
pid_t spawn_peer(int devices, int interfaces, int domain);
// SIGTERM, SIGKILL if it has not ended 10 s on, and reaped.
void stop_peer(pid_t pid);

// True once every requester sees its responder READY, within `timeout`.
bool wait_all_ready(const std::vector<mtc::dds::Requester*>& requesters,
                    std::chrono::steady_clock::duration timeout);

}  // namespace mtc::bench::scale
