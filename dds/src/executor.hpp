// Internal: the single thread on which an Equipment or DomainObserver runs
// everything that touches its state: queued tasks (DDS events handed off by
// listeners, application commands) and timers. Waits on a condition
// variable until the next task or the next wake-up instant; never sleeps.
#pragma once

#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>

namespace mtc::dds::detail {

class Executor {
 public:
  using Clock = std::chrono::steady_clock;
  using Task = std::function<void()>;
  // Called on the executor thread after every batch of tasks: returns the
  // next instant `on_wake` wants to run (Clock::time_point::max() = none).
  using NextWake = std::function<Clock::time_point()>;
  using OnWake = std::function<void(Clock::time_point now)>;

  Executor() = default;
  ~Executor() { stop(); }
  Executor(const Executor&) = delete;
  Executor& operator=(const Executor&) = delete;

  void start(NextWake next_wake, OnWake on_wake);
  // Thread-safe; tasks run in posting order. Ignored after stop().
  void post(Task task);
  // Runs the remaining queued tasks, then joins. Idempotent.
  void stop();
  bool on_executor_thread() const noexcept {
    return std::this_thread::get_id() == thread_.get_id();
  }
  // How long the executor has owed work without finishing any: zero when it
  // is idle or has just finished a batch; otherwise the time since tasks
  // were posted to it idle, or since it last finished a batch while more
  // were waiting. The heartbeat thread's watchdog: a process whose executor
  // is stuck must stop heartbeating, so that its peers see it as lost.
  Clock::duration owed_for(Clock::time_point now) const;

 private:
  void run();

  NextWake next_wake_;
  OnWake on_wake_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<Task> tasks_;
  bool stopping_ = false;
  bool running_ = false;            // a batch or on_wake is executing
  Clock::time_point owed_since_{};  // == Clock::time_point{}: owes nothing
  std::thread thread_;
};

}  // namespace mtc::dds::detail
