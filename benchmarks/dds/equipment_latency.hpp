// The project's own latencies through the Equipment runtime (mtc::dds):
// * transition: one state change published by one Equipment until the
//   counterpart's state machine has applied it;
// * handshake: a request going ACTIVE until both sides are READY again
//   (the 8 steps of Part 5 Table 1).
#pragma once

#include <string>
#include <vector>

#include "latency_stats.hpp"
#include "mtc/bench/stepping.hpp"

namespace mtc::bench {

struct EquipmentBenchOptions {
  int first_domain_id = 104;  // uses up to 4 ids from here
  // Both ends on Cyclone DDS (MTC_CYCLONE builds), in a domain of its own:
  // the benchmarks' range 100-119 is full.
  int cyclone_domain_id = 189;
  int handshakes = 300;
  int round = 1;  // part of the devices' names: a new pair per round
};

// A series' name suffix: "", "_executor", "_inline", "_inline_packed".
std::string series_suffix(Stepping s);
// A run measuring several modes names the devices of a mode's pass by
// round + this, so that no pair meets an earlier pair's names: at most
// kModeRoundOffset rounds then.
inline constexpr int kModeRoundOffset = 250;
inline int mode_round(Stepping s, int round) {
  return round + kModeRoundOffset * static_cast<int>(s);
}

// Both ends of every series from now on (default: Stepping::Default); call
// before the series or the peer run.
void set_stepping(Stepping s);

// The handshake series of the runtime (mtc::dds), one per transport.
std::vector<Series> run_equipment_series(const EquipmentBenchOptions& options);

// The forked responder of the two-process series: runs until SIGTERM.
int run_equipment_peer(int domain, bool udp_only, int round, bool cyclone);

}  // namespace mtc::bench
