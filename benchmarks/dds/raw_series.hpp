// The raw Fast DDS round-trip series of mtc-bench-dds-latency as the run
// sees them: each in a process of its own (one-process series) or against a
// forked ponger (two-process series), every one bounded in time: a ponger
// that dies or hangs ends the series with its round trips counted as
// timeouts, and every child is reaped (killed if need be).
#pragma once

#include <chrono>

#include "latency_stats.hpp"
#include "raw_pingpong.hpp"

namespace mtc::bench {

// What every raw series of a run shares.
struct RawSeriesOptions {
  int samples = 2000;
  int warmup = 200;
  std::chrono::milliseconds reply_timeout{1000};
  // Test hook (--peer-quits-after): the ponger stops after this many echoes,
  // a forked one with SIGKILL on itself (0: never).
  int peer_quits_after = 0;
};

// One series; `processes` 1 runs both ends in a child process, 2 the pinger
// here against a forked ponger (`listener`: both echo from the listener).
Series run_raw_series(const RawSeriesOptions& options, Transport t, int processes, int domain,
                      bool listener);

// The forked ponger (--peer): echoes until SIGTERM or its parent dies.
int run_raw_peer(const RawSeriesOptions& options, Transport t, int domain, bool listener);

// The one-process series' child (--both-ends): runs it and prints it on
// stdout, "timeouts cpu" then one sample (us) per line.
int print_both_ends(const RawSeriesOptions& options, Transport t, int domain);

}  // namespace mtc::bench
