// Writes held for a burst (mw::WriteBatch): a writer outside any batch sends
// at once; inside, each writer is sent once when the thread's outermost
// batch ends, or at send_now(). The executor opens one around a run of
// reports and closes it early once it is as old as its burst age, so many
// reports in a row do not hold the first one's writes back. The ages are
// set far from the reports' durations, so no timing decides a result. The
// "writers" here are a recording flush function, no DDS.
#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <future>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "executor.hpp"
#include "mw/write_batch.hpp"

namespace {

using mtc::dds::detail::Executor;
using mtc::dds::mw::WriteBatch;
using Clock = Executor::Clock;
using namespace std::chrono_literals;

constexpr auto kGenerous = 10s;  // a bound that only a hang exceeds

std::mutex g_mutex;
std::condition_variable g_changed;
std::vector<std::int64_t> g_sent;  // handles flushed, in order

void record_flush(std::int64_t handle) noexcept {
  {
    const std::lock_guard<std::mutex> lock(g_mutex);
    g_sent.push_back(handle);
  }
  g_changed.notify_all();
}

std::vector<std::int64_t> sent() {
  const std::lock_guard<std::mutex> lock(g_mutex);
  return g_sent;
}

// What was flushed once `count` handles were, or after kGenerous.
std::vector<std::int64_t> sent_once(std::size_t count) {
  std::unique_lock<std::mutex> lock(g_mutex);
  g_changed.wait_for(lock, kGenerous, [&] { return g_sent.size() >= count; });
  return g_sent;
}

void forget_sent() {
  const std::lock_guard<std::mutex> lock(g_mutex);
  g_sent.clear();
}

TEST(WriteBatch, OutsideABatchTheWriterSendsAtOnce) {
  forget_sent();
  EXPECT_FALSE(WriteBatch::defer(&record_flush, 1));
  EXPECT_TRUE(sent().empty());  // the caller sends, not the batch
}

TEST(WriteBatch, TheOutermostBatchSendsEachWriterOnce) {
  forget_sent();
  {
    const WriteBatch outer;
    {
      const WriteBatch inner;
      EXPECT_TRUE(WriteBatch::defer(&record_flush, 7));
      EXPECT_TRUE(WriteBatch::defer(&record_flush, 7));
      EXPECT_TRUE(WriteBatch::defer(&record_flush, 9));
    }
    EXPECT_TRUE(sent().empty()) << "an inner batch ended the burst";
    EXPECT_TRUE(WriteBatch::defer(&record_flush, 7));
  }
  EXPECT_EQ(sent(), (std::vector<std::int64_t>{7, 9}));
  EXPECT_FALSE(WriteBatch::defer(&record_flush, 7)) << "no batch is open any more";
}

TEST(WriteBatch, SendNowSendsWhatIsHeldAndStaysOpen) {
  forget_sent();
  const WriteBatch batch;
  EXPECT_TRUE(WriteBatch::defer(&record_flush, 3));
  WriteBatch::send_now();
  EXPECT_EQ(sent(), (std::vector<std::int64_t>{3}));
  EXPECT_TRUE(WriteBatch::defer(&record_flush, 4));
  EXPECT_EQ(sent(), (std::vector<std::int64_t>{3}));
}

TEST(WriteBatch, EachThreadHasItsOwn) {
  forget_sent();
  const WriteBatch here;
  EXPECT_TRUE(WriteBatch::defer(&record_flush, 5));
  bool deferred_there = true;
  std::thread([&] { deferred_there = WriteBatch::defer(&record_flush, 6); }).join();
  EXPECT_FALSE(deferred_there);
  EXPECT_TRUE(sent().empty());
}

void start_without_timers(Executor& ex) {
  ex.start([] { return Clock::time_point::max(); }, [](Clock::time_point) {});
}

// A report that holds the executor thread until `release` is set: the
// reports posted meanwhile queue up and then run as one run.
void hold_executor_thread(Executor& ex, std::promise<void>& release) {
  // Shared: the report may still be inside set_value() when this returns.
  auto holding = std::make_shared<std::promise<void>>();
  auto held = holding->get_future();
  ex.post_report([holding, &release] {
    holding->set_value();
    release.get_future().wait();
  });
  held.wait();
}

// Two reports queued behind a third that holds the executor thread: they
// run as one run, and what both wrote is sent after the second.
TEST(WriteBatch, AnExecutorSendsARunOfReportsTogether) {
  forget_sent();
  std::promise<void> release;
  std::promise<std::vector<std::int64_t>> seen_by_second;
  Executor ex;                  // after what its reports touch: destroyed (and joined) first
  ex.set_burst_age(kGenerous);  // never reached here: one burst
  start_without_timers(ex);
  hold_executor_thread(ex, release);
  ex.post_report([] { WriteBatch::defer(&record_flush, 1); });
  ex.post_report([&] {
    WriteBatch::defer(&record_flush, 2);
    seen_by_second.set_value(sent());
  });
  release.set_value();
  auto second = seen_by_second.get_future();
  ASSERT_EQ(second.wait_for(kGenerous), std::future_status::ready);
  EXPECT_TRUE(second.get().empty()) << "the first report's write left before the run ended";
  EXPECT_EQ(sent_once(2), (std::vector<std::int64_t>{1, 2}));
}

// A burst as old as the age (zero here: any report outlasts it) is sent
// before the next report runs.
TEST(WriteBatch, AnExecutorClosesABurstOnceItIsOld) {
  forget_sent();
  std::promise<void> release;
  std::promise<std::vector<std::int64_t>> seen_by_next;
  Executor ex;
  ex.set_burst_age(Clock::duration::zero());
  start_without_timers(ex);
  hold_executor_thread(ex, release);
  ex.post_report([] { WriteBatch::defer(&record_flush, 1); });
  ex.post_report([&] { seen_by_next.set_value(sent()); });
  release.set_value();
  auto next = seen_by_next.get_future();
  ASSERT_EQ(next.wait_for(kGenerous), std::future_status::ready);
  EXPECT_EQ(next.get(), (std::vector<std::int64_t>{1}));
}

}  // namespace
