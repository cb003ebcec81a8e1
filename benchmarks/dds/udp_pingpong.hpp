// The physical limit of the machine: a UDP datagram echoed between two
// processes over loopback with blocking sockets, no middleware at all. Every
// DDS round trip of the same run is read against it.
#pragma once

#include "latency_stats.hpp"

namespace mtc::bench {

// Forks and execs `self_exe` with --udp-peer-fd N (the echoing process),
// times `samples` round trips after `warmup`, stops the peer. Throws when
// the sockets cannot be set up.
Series run_udp_round_trips(const char* self_exe, int warmup, int samples);

// The echoing process: answers every datagram on `fd` until it receives an
// empty one (or the benchmark dies). Returns the exit code.
int run_udp_echo(int fd);

}  // namespace mtc::bench
