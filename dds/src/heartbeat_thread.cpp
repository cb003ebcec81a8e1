#include "heartbeat_thread.hpp"

#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <exception>

namespace mtc::dds::detail {

namespace {

// The lowest real-time priority: above every normal thread, below anything
// real-time the system already runs. Failing is fine (EPERM without
// privileges): the thread then competes like the others.
bool ask_for_realtime() noexcept {
  sched_param param{};
  param.sched_priority = 1;
  return pthread_setschedparam(pthread_self(), SCHED_FIFO, &param) == 0;
}

long long ms(HeartbeatThread::Clock::duration d) {
  return std::chrono::duration_cast<std::chrono::milliseconds>(d).count();
}

}  // namespace

HeartbeatThread::HeartbeatThread(std::vector<Group> groups, const Executor& executor, Report report)
    : groups_(std::move(groups)),
      next_(groups_.size(), Clock::now()),
      withheld_(groups_.size(), false),
      last_beat_(groups_.size(), Clock::now()),
      longest_gap_(groups_.size()),
      executor_(executor),
      report_(std::move(report)) {
  thread_ = std::thread([this] {
    pthread_setname_np(pthread_self(), "mtc-heartbeat");  // as the executor's
    run();
  });
}

HeartbeatThread::~HeartbeatThread() {
  stop();
}

void HeartbeatThread::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  cv_.notify_all();
  if (thread_.joinable()) thread_.join();
}

bool HeartbeatThread::realtime() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return realtime_;
}

HeartbeatThread::Silence HeartbeatThread::take_silence(std::size_t group, Clock::time_point now) {
  std::lock_guard<std::mutex> lock(mutex_);
  Silence ongoing{now > last_beat_[group] ? now - last_beat_[group] : Clock::duration{},
                  last_beat_[group]};
  const Silence longest =
      longest_gap_[group].length > ongoing.length ? longest_gap_[group] : ongoing;
  longest_gap_[group] = Silence{};
  return longest;
}

void HeartbeatThread::run() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    realtime_ = ask_for_realtime();
  }
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stopping_) {
    const auto due = *std::min_element(next_.begin(), next_.end());
    // A timer, not a synchronisation: the period is the heartbeat contract.
    if (cv_.wait_until(lock, due, [this] { return stopping_; })) break;
    lock.unlock();
    const auto now = Clock::now();
    for (std::size_t i = 0; i < groups_.size(); ++i) {
      if (now >= next_[i]) beat_group(i, now);
    }
    lock.lock();
  }
}

void HeartbeatThread::beat_group(std::size_t index, Clock::time_point now) {
  const auto& g = groups_[index];
  const auto owed = executor_.owed_for(now);
  if (owed >= g.stall_limit) {
    if (!withheld_[index]) {
      withheld_[index] = true;
      report_("heartbeat group " + std::to_string(index) + " withheld: the executor has made " +
                  "no progress for " + std::to_string(ms(owed)) + " ms",
              true);
    }
  } else {
    if (withheld_[index]) {
      withheld_[index] = false;
      report_("heartbeat group " + std::to_string(index) + " resumed: the executor made progress",
              false);
    }
    try {
      g.beat();
      const auto written = Clock::now();
      std::lock_guard<std::mutex> lock(mutex_);
      if (written - last_beat_[index] > longest_gap_[index].length) {
        longest_gap_[index] = Silence{written - last_beat_[index], last_beat_[index]};
      }
      last_beat_[index] = written;
    } catch (const std::exception& e) {
      report_("heartbeat group " + std::to_string(index) + ": " + e.what(), false);
    }
  }
  next_[index] += g.period;
  if (next_[index] <= now) next_[index] = now + g.period;  // late: skip, never burst
}

}  // namespace mtc::dds::detail
