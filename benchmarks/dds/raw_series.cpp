#include "raw_series.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/prctl.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "mtc/bench/peer_process.hpp"
#include "mtc/qos/participant.hpp"

namespace mtc::bench {
namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

constexpr milliseconds kMatchTimeout{10000};
// How long a child may take to start and to tear its participants down.
constexpr std::chrono::seconds kChildOverhead{30};
constexpr std::chrono::seconds kStopGrace{5};
constexpr const char* kArgv0 = "mtc-bench-dds-latency";  // the children's argv[0]

std::atomic<bool> g_peer_stop{false};

extern "C" void on_peer_signal(int) {
  g_peer_stop.store(true);
}

PingPongOptions pingpong_options(const RawSeriesOptions& o, Transport t, int domain,
                                 bool listener) {
  PingPongOptions po;
  po.domain_id = domain;
  po.transport = t;
  po.samples = o.samples;
  po.warmup = o.warmup;
  po.reply_timeout = o.reply_timeout;
  po.listener = listener;
  po.echo_limit = o.peer_quits_after;
  return po;
}

std::vector<std::string> child_args(const RawSeriesOptions& o, const char* role, Transport t,
                                    int domain) {
  return {role,
          "--transport",
          to_string(t),
          "--domain",
          std::to_string(domain),
          "--samples",
          std::to_string(o.samples),
          "--warmup",
          std::to_string(o.warmup),
          "--reply-timeout-ms",
          std::to_string(o.reply_timeout.count()),
          "--peer-quits-after",
          std::to_string(o.peer_quits_after)};
}

// Reads `fd` to its end; false if `deadline` passes first.
bool read_until(int fd, std::string& text, Clock::time_point deadline) {
  pollfd p{fd, POLLIN, 0};
  char buffer[4096];
  for (;;) {
    const auto left = std::chrono::duration_cast<milliseconds>(deadline - Clock::now()).count();
    if (left <= 0) {
      return false;
    }
    const int ready = poll(&p, 1, static_cast<int>(left));
    if (ready < 0 && errno == EINTR) {
      continue;
    }
    if (ready <= 0) {
      return false;
    }
    const ssize_t n = read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) {
      continue;
    }
    if (n <= 0) {
      return n == 0;
    }
    text.append(buffer, static_cast<std::size_t>(n));
  }
}

// Both ends in one process: the ponger on a thread, the pinger here. Raw
// endpoints of one process talk intra-process, as Fast DDS does by default:
// this switches the process-wide setting on, which is why the run does it
// in a child of its own (--both-ends) and never next to the mtc series (the
// runtime switches it off for its participants).
Series run_both_ends_here(const PingPongOptions& po) {
  mtc::qos::set_intraprocess_delivery(true);
  std::atomic<bool> stop{false};
  std::thread ponger([&] {
    try {
      run_ponger(po, stop);
    } catch (const std::exception& e) {
      std::cerr << "ponger: " << e.what() << "\n";
    }
  });
  Series s;
  try {
    s = run_pinger(po, kMatchTimeout);
  } catch (...) {
    stop.store(true);
    ponger.join();
    throw;
  }
  stop.store(true);
  ponger.join();
  return s;
}

// The one-process series in a child. The child ends its series by itself
// (reply timeouts, give-up): past the longest that can take, it is stuck
// and is killed.
Series run_both_ends_in_child(const RawSeriesOptions& o, Transport t, int domain) {
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) {
    throw std::runtime_error("pipe failed");
  }
  const pid_t pid = exec_self(kArgv0, child_args(o, "--both-ends", t, domain), fds[1]);
  close(fds[1]);
  const auto deadline =
      Clock::now() + kMatchTimeout + kChildOverhead + (o.warmup + o.samples) * o.reply_timeout;
  std::string text;
  const bool complete = read_until(fds[0], text, deadline);
  close(fds[0]);
  if (complete) {
    ends_within(pid, kChildOverhead);  // its teardown; stop_child reaps it
  }
  const int status = stop_child(pid, kStopGrace);
  if (!complete || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw std::runtime_error(std::string("one-process raw series ") +
                             (complete ? "failed" : "stuck, killed") + " (status " +
                             std::to_string(status) + ")");
  }
  std::istringstream in(text);
  Series s;
  in >> s.timeouts >> s.cpu_us_per_op;
  for (double v = 0; in >> v;) {
    s.samples_us.push_back(v);
  }
  return s;
}

Series run_against_peer(const RawSeriesOptions& o, Transport t, int domain, bool listener) {
  std::vector<std::string> args = child_args(o, "--peer", t, domain);
  if (listener) {
    args.emplace_back("--listener");
  }
  PingPongOptions po = pingpong_options(o, t, domain, listener);
  po.peer = exec_self(kArgv0, args);
  Series s;
  try {
    s = run_pinger(po, kMatchTimeout);
  } catch (...) {
    stop_child(po.peer, kStopGrace);
    throw;
  }
  stop_child(po.peer, kStopGrace);
  return s;
}

}  // namespace

Series run_raw_series(const RawSeriesOptions& options, Transport t, int processes, int domain,
                      bool listener) {
  std::cerr << "raw fast dds round trip" << (listener ? " (listener echo): " : ": ") << to_string(t)
            << ", " << processes << " process(es), " << options.samples << " samples\n";
  Series s = processes == 1 ? run_both_ends_in_child(options, t, domain)
                            : run_against_peer(options, t, domain, listener);
  s.processes = processes;
  s.name = std::string(listener ? "raw_fastdds_listener_round_trip_" : "raw_fastdds_round_trip_") +
           to_string(t) + "_" + std::to_string(processes) + "proc";
  return s;
}

int run_raw_peer(const RawSeriesOptions& options, Transport t, int domain, bool listener) {
  // The peer must not outlive the benchmark, whatever happens to it.
  prctl(PR_SET_PDEATHSIG, SIGTERM);
  std::signal(SIGTERM, on_peer_signal);
  std::signal(SIGINT, on_peer_signal);
  PingPongOptions po = pingpong_options(options, t, domain, listener);
  // The test hook's peer dies as a crashed one would, without a goodbye.
  po.on_echo_limit = [] { kill(getpid(), SIGKILL); };
  try {
    run_ponger(po, g_peer_stop);
  } catch (const std::exception& e) {
    std::cerr << "ponger peer: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

int print_both_ends(const RawSeriesOptions& options, Transport t, int domain) {
  prctl(PR_SET_PDEATHSIG, SIGTERM);
  const Series s = run_both_ends_here(pingpong_options(options, t, domain, false));
  std::cout << s.timeouts << " " << s.cpu_us_per_op << "\n";
  for (double v : s.samples_us) {
    std::cout << v << "\n";
  }
  return std::cout.good() ? 0 : 1;
}

}  // namespace mtc::bench
