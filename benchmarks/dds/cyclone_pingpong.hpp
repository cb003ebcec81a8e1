// Cyclone DDS's round trip on the same machine in the same run, from its own
// tool: `ddsperf pong` and `ddsperf ping` (Debian cyclonedds-tools), two
// processes, listener mode, reliable, KEEP_LAST 1, keyed topic, restricted
// to the loopback interface. A yardstick for what a DDS implementation can
// do here, not a second backend of this project.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace mtc::bench {

// One line of ddsperf's per-second report, turned into round trips: ddsperf
// prints half the round trip (its "latency"), these are doubled.
struct CycloneSecond {
  double mean = 0, min = 0, p50 = 0, p90 = 0, p99 = 0, max = 0;
  long count = 0;
};

struct CycloneResult {
  std::vector<CycloneSecond> seconds;
  double cpu_us_per_op = -1;  // both ddsperf processes, start-up included
  std::string command;
};

// Nothing when ddsperf is not installed or printed no round trip; the
// reason goes to `why`.
std::optional<CycloneResult> run_cyclone_round_trips(int domain, int seconds, std::string& why);

// {"available":true,"p50":...,...} or {"available":false,"why":...}: the
// summary uses the median over the seconds of each per-second percentile
// (ddsperf reports no raw samples) and the worst second's p99 and max.
std::string cyclone_json(const std::optional<CycloneResult>& result, const std::string& why);

// The median of the per-second figure `field` (p50 or p99), 0 when empty.
double cyclone_median(const CycloneResult& result, double CycloneSecond::*field);

}  // namespace mtc::bench
