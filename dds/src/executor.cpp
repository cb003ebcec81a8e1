#include "executor.hpp"

#include <pthread.h>

#include <algorithm>
#include <exception>
#include <iostream>
#include <optional>

#include "mw/write_batch.hpp"

namespace mtc::dds::detail {

namespace {

// How many states this thread owns right now (an inline step, the executor
// thread's batch), of any Executor. A thread that owns one never steps
// another inline: Cyclone DDS delivers to a reader of the same process on the
// writer's thread and lets one thread at a time into a reader's listener, so
// an equipment stepped inside another's write, writing back, would wait for
// the listener its own thread is in (seen: two equipments of one process
// both stuck). Queued instead, the step goes to that equipment's executor.
thread_local int t_states_owned = 0;

struct OwningAState {
  OwningAState() noexcept { ++t_states_owned; }
  ~OwningAState() { --t_states_owned; }
  OwningAState(const OwningAState&) = delete;
  OwningAState& operator=(const OwningAState&) = delete;
};

// A throwing task or timer must not take the executor down with it.
template <typename Fn>
void guarded(Fn&& fn) {
  try {
    fn();
  } catch (const std::exception& e) {
    std::cerr << "mtc::dds executor: task threw: " << e.what() << '\n';
  } catch (...) {
    std::cerr << "mtc::dds executor: task threw an unknown exception\n";
  }
}

}  // namespace

void Executor::start(NextWake next_wake, OnWake on_wake) {
  next_wake_ = std::move(next_wake);
  on_wake_ = std::move(on_wake);
  // The first wake-up instant is read here, while nothing else can own the
  // state (no executor thread yet, no inline step before started_): had the
  // new thread read it, a dispatch right after start() would find the state
  // busy for no reason and queue a step it could have run (seen under TSan).
  const auto first_wake = next_wake_ ? next_wake_() : Clock::time_point::max();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    wake_at_ = first_wake;
    started_ = true;
  }
  thread_ = std::thread([this] {
    // Named, so that top -H, perf and gdb tell it from the middleware's.
    pthread_setname_np(pthread_self(), "mtc-executor");
    run();
  });
}

void Executor::post(Task task) {
  bool notify = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stopping_) {
      return;
    }
    enqueue_locked(std::move(task));
    notify = !busy_;
  }
  // While the state is owned, the owner runs what was queued before it lets
  // go (the executor thread in its loop, an inline step in
  // drain_while_owner) and release() hands on the rest: waking the executor
  // thread now would be futile, twice over, as it would find the state busy
  // and wait again for release() to wake it.
  if (notify) cv_.notify_one();
}

void Executor::post_report(Task task) {
  bool notify = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (reports_.empty() && !reporting_) {
      reports_owed_since_ = Clock::now();
    }
    reports_.push_back(std::move(task));
    // Only a sleeping executor thread needs waking; an awake one looks at
    // the reports before it sleeps again. Nor while a step owns the state:
    // release() wakes it after the step, so that the wake-up (a futex call,
    // a cross-core interrupt) never delays the step's own writes.
    notify = !busy_ && sleeping_until_ != Clock::time_point::min();
  }
  if (notify) cv_.notify_one();
}

void Executor::run_reports(std::deque<Task>& batch) {
  // What the reports write leaves together (mw::WriteBatch), but a burst
  // is closed before the next report once it is burst_age_ old: many reports
  // in a row do not hold the first one's writes back for long. A report that
  // itself takes long (callbacks must be short) delays the burst by as much.
  std::optional<mw::WriteBatch> burst;
  auto opened = Clock::time_point{};
  for (auto& report : batch) {
    const auto now = Clock::now();
    if (!burst || now - opened >= burst_age_) {
      burst.reset();
      burst.emplace();
      opened = now;
    }
    guarded(report);
  }
  burst.reset();
  batch.clear();
  std::lock_guard<std::mutex> lock(mutex_);
  reporting_ = false;
  reports_owed_since_ = reports_.empty() ? Clock::time_point{} : Clock::now();
}

void Executor::enqueue_locked(Task task) {
  if (tasks_.empty() && !busy_ && owed_since_ == Clock::time_point{}) {
    owed_since_ = Clock::now();
  }
  tasks_.push_back(std::move(task));
}

bool Executor::claim_for_inline_step() {
  if (!inline_steps_) return false;
  std::lock_guard<std::mutex> lock(mutex_);
  // The executor thread must exist to pick up what this step leaves behind;
  // a stopping executor takes nothing (post() drops it).
  if (stopping_ || !started_ || busy_ || (t_states_owned != 0 && steps_write_)) return false;
  busy_ = true;
  if (owed_since_ == Clock::time_point{}) owed_since_ = Clock::now();
  // Queued tasks go first (posting order), here: left to the executor
  // thread, they and every step behind them would wait for whatever it runs
  // meanwhile, a report such as an application callback that blocks (seen
  // under TSan: a status queued while the robot's on_request was held kept
  // its ACTIVE back until the heartbeat was withheld).
  owner_batch_.swap(tasks_);
  return true;
}

void Executor::run_claimed_step(const Task& step) {
  {
    const mw::WriteBatch burst;
    std::optional<OwningAState> owning;
    if (steps_write_) owning.emplace();
    for (auto& earlier : owner_batch_) {
      guarded(earlier);
    }
    owner_batch_.clear();
    guarded(step);
    drain_while_owner();
  }
  release();
}

void Executor::drain_while_owner() {
  // What the step queued (a callback's command, say complete() from
  // on_request) runs here too, while this thread owns the state anyway:
  // handing it to the executor thread would cost the hand-off the inline
  // step saved. One batch only: a middleware thread must not be kept from
  // its own work by a stream of tasks; what comes after goes to the executor.
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stopping_) return;
    owner_batch_.swap(tasks_);
  }
  for (auto& task : owner_batch_) {
    guarded(task);
  }
  owner_batch_.clear();
}

Executor::Clock::duration Executor::owed_for(Clock::time_point now) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto owed = Clock::duration::zero();
  for (const auto since : {owed_since_, reports_owed_since_}) {
    if (since != Clock::time_point{} && now > since) owed = std::max(owed, now - since);
  }
  return owed;
}

void Executor::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  cv_.notify_one();
  if (thread_.joinable() && !on_executor_thread()) {
    thread_.join();
  }
}

void Executor::release() {
  // Still the owner: nothing else reads the state while next_wake_ does.
  const auto wake = next_wake_ ? next_wake_() : Clock::time_point::max();
  bool wake_executor = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    wake_at_ = wake;
    busy_ = false;
    // Progress: what is waiting now is owed from now on.
    owed_since_ = tasks_.empty() ? Clock::time_point{} : Clock::now();
    // After an inline step, the executor thread has work only if it waits
    // for the state, if tasks or reports came meanwhile, or if the step
    // moved the next instant before the one it sleeps on.
    wake_executor = sleeping_on_state_ || !tasks_.empty() || !reports_.empty() || stopping_ ||
                    (sleeping_until_ != Clock::time_point::min() && wake < sleeping_until_);
  }
  if (wake_executor) cv_.notify_one();
}

Executor::Clock::time_point Executor::await_work(std::unique_lock<std::mutex>& lock) {
  for (;;) {
    if (!reports_.empty()) {
      return wake_at_;  // reports need no state: they run while a step owns it
    }
    if (!busy_) {
      if (stopping_ || !tasks_.empty()) {
        return wake_at_;
      }
      if (wake_at_ != Clock::time_point::max() && Clock::now() >= wake_at_) {
        return wake_at_;
      }
    }
    sleeping_on_state_ = busy_;
    sleeping_until_ = busy_ ? Clock::time_point::max() : wake_at_;
    if (busy_ || wake_at_ == Clock::time_point::max()) {
      cv_.wait(lock);
    } else {
      cv_.wait_until(lock, wake_at_);
    }
    sleeping_on_state_ = false;
    sleeping_until_ = Clock::time_point::min();
  }
}

void Executor::run() {
  std::deque<Task> batch;
  for (;;) {
    Clock::time_point wake;
    bool reports = false;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake = await_work(lock);
      reports = reporting_ = !reports_.empty();
      if (reports) {
        batch.swap(reports_);
      } else {
        batch.swap(tasks_);
        if (stopping_ && batch.empty()) {
          return;
        }
        busy_ = true;
        if (owed_since_ == Clock::time_point{}) {
          owed_since_ = Clock::now();  // a timer's work
        }
      }
    }
    if (reports) {
      run_reports(batch);
      continue;
    }
    {
      const mw::WriteBatch burst;
      std::optional<OwningAState> owning;
      if (steps_write_) owning.emplace();
      for (auto& task : batch) {
        guarded(task);
      }
      batch.clear();
      if (on_wake_ && Clock::now() >= wake) {
        guarded([this] { on_wake_(Clock::now()); });
      }
    }
    release();
  }
}

}  // namespace mtc::dds::detail
