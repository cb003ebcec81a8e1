// CPU time and resident memory of a process and the machine's load, for the
// benchmarks' JSON: a latency figure is only comparable with the CPU it cost
// and with how busy the (shared) machine was while it was taken.
#pragma once

#include <dirent.h>
#include <sys/types.h>
#include <unistd.h>

#include <array>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>

namespace mtc::bench {

// CPU seconds the threads of `pid` (0: this process) that are alive now
// have run, from /proc/<pid>/task/*/schedstat (nanoseconds; the clock ticks
// of /proc/<pid>/stat are too coarse for a few hundred round trips).
// Negative when the kernel offers no schedstat.
inline double thread_run_seconds(pid_t pid) {
  const std::string dir =
      (pid == 0 ? std::string("/proc/self") : "/proc/" + std::to_string(pid)) + "/task";
  DIR* tasks = opendir(dir.c_str());
  if (tasks == nullptr) {
    return -1;
  }
  std::uint64_t ns = 0;
  bool any = false;
  // glibc's readdir is safe on a stream no other thread reads; readdir_r is
  // deprecated.
  while (const dirent* entry = readdir(tasks)) {  // NOLINT(concurrency-mt-unsafe)
    if (entry->d_name[0] == '.') {
      continue;
    }
    std::ifstream stat(dir + "/" + entry->d_name + "/schedstat");
    std::uint64_t run_ns = 0;
    if (stat >> run_ns) {
      ns += run_ns;
      any = true;
    }
  }
  closedir(tasks);
  return any ? static_cast<double>(ns) / 1e9 : -1;
}

// User + system CPU seconds of every thread of `pid` (0: this process) so
// far: the threads' run time from schedstat where the kernel has it, else
// /proc/<pid>/stat (clock-tick resolution); negative when unreadable. Only
// differences of two readings over a window where no thread ended mean
// anything.
inline double cpu_seconds(pid_t pid) {
  const double precise = thread_run_seconds(pid);
  if (precise >= 0) {
    return precise;
  }
  const std::string path =
      pid == 0 ? std::string("/proc/self/stat") : "/proc/" + std::to_string(pid) + "/stat";
  std::ifstream file(path);
  std::string line;
  if (!std::getline(file, line)) {
    return -1;
  }
  // The command name (field 2) may hold spaces; the fields after it start
  // behind its closing parenthesis. utime and stime are fields 14 and 15.
  const auto close = line.rfind(')');
  if (close == std::string::npos) {
    return -1;
  }
  std::istringstream rest(line.substr(close + 2));
  std::string field;
  double ticks = 0;
  for (int index = 3; index <= 15 && rest >> field; ++index) {
    if (index >= 14) {
      ticks += std::stod(field);
    }
  }
  return ticks / static_cast<double>(sysconf(_SC_CLK_TCK));
}

// The 1, 5 and 15 minute load averages (zeros when unreadable).
inline std::array<double, 3> load_average() {
  std::array<double, 3> load{};
  std::ifstream file("/proc/loadavg");
  file >> load[0] >> load[1] >> load[2];
  return load;
}

// CPU seconds of this process and (when non-zero) a peer, summed.
inline double cpu_seconds_both(pid_t peer) {
  const double own = cpu_seconds(0);
  return peer == 0 ? own : own + cpu_seconds(peer);
}

// Resident set size of `pid` (0: this process) in KiB, from the VmRSS line
// of /proc/<pid>/status; -1 when unreadable (the process is gone, say).
inline long rss_kb(pid_t pid = 0) {
  std::ifstream status(pid == 0 ? std::string("/proc/self/status")
                                : "/proc/" + std::to_string(pid) + "/status");
  std::string key;
  while (status >> key) {
    if (key == "VmRSS:") {
      long kb = -1;
      status >> kb;
      return kb;
    }
    status.ignore(4096, '\n');
  }
  return -1;
}

}  // namespace mtc::bench
