// Tools of the abuse tests: many connections from many loopback addresses,
// a well-behaved client that times its requests, the process's RSS.
#pragma once

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "raw_client.hpp"

namespace mtc::bridge::test {

// Thousands of sockets in one process: the soft descriptor limit up to the
// hard one.
inline void raise_descriptor_limit() {
  rlimit limit{};
  if (::getrlimit(RLIMIT_NOFILE, &limit) == 0 && limit.rlim_cur < limit.rlim_max) {
    limit.rlim_cur = limit.rlim_max;
    ::setrlimit(RLIMIT_NOFILE, &limit);
  }
}

// Resident memory of this process, bytes (/proc/self/statm).
inline std::size_t resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  std::size_t pages = 0;
  std::size_t resident = 0;
  statm >> pages >> resident;
  return resident * static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
}

// "127.0.0.<2 + i % spread>": an abusive client among `spread` addresses.
inline std::string abuser_address(std::size_t i, std::size_t spread) {
  return "127.0.0." + std::to_string(2 + i % spread);
}

// What a well-behaved client saw: each request on a new connection.
struct Served {
  int ok = 0;      // 200 answers
  int failed = 0;  // anything else, or nothing in time
  std::vector<double> latency_ms;

  double max_ms() const {
    return latency_ms.empty() ? 0 : *std::max_element(latency_ms.begin(), latency_ms.end());
  }
};

// `count` GETs of `target` from 127.0.0.1, one connection each, one after
// the other; a request counts as served when its 200 arrives in `timeout`.
inline Served serve_well_behaved(std::uint16_t port, int count,
                                 const std::string& target = "/current",
                                 std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
  Served served;
  for (int i = 0; i < count; ++i) {
    const auto start = std::chrono::steady_clock::now();
    try {
      RawClient client(port);
      client.send(get_request(target));
      const auto response = client.read_response(timeout);
      if (response && response->status == 200) {
        ++served.ok;
      } else {
        ++served.failed;
      }
    } catch (const std::exception&) {
      ++served.failed;
    }
    served.latency_ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
            .count());
  }
  return served;
}

}  // namespace mtc::bridge::test
