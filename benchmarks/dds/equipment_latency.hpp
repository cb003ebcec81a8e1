// The project's own latencies through the Equipment runtime (mtc::dds):
// * transition: one state change published by one Equipment until the
//   counterpart's state machine has applied it;
// * handshake: a request going ACTIVE until both sides are READY again
//   (the 8 steps of Part 5 Table 1).
#pragma once

#include <vector>

#include "latency_stats.hpp"

namespace mtc::bench {

struct EquipmentBenchOptions {
  int first_domain_id = 104;  // uses up to 4 ids from here
  // Both ends on Cyclone DDS (MTC_CYCLONE builds), in a domain of its own:
  // the benchmarks' range 100-119 is full.
  int cyclone_domain_id = 189;
  int handshakes = 300;
  int round = 1;  // part of the devices' names: a new pair per round
};

// The inline pass of a run that measures both step modes names its devices
// by round + this, so that no pair meets an earlier pair's names.
inline constexpr int kInlineRoundOffset = 500;

// Both ends of every series with EquipmentOptions::inline_steps (default
// off: the runtime's default); call before the series or the peer run. The
// series of an inline run carry "_inline" after their names.
void set_inline_steps(bool on);

// The handshake series of the runtime (mtc::dds), one per transport.
std::vector<Series> run_equipment_series(const EquipmentBenchOptions& options);

// The forked responder of the two-process series: runs until SIGTERM.
int run_equipment_peer(int domain, bool udp_only, int round, bool cyclone);

}  // namespace mtc::bench
