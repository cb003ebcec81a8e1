// The executor's guarantees with and without inline steps: one task at a
// time, in dispatch order; an inline step runs on the calling thread only
// when the state is idle; what it leaves behind (queued tasks, a moved
// wake-up instant) is picked up by the executor thread; stop() waits for a
// step in progress. Synchronised by promises and latches, never by sleeps.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <mutex>
#include <thread>
#include <vector>

#include "executor.hpp"

namespace {

using mtc::dds::detail::Executor;
using Clock = Executor::Clock;
using namespace std::chrono_literals;

constexpr auto kGenerous = 10s;  // a bound that only a hang exceeds

void start_without_timers(Executor& ex) {
  ex.start([] { return Clock::time_point::max(); }, [](Clock::time_point) {});
}

TEST(Executor, WithoutInlineStepsEveryTaskRunsOnTheExecutorThread) {
  std::promise<bool> on_executor;
  Executor ex;  // after what its tasks touch: destroyed (and joined) first
  start_without_timers(ex);
  ex.dispatch([&] { on_executor.set_value(ex.on_executor_thread()); });
  auto f = on_executor.get_future();
  ASSERT_EQ(f.wait_for(kGenerous), std::future_status::ready);
  EXPECT_TRUE(f.get());
}

TEST(Executor, AnIdleStateIsSteppedOnTheCallingThread) {
  Executor ex;
  ex.set_inline_steps(true);
  start_without_timers(ex);
  std::thread::id ran_on;
  ex.dispatch([&] { ran_on = std::this_thread::get_id(); });
  EXPECT_EQ(ran_on, std::this_thread::get_id());  // done before dispatch returned
}

TEST(Executor, ABusyStateQueuesAndKeepsTheOrder) {
  std::promise<void> release_first;
  std::promise<void> first_running;
  std::vector<int> order;  // touched only by tasks: one at a time
  std::promise<void> all_done;
  const auto me = std::this_thread::get_id();
  std::atomic<bool> ran_here{false};
  Executor ex;  // after what its tasks touch: destroyed (and joined) first
  ex.set_inline_steps(true);
  start_without_timers(ex);
  std::thread holder([&] {
    ex.dispatch([&] {
      order.push_back(1);
      first_running.set_value();
      release_first.get_future().wait();
    });
  });
  first_running.get_future().wait();
  // The state is busy: these two must not run here, nor before the first.
  ex.dispatch([&] {
    ran_here = ran_here || std::this_thread::get_id() == me;
    order.push_back(2);
  });
  ex.dispatch([&] {
    ran_here = ran_here || std::this_thread::get_id() == me;
    order.push_back(3);
    all_done.set_value();
  });
  release_first.set_value();
  holder.join();
  auto f = all_done.get_future();
  ASSERT_EQ(f.wait_for(kGenerous), std::future_status::ready);
  EXPECT_FALSE(ran_here);
  EXPECT_EQ(order, (std::vector<int>{1, 2, 3}));
}

// A command a callback issues inside an inline step (complete() from
// on_request) runs right after the step on the same thread, before it lets
// go: no hand-off to the executor thread for it.
TEST(Executor, WhatAnInlineStepQueuesRunsBeforeItLetsGo) {
  Executor ex;
  ex.set_inline_steps(true);
  start_without_timers(ex);
  std::vector<int> order;
  std::thread::id nested_ran_on;
  ex.dispatch([&] {
    order.push_back(1);
    ex.dispatch([&] {
      nested_ran_on = std::this_thread::get_id();
      order.push_back(2);
    });
    order.push_back(3);  // the nested task waits for this step to end
  });
  EXPECT_EQ(order, (std::vector<int>{1, 3, 2}));  // all done when dispatch returned
  EXPECT_EQ(nested_ran_on, std::this_thread::get_id());
}

// A task queued while the executor thread runs a report (an application
// callback that takes its time) does not hold back the steps behind it: the
// next dispatch that finds the state idle runs it first, then its own step.
TEST(Executor, AQueuedTaskIsRunByTheNextInlineStepNotLeftBehindAReport) {
  std::promise<void> in_report;
  std::promise<void> hold;
  std::shared_future<void> held = hold.get_future().share();
  std::vector<int> order;
  std::thread::id queued_ran_on;
  Executor ex;  // after what its tasks touch: destroyed (and joined) first
  ex.set_inline_steps(true);
  start_without_timers(ex);
  ex.post_report([&in_report, held] {
    in_report.set_value();
    held.wait();
  });
  in_report.get_future().wait();
  ex.post([&] {
    queued_ran_on = std::this_thread::get_id();
    order.push_back(1);
  });
  ex.dispatch([&] { order.push_back(2); });
  EXPECT_EQ(order, (std::vector<int>{1, 2}));  // both done when dispatch returned
  EXPECT_EQ(queued_ran_on, std::this_thread::get_id());
  hold.set_value();
}

// A task queued by the executor thread's own task wakes nobody (the thread
// is awake) and still runs: the loop finds it after the batch.
TEST(Executor, WhatATaskPostsRunsAfterIt) {
  std::promise<std::vector<int>> done;
  std::vector<int> order;
  Executor ex;
  start_without_timers(ex);
  ex.post([&] {
    order.push_back(1);
    ex.post([&] {
      order.push_back(3);
      done.set_value(order);
    });
    order.push_back(2);
  });
  auto f = done.get_future();
  ASSERT_EQ(f.wait_for(kGenerous), std::future_status::ready);
  EXPECT_EQ(f.get(), (std::vector<int>{1, 2, 3}));
}

// A thread inside one equipment's step (its write delivering, as Cyclone
// DDS does within a process, to another equipment's listener) never steps a
// second equipment inline: that one's executor takes it. A state whose
// steps write nothing (an observer's) may still be stepped there.
TEST(Executor, AThreadOwningAStateStepsNoOtherThatWritesInline) {
  Executor outer;
  Executor writes;
  Executor reads_only;
  for (Executor* ex : {&outer, &writes, &reads_only}) ex->set_inline_steps(true);
  reads_only.set_inline_steps(true, /*steps_write=*/false);
  for (Executor* ex : {&outer, &writes, &reads_only}) start_without_timers(*ex);
  std::promise<std::thread::id> writes_ran_on;
  std::thread::id reads_only_ran_on;
  std::thread::id outer_ran_on;
  outer.dispatch([&] {
    outer_ran_on = std::this_thread::get_id();
    writes.dispatch([&] { writes_ran_on.set_value(std::this_thread::get_id()); });
    reads_only.dispatch([&] { reads_only_ran_on = std::this_thread::get_id(); });
  });
  auto f = writes_ran_on.get_future();
  ASSERT_EQ(f.wait_for(kGenerous), std::future_status::ready);
  EXPECT_EQ(outer_ran_on, std::this_thread::get_id());
  EXPECT_NE(f.get(), std::this_thread::get_id());            // on its executor thread
  EXPECT_EQ(reads_only_ran_on, std::this_thread::get_id());  // inline, nested
}

TEST(Executor, ManyThreadsNeverStepAtOnce) {
  constexpr int kThreads = 4;
  constexpr int kEach = 2000;
  std::atomic<int> inside{0};
  std::atomic<int> overlaps{0};
  int count = 0;  // unsynchronised on purpose: TSan reports a second owner
  std::promise<void> last;
  // Declared after what its tasks touch: destroyed (and joined) first.
  Executor ex;
  ex.set_inline_steps(true);
  start_without_timers(ex);
  std::vector<std::thread> threads;
  threads.reserve(kThreads);
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&] {
      for (int i = 0; i < kEach; ++i) {
        ex.dispatch([&] {
          if (inside.fetch_add(1) != 0) overlaps.fetch_add(1);
          std::this_thread::yield();  // widens the window a second owner would hit
          if (++count == kThreads * kEach) last.set_value();
          inside.fetch_sub(1);
        });
      }
    });
  }
  for (auto& t : threads) t.join();
  auto f = last.get_future();
  ASSERT_EQ(f.wait_for(kGenerous), std::future_status::ready);
  EXPECT_EQ(overlaps.load(), 0);
}

// An inline step that moves the next wake-up earlier must wake the executor
// thread, which was waiting for an instant far away.
TEST(Executor, AnInlineStepThatMovesTheWakeUpIsHonoured) {
  Clock::time_point next = Clock::time_point::max();  // read by the owner only
  std::promise<bool> woke;
  std::atomic<bool> fired{false};
  Executor ex;  // after what its callbacks touch: destroyed (and joined) first
  ex.set_inline_steps(true);
  ex.start([&] { return next; },
           [&](Clock::time_point) {
             if (!fired.exchange(true)) {
               woke.set_value(ex.on_executor_thread());
               next = Clock::time_point::max();
             }
           });
  ex.dispatch([&] { next = Clock::now() + 20ms; });
  auto f = woke.get_future();
  ASSERT_EQ(f.wait_for(kGenerous), std::future_status::ready);
  EXPECT_TRUE(f.get());
}

TEST(Executor, StopWaitsForAStepInProgressAndRefusesNewOnes) {
  auto ex = std::make_unique<Executor>();
  ex->set_inline_steps(true);
  start_without_timers(*ex);
  std::promise<void> running;
  std::promise<void> finish;
  std::atomic<bool> step_done{false};
  std::thread stepper([&] {
    ex->dispatch([&] {
      running.set_value();
      finish.get_future().wait();
      step_done = true;
    });
  });
  running.get_future().wait();
  auto stopped = std::async(std::launch::async, [&] { ex->stop(); });
  // stop() cannot return while the step runs: it returns only after finish.
  EXPECT_EQ(stopped.wait_for(50ms), std::future_status::timeout);
  finish.set_value();
  ASSERT_EQ(stopped.wait_for(kGenerous), std::future_status::ready);
  EXPECT_TRUE(step_done);
  stepper.join();
  bool ran_after_stop = false;
  ex->dispatch([&] { ran_after_stop = true; });
  EXPECT_FALSE(ran_after_stop);
}

TEST(Executor, TheWatchdogSeesAStuckInlineStep) {
  std::promise<void> running;
  std::promise<void> finish;
  Executor ex;
  ex.set_inline_steps(true);
  start_without_timers(ex);
  std::thread stepper([&] {
    ex.dispatch([&] {
      running.set_value();
      finish.get_future().wait();
    });
  });
  running.get_future().wait();
  const auto later = Clock::now() + 1s;
  EXPECT_GE(ex.owed_for(later), 1s - 1ms);
  finish.set_value();
  stepper.join();
  EXPECT_EQ(ex.owed_for(Clock::now()), Clock::duration::zero());
}

}  // namespace
