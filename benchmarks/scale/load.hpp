// The load generators of mtc-bench-scale, each driving every pair's
// requester until a deadline and tallying the handshakes:
// * Chains (closed loop): each pair re-issues its request from the previous
//   one's result, so every pair always has one handshake in flight: the
//   offered load is whatever the runtime can do.
// * Pacer (open loop): a fixed offered rate, whatever the runtime does with
//   it; what a load below capacity costs in latency.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <thread>
#include <vector>

#include "mtc/dds/equipment.hpp"

namespace mtc::bench::scale {

using Clock = std::chrono::steady_clock;

// What a load generator measured.
struct Tally {
  std::vector<double> samples_us;  // latency of every completed handshake
  // Pacer only: scheduled instant to request(), for the same handshakes (the
  // load generator's own lateness plus any wait for the pair's last handshake).
  std::vector<double> issue_delay_us;
  std::size_t failed = 0;  // handshakes with any other outcome
  Clock::time_point last_result;
};

class Chains {
 public:
  Chains(std::vector<mtc::dds::Requester*> requesters, Clock::time_point end);

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

// `rate` handshakes/s offered over all pairs: the k-th instant of the
// schedule, start + k / rate, belongs to pair k mod pairs, so each pair asks
// at rate / pairs per second with the pairs' phases staggered evenly. One
// thread issues each request at its instant; a pair still busy then asks
// again as soon as its result arrives. A handshake's latency runs from its
// scheduled instant to its outcome (the issue's delay plus request() to
// outcome): a late issue counts against the runtime, as a closed loop that
// waits before asking would hide it (coordinated omission).
class Pacer {
 public:
  // The schedule runs from start() (plus a few milliseconds for the thread
  // to start) for `length`.
  Pacer(const std::vector<mtc::dds::Requester*>& requesters, double rate, Clock::duration length);
  Pacer(const Pacer&) = delete;
  Pacer& operator=(const Pacer&) = delete;
  // Stops the schedule and waits (bounded) for the requests in flight: their
  // callbacks hold this object.
  ~Pacer();

  // Starts the pacing thread; returns the schedule's first instant.
  Clock::time_point start();
  // Waits up to `timeout` for the schedule to end and every request
  // scheduled in it to have its result. On a timeout the requests not yet
  // issued are dropped (counted in failed and in not_issued()) and only
  // those in flight are waited for, up to 30 s; false if even they are not done.
  bool wait(Clock::duration timeout);
  // Valid once wait() returned.
  Tally& tally() { return tally_; }
  std::size_t scheduled() const { return scheduled_; }
  std::size_t not_issued() const { return not_issued_; }

 private:
  struct Pair {
    mtc::dds::Requester* requester = nullptr;
    bool busy = false;                   // a request of this pair is in flight
    std::deque<Clock::time_point> late;  // instants that came while it was busy
  };

  void pace();
  void issue(std::size_t pair, Clock::time_point scheduled);
  void on_result(std::size_t pair, Clock::time_point scheduled, Clock::time_point issued,
                 const mtc::dds::RequestResult& result);
  void drop_late();  // with mutex_ held
  bool finished() const { return paced_all_ && outstanding_ == 0; }

  std::vector<Pair> pairs_;
  double rate_;
  Clock::duration length_;
  Clock::time_point start_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::size_t scheduled_ = 0;    // instants the pacing thread has reached
  std::size_t outstanding_ = 0;  // scheduled, no result yet
  std::size_t not_issued_ = 0;
  bool paced_all_ = false;
  bool stop_ = false;
  Tally tally_;
  std::thread thread_;
};

}  // namespace mtc::bench::scale
