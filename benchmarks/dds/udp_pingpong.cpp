#include "udp_pingpong.hpp"

#include <netinet/in.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <stdexcept>
#include <string>

#include "mtc/bench/proc_cpu.hpp"

namespace mtc::bench {
namespace {

// A UDP socket bound to an ephemeral loopback port; its address in `bound`.
int bound_socket(sockaddr_in& bound, bool close_on_exec) {
  const int fd = ::socket(AF_INET, SOCK_DGRAM | (close_on_exec ? SOCK_CLOEXEC : 0), 0);
  if (fd < 0) {
    throw std::runtime_error("udp: cannot create a socket");
  }
  bound = {};
  bound.sin_family = AF_INET;
  bound.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof bound;
  if (::bind(fd, reinterpret_cast<sockaddr*>(&bound), sizeof bound) != 0 ||
      ::getsockname(fd, reinterpret_cast<sockaddr*>(&bound), &length) != 0) {
    ::close(fd);
    throw std::runtime_error("udp: cannot bind to loopback");
  }
  return fd;
}

pid_t spawn_echo(const char* self_exe, int fd) {
  const std::string fd_text = std::to_string(fd);
  const pid_t pid = fork();
  if (pid < 0) {
    throw std::runtime_error("udp: fork failed");
  }
  if (pid == 0) {
    execl(self_exe, "mtc-bench-dds-latency", "--udp-peer-fd", fd_text.c_str(),
          static_cast<char*>(nullptr));
    _exit(127);
  }
  return pid;
}

}  // namespace

int run_udp_echo(int fd) {
  prctl(PR_SET_PDEATHSIG, SIGTERM);  // never outlive the benchmark
  std::array<char, 256> buffer{};
  for (;;) {
    sockaddr_in from{};
    socklen_t length = sizeof from;
    const auto n = ::recvfrom(fd, buffer.data(), buffer.size(), 0,
                              reinterpret_cast<sockaddr*>(&from), &length);
    if (n <= 0) {
      return n == 0 ? 0 : 1;  // empty datagram: the benchmark is done
    }
    ::sendto(fd, buffer.data(), static_cast<std::size_t>(n), 0, reinterpret_cast<sockaddr*>(&from),
             length);
  }
}

Series run_udp_round_trips(const char* self_exe, int warmup, int samples) {
  sockaddr_in echo_address{};
  const int echo_fd = bound_socket(echo_address, false);  // inherited by the peer
  sockaddr_in own_address{};
  int fd = -1;
  pid_t peer = -1;
  try {
    fd = bound_socket(own_address, true);
    peer = spawn_echo(self_exe, echo_fd);
  } catch (...) {
    ::close(echo_fd);
    if (fd >= 0) ::close(fd);
    throw;
  }
  ::close(echo_fd);
  timeval timeout{2, 0};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);

  Series series;
  series.name = "udp_round_trip_2proc";
  series.layer = "raw_udp";
  series.metric = "round_trip";
  series.transport = "udp_loopback";
  series.processes = 2;
  series.samples_us.reserve(static_cast<std::size_t>(samples));
  // The InteractionSample of the DDS series serialises to about this size.
  std::array<char, 128> datagram{};
  double cpu0 = 0;
  for (int i = 0; i < warmup + samples; ++i) {
    if (i == warmup) {
      cpu0 = cpu_seconds_both(peer);
    }
    const auto t0 = std::chrono::steady_clock::now();
    const bool sent = ::sendto(fd, datagram.data(), datagram.size(), 0,
                               reinterpret_cast<sockaddr*>(&echo_address), sizeof echo_address) > 0;
    const bool answered = sent && ::recv(fd, datagram.data(), datagram.size(), 0) > 0;
    const auto t1 = std::chrono::steady_clock::now();
    if (i < warmup) {
      continue;
    }
    if (answered) {
      series.samples_us.push_back(to_us(t1 - t0));
    } else {
      ++series.timeouts;
    }
  }
  series.cpu_us_per_op = (cpu_seconds_both(peer) - cpu0) * 1e6 / samples;
  ::sendto(fd, datagram.data(), 0, 0, reinterpret_cast<sockaddr*>(&echo_address),
           sizeof echo_address);
  ::kill(peer, SIGTERM);  // in case the empty datagram did not stop it
  ::waitpid(peer, nullptr, 0);
  ::close(fd);
  return series;
}

}  // namespace mtc::bench
