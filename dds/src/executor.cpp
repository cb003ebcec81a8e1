#include "executor.hpp"

#include <exception>
#include <iostream>

namespace mtc::dds::detail {

void Executor::start(NextWake next_wake, OnWake on_wake) {
  next_wake_ = std::move(next_wake);
  on_wake_ = std::move(on_wake);
  thread_ = std::thread([this] { run(); });
}

void Executor::post(Task task) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stopping_) {
      return;
    }
    if (tasks_.empty() && !running_ && owed_since_ == Clock::time_point{}) {
      owed_since_ = Clock::now();
    }
    tasks_.push_back(std::move(task));
  }
  cv_.notify_one();
}

Executor::Clock::duration Executor::owed_for(Clock::time_point now) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (owed_since_ == Clock::time_point{} || now < owed_since_) {
    return Clock::duration::zero();
  }
  return now - owed_since_;
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

namespace {

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

void Executor::run() {
  std::deque<Task> batch;
  for (;;) {
    const auto wake = next_wake_ ? next_wake_() : Clock::time_point::max();
    {
      std::unique_lock<std::mutex> lock(mutex_);
      auto ready = [this] { return stopping_ || !tasks_.empty(); };
      if (wake == Clock::time_point::max()) {
        cv_.wait(lock, ready);
      } else {
        cv_.wait_until(lock, wake, ready);
      }
      batch.swap(tasks_);
      if (stopping_ && batch.empty()) {
        return;
      }
      running_ = true;
      if (owed_since_ == Clock::time_point{}) {
        owed_since_ = Clock::now();  // a timer's work
      }
    }
    for (auto& task : batch) {
      guarded(task);
    }
    batch.clear();
    if (on_wake_ && Clock::now() >= wake) {
      guarded([this] { on_wake_(Clock::now()); });
    }
    std::lock_guard<std::mutex> lock(mutex_);
    running_ = false;
    // Progress: what is waiting now is owed from now on.
    owed_since_ = tasks_.empty() ? Clock::time_point{} : Clock::now();
  }
}

}  // namespace mtc::dds::detail
