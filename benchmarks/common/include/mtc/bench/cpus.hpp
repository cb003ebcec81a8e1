// Where a benchmark's processes run: `--cpus LIST` confines the benchmark,
// and every process it starts afterwards (they inherit the mask), to some
// CPUs. On a VM guest whose idle vCPUs halt, a thread woken on the other
// vCPU started 15-46 us (p50) after the notify, one on the same vCPU 2-6 us
// (mtc-bench-wakeup; docs/benchmarks.md, "Hand-offs between vCPUs"), and a
// handshake is a chain of such hand-offs: placement is then a figure's
// first condition, and the JSON says which one it was taken under.
#pragma once

#include <sched.h>

#include <cctype>
#include <optional>
#include <string>

namespace mtc::bench {

// "all" (leave the mask as it is) or a comma list of CPU numbers and
// ranges ("0", "0,1", "0-1"). Returns an error message, or nothing when
// `mask` holds the CPUs, each of which this process may run on.
inline std::optional<std::string> parse_cpus(const std::string& text, cpu_set_t& mask) {
  CPU_ZERO(&mask);
  cpu_set_t allowed;
  if (sched_getaffinity(0, sizeof allowed, &allowed) != 0) {
    return std::string("cannot read this process's CPU mask");
  }
  std::size_t i = 0;
  auto number = [&](int& out) {
    if (i >= text.size() || std::isdigit(static_cast<unsigned char>(text[i])) == 0) return false;
    out = 0;
    while (i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])) != 0) {
      out = out * 10 + (text[i++] - '0');
      if (out >= CPU_SETSIZE) return false;
    }
    return true;
  };
  while (i < text.size()) {
    int first = 0;
    int last = 0;
    if (!number(first)) return "--cpus: expected a CPU number at '" + text.substr(i) + "'";
    last = first;
    if (i < text.size() && text[i] == '-') {
      ++i;
      if (!number(last) || last < first) return "--cpus: bad range in '" + text + "'";
    }
    for (int cpu = first; cpu <= last; ++cpu) {
      if (CPU_ISSET(cpu, &allowed) == 0) {
        return "--cpus: CPU " + std::to_string(cpu) + " is not available to this process";
      }
      CPU_SET(cpu, &mask);
    }
    if (i < text.size() && text[i++] != ',') return "--cpus: expected ',' in '" + text + "'";
  }
  if (CPU_COUNT(&mask) == 0) return std::string("--cpus: no CPU given");
  return std::nullopt;
}

// Applies `--cpus` to this process before it starts any thread or child.
// Returns an error message, or nothing (also for "all").
inline std::optional<std::string> confine_to_cpus(const std::string& text) {
  if (text == "all") return std::nullopt;
  cpu_set_t mask;
  if (auto error = parse_cpus(text, mask)) return error;
  if (sched_setaffinity(0, sizeof mask, &mask) != 0) {
    return "--cpus: cannot confine this process to " + text;
  }
  return std::nullopt;
}

}  // namespace mtc::bench
