#include "load.hpp"

#include <sys/prctl.h>

#include <cerrno>
#include <iostream>
#include <optional>
#include <system_error>

#include "../dds/latency_stats.hpp"

namespace mtc::bench::scale {
namespace {

using namespace std::chrono_literals;

// A pair returning to READY after its last handshake is waited for, not rejected.
const mtc::dds::RequestOptions kRequest{2000ms};

// Linux lets a sleeping thread's timer fire up to its slack late (50 us by
// default) to batch wake-ups. For the pacing thread that lateness is the load
// generator's, not the runtime's, yet it would be counted in every paced
// latency (measured: issue delay p50 87 -> 37 us over Cyclone, 1 and 100
// pairs; what is left is the idle vCPU's wake-up).
void exact_timers_for_this_thread() {
  if (prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL) != 0) {
    std::cerr << "scale: PR_SET_TIMERSLACK failed ("
              << std::error_code(errno, std::system_category()).message()
              << "); paced issues may be up to 50 us late\n";
  }
}

}  // namespace

Chains::Chains(std::vector<mtc::dds::Requester*> requesters, Clock::time_point end)
    : requesters_(std::move(requesters)), end_(end) {}

void Chains::start() {
  running_ = requesters_.size();
  for (auto* r : requesters_) {
    issue(*r);
  }
}

bool Chains::wait(Clock::duration timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  return stopped_.wait_for(lock, timeout, [&] { return running_ == 0; });
}

void Chains::issue(mtc::dds::Requester& r) {
  r.request(kRequest, [this, &r](const mtc::dds::RequestResult& result) { on_result(r, result); });
}

void Chains::on_result(mtc::dds::Requester& r, const mtc::dds::RequestResult& result) {
  const auto now = Clock::now();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (result.outcome == mtc::dds::Outcome::Completed) {
      tally_.samples_us.push_back(mtc::bench::to_us(result.elapsed));
    } else {
      ++tally_.failed;
    }
    tally_.last_result = now;
    if (now >= end_) {
      if (--running_ == 0) {
        stopped_.notify_all();
      }
      return;
    }
  }
  issue(r);
}

Pacer::Pacer(const std::vector<mtc::dds::Requester*>& requesters, double rate,
             Clock::duration length)
    : rate_(rate), length_(length) {
  pairs_.reserve(requesters.size());
  for (auto* r : requesters) {
    pairs_.push_back(Pair{r, false, {}});
  }
}

Pacer::~Pacer() {
  std::unique_lock<std::mutex> lock(mutex_);
  stop_ = true;
  drop_late();
  lock.unlock();
  if (thread_.joinable()) {
    thread_.join();
  }
  lock.lock();
  changed_.wait_for(lock, 30s, [&] { return outstanding_ == 0; });
}

Clock::time_point Pacer::start() {
  start_ = Clock::now() + 5ms;  // the thread is running by then
  thread_ = std::thread([this] { pace(); });
  return start_;
}

bool Pacer::wait(Clock::duration timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (changed_.wait_for(lock, timeout, [&] { return finished(); })) {
    return true;
  }
  stop_ = true;
  drop_late();
  return changed_.wait_for(lock, 30s, [&] { return finished(); });
}

// The pacing thread: sleeps until each instant, then hands it to its pair.
void Pacer::pace() {
  exact_timers_for_this_thread();
  const auto end = start_ + length_;
  const std::size_t n = pairs_.size();
  for (std::size_t k = 0;; ++k) {
    const auto at = start_ + std::chrono::duration_cast<Clock::duration>(
                                 std::chrono::duration<double>(static_cast<double>(k) / rate_));
    if (at >= end) {
      break;
    }
    std::this_thread::sleep_until(at);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (stop_) {
        break;
      }
      ++scheduled_;
      ++outstanding_;
      Pair& p = pairs_[k % n];
      if (p.busy) {
        p.late.push_back(at);
        continue;
      }
      p.busy = true;
    }
    issue(k % n, at);
  }
  std::lock_guard<std::mutex> lock(mutex_);
  paced_all_ = true;
  changed_.notify_all();
}

void Pacer::issue(std::size_t pair, Clock::time_point scheduled) {
  const auto issued = Clock::now();
  pairs_[pair].requester->request(
      kRequest, [this, pair, scheduled, issued](const mtc::dds::RequestResult& result) {
        on_result(pair, scheduled, issued, result);
      });
}

void Pacer::on_result(std::size_t pair, Clock::time_point scheduled, Clock::time_point issued,
                      const mtc::dds::RequestResult& result) {
  const auto now = Clock::now();
  std::optional<Clock::time_point> next;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (result.outcome == mtc::dds::Outcome::Completed) {
      tally_.samples_us.push_back(mtc::bench::to_us(issued - scheduled + result.elapsed));
      tally_.issue_delay_us.push_back(mtc::bench::to_us(issued - scheduled));
    } else {
      ++tally_.failed;
    }
    tally_.last_result = now;
    --outstanding_;
    Pair& p = pairs_[pair];
    if (p.late.empty()) {
      p.busy = false;
    } else {
      next = p.late.front();
      p.late.pop_front();
    }
    if (outstanding_ == 0) {
      changed_.notify_all();
    }
  }
  if (next) {
    issue(pair, *next);
  }
}

void Pacer::drop_late() {
  for (auto& p : pairs_) {
    not_issued_ += p.late.size();
    tally_.failed += p.late.size();
    outstanding_ -= p.late.size();
    p.late.clear();
  }
  changed_.notify_all();
}

}  // namespace mtc::bench::scale
