// The life of a benchmark's forked peer process, from both sides: the
// benchmark starts it (this executable again), the peer blocks its stop
// signals and waits for one; the benchmark stops and reaps it without ever
// waiting forever for a peer that will not go.
#pragma once

#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <stdexcept>
#include <string>
#include <vector>

namespace mtc::bench {

// Runs this executable again as `argv0` with `args` (fork, then exec at
// once: a forked copy of a process that already runs Fast DDS threads is
// unsafe, an exec'd one starts clean); its stdout goes to `stdout_fd` when
// that is not -1. Throws when fork fails; the child exits 127 when exec does.
inline pid_t exec_self(const char* argv0, const std::vector<std::string>& args,
                       int stdout_fd = -1) {
  std::vector<char*> argv;
  argv.reserve(args.size() + 2);
  argv.push_back(const_cast<char*>(argv0));
  for (const auto& a : args) {
    argv.push_back(const_cast<char*>(a.c_str()));
  }
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid < 0) {
    throw std::runtime_error("fork failed");
  }
  if (pid == 0) {
    if (stdout_fd >= 0 && dup2(stdout_fd, STDOUT_FILENO) < 0) {
      _exit(127);
    }
    execv("/proc/self/exe", argv.data());
    _exit(127);
  }
  return pid;
}

// In the peer, before any thread starts (threads inherit the mask): the
// peer gets SIGTERM when the benchmark dies, and SIGTERM and SIGINT are
// blocked so that wait_for_stop_signal() takes them instead of the default
// action killing the process in the middle of DDS teardown. Returns the set.
inline sigset_t block_stop_signals() {
  if (prctl(PR_SET_PDEATHSIG, SIGTERM) != 0) {
    throw std::runtime_error("prctl(PR_SET_PDEATHSIG) failed");
  }
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGINT);
  if (pthread_sigmask(SIG_BLOCK, &set, nullptr) != 0) {
    throw std::runtime_error("pthread_sigmask failed");
  }
  return set;
}

// Blocks until one of `set` (from block_stop_signals) arrives; returns it.
inline int wait_for_stop_signal(const sigset_t& set) {
  int sig = 0;
  if (sigwait(&set, &sig) != 0) {
    throw std::runtime_error("sigwait failed");
  }
  return sig;
}

// True when the child `pid` has ended (not yet reaped) within `timeout`:
// its pidfd becomes readable then, an event rather than a polling loop.
inline bool ends_within(pid_t pid, std::chrono::milliseconds timeout) {
  const int fd = static_cast<int>(syscall(SYS_pidfd_open, pid, 0));
  if (fd < 0) {
    return false;  // no pidfd (old kernel): the caller's SIGKILL decides
  }
  pollfd p{fd, POLLIN, 0};
  int ready = 0;
  do {
    ready = poll(&p, 1, static_cast<int>(timeout.count()));
  } while (ready < 0 && errno == EINTR);
  close(fd);
  return ready > 0;
}

// Asks the child `pid` to stop (SIGTERM), kills it (SIGKILL) if it has not
// ended within `grace`, and reaps it. A peer stuck in DDS teardown would
// otherwise keep the benchmark in waitpid() for good. Returns the wait
// status, -1 if the child could not be reaped.
inline int stop_child(pid_t pid, std::chrono::milliseconds grace) {
  if (pid <= 0) {
    return -1;
  }
  kill(pid, SIGTERM);  // a child already gone (a zombie) ignores it
  if (!ends_within(pid, grace)) {
    kill(pid, SIGKILL);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) {
      return -1;
    }
  }
  return status;
}

}  // namespace mtc::bench
