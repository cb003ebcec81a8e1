// Baseline: plain Fast DDS ping-pong with the QoS the project uses for
// interaction items (RELIABLE, KEEP_LAST 1, TRANSIENT_LOCAL, keyed
// InteractionSample), so the project's own latencies can be read against
// what the middleware alone costs on the same machine in the same run.
//
// Fast DDS entities are used directly here on purpose: this series measures
// the middleware without any mtc layer in between; only the QoS comes from
// mtc::qos, so both sides of the comparison use the same preset.
#pragma once

#include <sys/types.h>

#include <atomic>
#include <chrono>
#include <functional>
#include <string>

#include "latency_stats.hpp"

namespace mtc::bench {

enum class Transport { UdpLoopback, ShmUdp };

std::string to_string(Transport t);
bool parse_transport(const std::string& text, Transport& out);

struct PingPongOptions {
  int domain_id = 100;
  Transport transport = Transport::UdpLoopback;
  int warmup = 200;
  int samples = 2000;
  // A round trip with no echo within this counts as a timeout; after
  // `give_up_after` in a row (warm-up included) the ponger is taken for gone
  // and the series ends, its round trips not run counted as timeouts too: a
  // dead peer must not hold the run for a reply timeout per round trip.
  std::chrono::milliseconds reply_timeout{1000};
  int give_up_after = 5;
  // true: every echo, and the pinger's next ping, is written from the
  // reader's listener on Fast DDS's receive thread (the fastest ping-pong
  // the library offers); false: an application thread waits on a WaitSet.
  bool listener = false;
  // The ponger's process, when it is another one: its CPU time is counted.
  pid_t peer = 0;
  // Test hook (the benchmark's --peer-quits-after): the ponger stops after
  // this many echoes (0: never) and calls on_echo_limit, or, without one,
  // returns: a peer that dies or goes silent in the middle of a series.
  int echo_limit = 0;
  std::function<void()> on_echo_limit;
};

// Echoes every ping back on the pong topic until `stop` becomes true (or
// `echo_limit` echoes).
// Runs in a thread (one-process mode) or as a forked peer process.
void run_ponger(const PingPongOptions& options, const std::atomic<bool>& stop);

// Sends pings one at a time and times each until its echo arrives (at most
// reply_timeout; ends after give_up_after timeouts in a row). Waits up to
// `match_timeout` for the ponger to be discovered; throws if it is not.
Series run_pinger(const PingPongOptions& options, std::chrono::milliseconds match_timeout);

}  // namespace mtc::bench
