// Internal: the owner of an Equipment's or DomainObserver's state. Everything
// that touches that state runs one task at a time, in posting order: queued
// tasks (DDS events handed off by listeners, application commands) and timers.
// Normally on the executor's own thread, which waits on a condition variable
// until the next task or the next wake-up instant and never sleeps. With
// inline stepping switched on, dispatch() runs a task at once on the calling
// thread (a middleware thread, an application thread) when the state is idle:
// one thread hand-off less per step, the same one-at-a-time guarantee.
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
  // Called by whoever owns the state after every batch of tasks: returns the
  // next instant `on_wake` wants to run (Clock::time_point::max() = none).
  using NextWake = std::function<Clock::time_point()>;
  using OnWake = std::function<void(Clock::time_point now)>;

  Executor() = default;
  ~Executor() { stop(); }
  Executor(const Executor&) = delete;
  Executor& operator=(const Executor&) = delete;

  // Before start(): let dispatch() step inline (default: never).
  void set_inline_steps(bool on) noexcept { inline_steps_ = on; }
  void start(NextWake next_wake, OnWake on_wake);
  // Thread-safe; tasks run in posting order, on the executor thread. Ignored
  // after stop().
  void post(Task task);
  // Like post(), but with inline steps on, a task that finds the state idle
  // (nothing queued, nothing running) runs now on the calling thread.
  void dispatch(Task task);
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
  void enqueue_locked(Task task);  // mutex_ held
  // Waits (executor thread) until the state is free and there is work:
  // tasks, a due wake-up or stop. Returns the wake-up instant it waited for.
  Clock::time_point await_work(std::unique_lock<std::mutex>& lock);
  // An inline step's owner runs what was queued meanwhile before it lets go.
  void drain_while_owner();
  // The owner's last act: the next wake-up, then the state is free again.
  void release();

  NextWake next_wake_;
  OnWake on_wake_;
  bool inline_steps_ = false;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<Task> tasks_;
  bool started_ = false;
  bool stopping_ = false;
  bool busy_ = false;  // a batch, on_wake or an inline step owns the state
  Clock::time_point wake_at_ = Clock::time_point::max();
  // What the executor thread sleeps on, so that an inline step wakes it only
  // when there is something for it (a futile wake-up is a context switch).
  Clock::time_point sleeping_until_ = Clock::time_point::min();  // min: awake
  bool sleeping_on_state_ = false;  // waits for an inline step to finish
  Clock::time_point owed_since_{};  // == Clock::time_point{}: owes nothing
  std::thread thread_;
};

}  // namespace mtc::dds::detail
