// The three stations of the simulated cell, as scripts over a Link:
//   machine  requests MATERIAL_FEED (feeder), MATERIAL_LOAD and
//            MATERIAL_UNLOAD (robot) each cycle; serves OPEN/CLOSE_DOOR and
//            OPEN/CLOSE_CHUCK and publishes DOOR_STATE / CHUCK_STATE;
//   robot    serves MATERIAL_LOAD / MATERIAL_UNLOAD, requesting the door and
//            chuck from the machine while it works;
//   feeder   serves MATERIAL_FEED (advances bar stock to the pick position).
// Failures follow the seeded FaultPlan; every failure ends with both sides
// recovered to READY and the machine retrying the step.
#pragma once

#include <array>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>

#include "cell_plan.hpp"
#include "mtc/dds/middleware.hpp"
#include "mtc/qos/participant.hpp"
#include "mtc/qos/timing.hpp"
#include "ports.hpp"

namespace mtc::cell {

struct CellOptions {
  int domain_id = 110;
  int cycles = 0;          // machine stops after this many; 0 = until stopped
  int duration_s = 0;      // supervisor stops the cell after this; 0 = until stopped
  int freeze_every_s = 0;  // supervisor freezes robot or feeder about this often; 0 = never
  std::uint64_t seed = 1;
  int fail_every = 10;              // one injected failure per this many cycles; 0 = none
  Millis pace{150};                 // duration of one simulated motion
  Millis handshake_timeout{15000};  // a handshake that takes longer is a cell fault
  // DDS heartbeat of every station and how many may be missed before a peer
  // counts as lost (scenario 6): the runtime's default unless --heartbeat-ms /
  // --missed-heartbeats say otherwise. The bridge must use the same lease.
  qos::Timing timing;
  // --transport: the network by default, as every tool; start.sh and the
  // tests choose loopback.
  qos::Transport transport = qos::Transport::Network;
  // --middleware: the DDS implementation of each station (machine, robot,
  // feeder, in StationId order): Fast DDS unless told otherwise; a cell may
  // mix them (issue 9 section 3: the robot on Cyclone, the rest on Fast DDS).
  std::array<dds::Middleware, 3> middleware{dds::Middleware::FastDds, dds::Middleware::FastDds,
                                            dds::Middleware::FastDds};
  // DDS-Security: a scripts/security/make-pki.sh output directory for
  // scripts/security/cell.txt; each station uses <security_dir>/<its uuid>.
  // Empty: unsecured.
  std::string security_dir;
};

inline dds::Middleware middleware_of(StationId id, const CellOptions& options) {
  return options.middleware[static_cast<std::size_t>(id)];
}

// Stop request shared by a station's threads; its sleeps wake on stop().
class Stopper {
 public:
  void stop();
  bool stopped() const;
  // Simulated motion: false when stopped before `d` elapsed.
  bool sleep_for(Millis d);

 private:
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  bool stopped_ = false;
};

// Runs one station until its work is done (the machine after `cycles`) or
// `stop`. Returns the process exit code: 0 when everything recovered.
int run_station(StationId id, Link& link, const CellOptions& options, Stopper& stop);

}  // namespace mtc::cell
