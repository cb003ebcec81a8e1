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
  // How long the writes of a run of reports may wait for the rest of the
  // run (see run_reports): at 100 interfaces a run of results and their new
  // requests left as one message per writer, a fifth fewer system calls.
  static constexpr std::chrono::microseconds kBurstAge{50};

  Executor() = default;
  ~Executor() { stop(); }
  Executor(const Executor&) = delete;
  Executor& operator=(const Executor&) = delete;

  // Before start(): let dispatch() step inline (default: never).
  // `steps_write`: the state's steps write DDS samples (an Equipment's do,
  // an observer's do not); such a step is never taken inline by a thread
  // that owns a state already (executor.cpp says why).
  void set_inline_steps(bool on, bool steps_write = true) noexcept {
    inline_steps_ = on;
    steps_write_ = steps_write;
  }
  // Before start(): how old a burst of reports' writes may grow (default
  // kBurstAge; zero: each report's writes leave when it returns).
  void set_burst_age(Clock::duration age) noexcept { burst_age_ = age; }
  void start(NextWake next_wake, OnWake on_wake);
  // Thread-safe; tasks run in posting order, on the executor thread, or,
  // with inline steps on, on the thread of a later dispatch() that finds the
  // state idle. Ignored after stop().
  void post(Task task);
  // Like post(), but with inline steps on, a task that finds the state idle
  // (no task running) runs now on the calling thread, after those queued.
  // A step taken here is called in place, never wrapped in a Task: a Task
  // that holds a DDS event is a heap allocation for every value received.
  template <typename Step>
  void dispatch(Step&& step) {
    if (!claim_for_inline_step()) {
      post(Task(std::forward<Step>(step)));
      return;
    }
    run_claimed_step([&step] { step(); });
  }
  // A report (an application callback, a command's result): runs on the
  // executor thread, reports in posting order, but without owning the state,
  // so that a value stepped inline meanwhile never waits for a callback.
  // stop() runs those queued before the executor thread ends.
  void post_report(Task task);
  // Runs the remaining queued tasks, then joins. Idempotent.
  void stop();
  bool on_executor_thread() const noexcept {
    return std::this_thread::get_id() == thread_.get_id();
  }
  // How long the executor has owed work without finishing any: zero when it
  // is idle or has just finished a batch; otherwise the time since tasks
  // were posted to it idle, or since it last finished a batch while more
  // were waiting; the same for reports, the longer of the two. The heartbeat
  // thread's watchdog: a process whose executor is stuck (a callback that
  // blocks included) must stop heartbeating, so that its peers see it lost.
  Clock::duration owed_for(Clock::time_point now) const;

 private:
  void run();
  void enqueue_locked(Task task);  // mutex_ held
  // Inline steps on, the state idle and this thread free to step it: takes
  // the state (and what is queued, to run first) and returns true.
  bool claim_for_inline_step();
  // The claimed state's step: what was queued, the step, what it queued, release().
  void run_claimed_step(const Task& step);
  // Waits (executor thread) until the state is free and there is work:
  // tasks, a due wake-up or stop. Returns the wake-up instant it waited for.
  Clock::time_point await_work(std::unique_lock<std::mutex>& lock);
  // An inline step's owner runs what was queued meanwhile before it lets go.
  void drain_while_owner();
  // Executor thread: runs the queued reports (mutex_ not held).
  void run_reports(std::deque<Task>& batch);
  // The owner's last act: the next wake-up, then the state is free again.
  void release();

  NextWake next_wake_;
  OnWake on_wake_;
  Clock::duration burst_age_ = kBurstAge;
  bool inline_steps_ = false;
  bool steps_write_ = true;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<Task> tasks_;
  // The tasks an inline step's owner runs (queued before the step, queued by
  // it). Touched only by the thread that set busy_: kept, not made per
  // step, because a std::deque allocates as it is constructed.
  std::deque<Task> owner_batch_;
  bool started_ = false;
  bool stopping_ = false;
  bool busy_ = false;  // a batch, on_wake or an inline step owns the state
  Clock::time_point wake_at_ = Clock::time_point::max();
  // What the executor thread sleeps on, so that an inline step wakes it only
  // when there is something for it (a futile wake-up is a context switch).
  Clock::time_point sleeping_until_ = Clock::time_point::min();  // min: awake
  bool sleeping_on_state_ = false;  // waits for an inline step to finish
  Clock::time_point owed_since_{};  // == Clock::time_point{}: owes nothing
  std::deque<Task> reports_;
  bool reporting_ = false;                  // the executor thread runs reports
  Clock::time_point reports_owed_since_{};  // as owed_since_, for reports
  std::thread thread_;
};

}  // namespace mtc::dds::detail
