#include "load.hpp"

#include "../dds/latency_stats.hpp"

namespace mtc::bench::scale {
namespace {

using namespace std::chrono_literals;

// A pair returning to READY after its last handshake is waited for, not rejected.
const mtc::dds::RequestOptions kRequest{2000ms};

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

}  // namespace mtc::bench::scale
