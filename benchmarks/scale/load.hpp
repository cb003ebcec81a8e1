// The load generators of mtc-bench-scale, each driving every pair's
// requester until a deadline and tallying the handshakes:
// * Chains (closed loop): each pair re-issues its request from the previous
//   one's result, so every pair always has one handshake in flight.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <mutex>
#include <vector>

#include "mtc/dds/equipment.hpp"

namespace mtc::bench::scale {

using Clock = std::chrono::steady_clock;

// What a load generator measured.
struct Tally {
  std::vector<double> samples_us;  // latency of every completed handshake
  std::size_t failed = 0;          // handshakes with any other outcome
  Clock::time_point last_result;
};

class Chains {
 public:
  Chains(std::vector<mtc::dds::Requester*> requesters, Clock::time_point end);
  Chains(const Chains&) = delete;
  Chains& operator=(const Chains&) = delete;

  void start();
  // Waits until every chain has stopped (bounded: a stuck request still
  // times out through wait_for_ready and the time limits).
  bool wait(Clock::duration timeout);
  // Valid once wait() returned true.
  Tally& tally() { return tally_; }

 private:
  void issue(mtc::dds::Requester& r);
  void on_result(mtc::dds::Requester& r, const mtc::dds::RequestResult& result);

  std::vector<mtc::dds::Requester*> requesters_;
  Clock::time_point end_;
  std::mutex mutex_;
  std::condition_variable stopped_;
  std::size_t running_ = 0;
  Tally tally_;
};

}  // namespace mtc::bench::scale
