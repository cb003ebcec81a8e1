// DomainObserverOptions::inline_steps: a received value that finds the
// observer idle is handled on the middleware's thread. The values and their
// order must be what the dispatch thread would have delivered, callbacks
// must never overlap, and some must really run off the dispatch thread.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

#include "equipment_fixture.hpp"
#include "mtc/dds/domain_observer.hpp"
#include "transport.hpp"

namespace mtc::dds::testing {
namespace {

// What the observer's callbacks saw: the responder's states in order, the
// threads they came on, and whether two ever ran at once.
struct ObservedThreads {
  std::atomic<int> inside{0};
  std::atomic<int> overlaps{0};
  std::mutex mutex;
  std::thread::id dispatch;  // where two of the beacon's heartbeats ran
  std::vector<std::thread::id> beacon_beats;
  std::vector<std::thread::id> value_threads;
  std::vector<std::uint64_t> sequences;
  std::vector<std::int32_t> states;  // raw InteractionState codes

  DomainObserverCallbacks callbacks(Recorder& rec) {
    DomainObserverCallbacks cb;
    cb.on_heartbeat = [this, &rec](const ObservedHeartbeat& h) {
      enter();
      if (h.device_uuid == "beacon-oi") note_beacon_beat();
      leave();
      rec.notify();
    };
    cb.on_value = [this, &rec](const ObservedValue& v) {
      enter();
      if (v.device_uuid == "robot-oi" && v.service == core::Service::MaterialLoad &&
          v.sub_type == core::SubType::Response && !v.redelivered) {
        std::lock_guard<std::mutex> lock(mutex);
        value_threads.push_back(std::this_thread::get_id());
        sequences.push_back(v.sequence_number);
        states.push_back(v.state.raw());
      }
      std::this_thread::yield();  // widen the window an overlap would need
      leave();
      rec.notify();
    };
    return cb;
  }
  std::size_t count() {
    std::lock_guard<std::mutex> lock(mutex);
    return states.size();
  }
  bool dispatch_known() {
    std::lock_guard<std::mutex> lock(mutex);
    return dispatch != std::thread::id();
  }

 private:
  void note_beacon_beat() {
    std::lock_guard<std::mutex> lock(mutex);
    const auto here = std::this_thread::get_id();
    if (dispatch == std::thread::id() &&
        std::find(beacon_beats.begin(), beacon_beats.end(), here) != beacon_beats.end()) {
      dispatch = here;
    }
    beacon_beats.push_back(here);
  }
  void enter() {
    if (inside.fetch_add(1) != 0) overlaps.fetch_add(1);
  }
  void leave() { inside.fetch_sub(1); }
};

// Ample for a pass of microseconds, even on a loaded 2-core runner.
constexpr auto kObserverGoesIdle = std::chrono::milliseconds(5);

// Finds the observer's dispatch thread first. Heartbeats are posted, never
// stepped inline, but one posted while a value is being stepped inline is
// drained on that middleware thread; the beacon writes its values once at
// start and then only heartbeats (10 per second), so the thread that runs
// two of them is the dispatch thread.
// Then toggles a responder `toggles` times (READY first). Each toggle waits
// until the observer has its value and then pauses: the callback wakes this
// thread before the observer's pass ends, and a toggle written meanwhile is
// queued, so without the pause one queued value can make the next one wait
// too, toggle after toggle (seen in CI on 2 cores). No event says "the
// observer is idle" (nothing outside needs one), and an idle observer is the
// condition under test, not the synchronisation of its results.
void toggle_and_watch(ObservedThreads& seen, Recorder& rec, bool inline_steps, int domain,
                      int toggles) {
  auto oo = mtc::test::loopback<DomainObserverOptions>();
  oo.domain_id = domain;
  oo.inline_steps = inline_steps;
  DomainObserver observer(oo, seen.callbacks(rec));
  Equipment beacon(options(domain, "beacon-oi"));
  beacon.add_interface({"mh1", core::InterfaceType::MaterialHandler, "", {}});
  beacon.start();
  ASSERT_TRUE(rec.wait([&] { return seen.dispatch_known(); }))
      << "the beacon's heartbeats never came";
  Equipment robot(options(domain, "robot-oi"));
  robot.add_interface({"mh1", core::InterfaceType::MaterialHandler, "", {}});
  auto& load = robot.add_responder("mh1", core::Service::MaterialLoad, ResponderCallbacks{});
  robot.start();
  ASSERT_TRUE(rec.wait([&] { return seen.count() >= 1; })) << "the first value never arrived";
  for (int k = 0; k < toggles; ++k) {
    const std::size_t before = seen.count();
    load.set_ready(k % 2 == 1).get();
    ASSERT_TRUE(rec.wait([&] { return seen.count() > before; })) << "toggle " << k;
    std::this_thread::sleep_for(kObserverGoesIdle);
  }
}

TEST(ObserverInlineSteps, ValuesArriveInOrderWithoutOverlapAndOffTheDispatchThread) {
  ObservedThreads seen;  // before the recorder's users: outlives the callbacks
  Recorder rec;
  toggle_and_watch(seen, rec, true, 163, 20);
  EXPECT_EQ(seen.overlaps.load(), 0);
  std::lock_guard<std::mutex> lock(seen.mutex);
  ASSERT_NE(seen.dispatch, std::thread::id()) << "the beacon was never seen";
  // Every toggle arrived, in the order written (rising change numbers), and
  // the last one written (READY) is the last one seen.
  EXPECT_GE(seen.states.size(), 21U);
  for (std::size_t i = 1; i < seen.states.size(); ++i) {
    EXPECT_GT(seen.sequences[i], seen.sequences[i - 1]) << "value " << i;
  }
  EXPECT_EQ(seen.states.back(), static_cast<std::int32_t>(InteractionState::Ready));
  int off_dispatch = 0;
  for (auto t : seen.value_threads) off_dispatch += t != seen.dispatch ? 1 : 0;
  EXPECT_GT(off_dispatch, 0) << "all " << seen.value_threads.size()
                             << " values were handed over on the dispatch thread";
}

// The control: without the option every value comes on the dispatch thread,
// so the case above really tells the two apart.
TEST(ObserverInlineSteps, WithoutThemEveryValueComesOnTheDispatchThread) {
  ObservedThreads seen;
  Recorder rec;
  toggle_and_watch(seen, rec, false, 168, 6);
  EXPECT_EQ(seen.overlaps.load(), 0);
  std::lock_guard<std::mutex> lock(seen.mutex);
  ASSERT_NE(seen.dispatch, std::thread::id());
  for (auto t : seen.value_threads) EXPECT_EQ(t, seen.dispatch);
}

}  // namespace
}  // namespace mtc::dds::testing
