// EquipmentOptions::inline_steps: values stepped on the middleware's thread
// and commands on the caller's when the equipment is idle, callbacks with
// them; and the default, which steps there too but keeps the callbacks on
// the executor thread. The handshake and
// failure behaviour must be exactly that of the executor-only runtime, and
// callbacks still run one at a time.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <functional>
#include <future>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "equipment_fixture.hpp"

namespace mtc::dds::testing {
namespace {

using core::InterfaceType;
using core::Reason;

// The thread of the robot's executor: where its configured pairing ran (a
// task start() posts before any DDS event can reach the equipment, so it
// runs on the executor thread with inline steps on or off).
class ExecutorThread {
 public:
  EquipmentCallbacks wrap(EquipmentCallbacks cb) {
    cb.on_link = [this, next = cb.on_link](const LinkEvent& e) {
      if (e.previous == LinkState::Unpaired && e.current == LinkState::Paired) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (id_ == std::thread::id()) id_ = std::this_thread::get_id();
      }
      if (next) next(e);
    };
    return cb;
  }
  std::thread::id id() {
    std::lock_guard<std::mutex> lock(mutex_);
    return id_;
  }

 private:
  std::mutex mutex_;
  std::thread::id id_;
};

struct InlineCell {
  Recorder cnc_rec;
  Recorder robot_rec;
  ExecutorThread robot_executor;
  Equipment cnc;
  Equipment robot;

  explicit InlineCell(int domain)
      : cnc(inline_options(domain, "cnc-1"), cnc_rec.callbacks()),
        robot(inline_options(domain, "robot-1"), robot_executor.wrap(robot_rec.callbacks())) {
    cnc.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"robot-1", "mh1"}});
    robot.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"cnc-1", "mh1"}});
  }
  static EquipmentOptions inline_options(int domain, const std::string& uuid) {
    auto o = options(domain, uuid);
    o.inline_steps = true;
    o.recovery = RecoveryPolicy::Manual;
    return o;
  }
};

// Every service completes, and no two callbacks of one equipment ever run
// at once although they may now come from several threads. And they do:
// requests from the counterpart are stepped on the middleware's thread, so
// some on_request runs off the robot's executor thread (with inline steps
// off, every one runs on it).
TEST(InlineSteps, EveryServiceCompletesAndCallbacksNeverOverlap) {
  std::atomic<int> inside{0};  // before the cell: outlives its callbacks
  std::atomic<int> overlaps{0};
  std::mutex threads_mutex;
  std::vector<std::thread::id> request_threads;  // where each on_request ran
  InlineCell cell(161);
  std::vector<Requester*> requesters;
  for (auto service : core::kAllServices) {
    requesters.push_back(&cell.cnc.add_requester("mh1", service));
    ResponderCallbacks cb;
    cb.on_request = [&](Responder& r) {
      if (inside.fetch_add(1) != 0) overlaps.fetch_add(1);
      {
        std::lock_guard<std::mutex> lock(threads_mutex);
        request_threads.push_back(std::this_thread::get_id());
      }
      std::this_thread::yield();
      r.complete();
      inside.fetch_sub(1);
    };
    cell.robot.add_responder("mh1", service, cb);
  }
  cell.cnc.start();
  cell.robot.start();
  RequestOptions wait;
  wait.wait_for_ready = 10s;
  for (int round = 0; round < 3; ++round) {
    std::vector<std::future<RequestResult>> results;
    results.reserve(requesters.size());
    for (auto* r : requesters) results.push_back(r->request(wait));  // all at once
    for (std::size_t i = 0; i < results.size(); ++i) {
      SCOPED_TRACE(std::string(core::to_string(core::kAllServices[i])));
      ASSERT_EQ(results[i].wait_for(kTimeout), std::future_status::ready);
      const auto result = results[i].get();
      EXPECT_EQ(result.outcome, Outcome::Completed) << core::describe(result.reason) << "\ncnc:\n"
                                                    << cell.cnc_rec.dump() << "robot:\n"
                                                    << cell.robot_rec.dump();
    }
  }
  EXPECT_EQ(overlaps.load(), 0);
  const auto executor = cell.robot_executor.id();
  ASSERT_NE(executor, std::thread::id()) << "the robot's pairing was never seen";
  std::lock_guard<std::mutex> lock(threads_mutex);
  ASSERT_FALSE(request_threads.empty());
  const auto off_executor = std::count_if(request_threads.begin(), request_threads.end(),
                                          [&](std::thread::id t) { return t != executor; });
  // Cyclone DDS delivers to a reader in the same process on the writer's
  // thread, so once the robot's executor writes, the whole ping-pong may stay
  // on it (the robot is busy whenever the cnc's answer comes back): there
  // the thread is the scheduling's choice, not the option's proof. Fast DDS
  // receives on threads of its own, where the option must show.
  if (mtc::test::test_middleware_is_cyclone()) return;
  EXPECT_GT(off_executor, 0) << "all " << request_threads.size()
                             << " on_request calls ran on the robot's executor thread";
}

// Scenario 2 (the responder fails while ACTIVE) and the manual recovery of
// both sides, with every step inline where it can be.
TEST(InlineSteps, Scenario2AndRecoveryBehaveAsWithoutThem) {
  InlineCell cell(162);
  auto& req = cell.cnc.add_requester("mh1", Service::PartChange);
  ResponderCallbacks cb;
  cb.on_request = [](Responder& r) { r.fail(); };
  auto& resp = cell.robot.add_responder("mh1", Service::PartChange, cb);
  cell.cnc.start();
  cell.robot.start();
  RequestOptions wait;
  wait.wait_for_ready = 10s;
  auto result = req.request(wait);
  ASSERT_EQ(result.wait_for(kTimeout), std::future_status::ready);
  const auto r = result.get();
  EXPECT_EQ(r.outcome, Outcome::Failed);
  EXPECT_EQ(r.reason, Reason::CounterpartFail);
  ASSERT_TRUE(
      cell.robot_rec.wait([&] { return resp.counterpart_state() == InteractionState::Fail; }));
  EXPECT_EQ(resp.recover(InteractionState::NotReady).get().current, InteractionState::NotReady);
  EXPECT_EQ(req.recover().get().current, InteractionState::Ready);
  EXPECT_TRUE(cell.robot_rec.wait_state(resp, InteractionState::NotReady));
}

// The default (neither inline_steps nor steps_on_executor): a value is
// stepped on the middleware's thread, so the robot answers a request with
// its ACTIVE while its executor thread is held by a task; yet every callback
// runs on that executor thread, as with steps_on_executor. Red with
// steps_on_executor: the ACTIVE waits for the executor.
TEST(DefaultStepping, StepsOffTheExecutorWhileEveryCallbackRunsOnIt) {
  std::mutex threads_mutex;
  std::vector<std::thread::id> callback_threads;  // the robot's callbacks
  const auto note_thread = [&] {
    std::lock_guard<std::mutex> lock(threads_mutex);
    callback_threads.push_back(std::this_thread::get_id());
  };
  Recorder cnc_rec;
  Recorder robot_rec;
  auto robot_cb = robot_rec.callbacks();
  robot_cb.on_transition = [&, next = robot_cb.on_transition](const TransitionEvent& e) {
    note_thread();
    next(e);
  };
  robot_cb.on_counterpart_value = [&,
                                   next = robot_cb.on_counterpart_value](const ObservedValue& v) {
    note_thread();
    next(v);
  };
  // A lease far beyond the time the robot's executor is held below, so that
  // the watchdog keeps its heartbeat. Fast DDS on both sides, whatever the
  // test middleware: it receives on threads of its own, while Cyclone DDS
  // delivers within one process on the writer's thread, which owns the
  // writer's state and so hands the robot's step to the robot's executor.
  auto long_lease = [](const std::string& uuid) {
    auto o = options(169, uuid);
    o.middleware = Middleware::FastDds;
    o.timing.missed_heartbeats = 30;
    return o;
  };
  Equipment cnc(long_lease("cnc-ds"), cnc_rec.callbacks());
  Equipment robot(long_lease("robot-ds"), robot_cb);
  cnc.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"robot-ds", "mh1"}});
  robot.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"cnc-ds", "mh1"}});
  auto& req = cnc.add_requester("mh1", Service::MaterialLoad);
  ResponderCallbacks cb;
  cb.on_request = [&](Responder& r) {
    note_thread();
    r.complete();
  };
  robot.add_responder("mh1", Service::MaterialLoad, cb);
  cnc.start();
  robot.start();
  RequestOptions wait;
  wait.wait_for_ready = 10s;
  // One handshake first: paired, and the robot's READY names the cnc.
  ASSERT_EQ(req.request(wait).get().outcome, Outcome::Completed) << cnc_rec.dump();
  ASSERT_TRUE(cnc_rec.wait([&] { return req.counterpart_state() == InteractionState::Ready; }));

  std::promise<std::thread::id> executor;
  std::promise<void> held;
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  bool opened = false;
  const auto open = [&] {
    if (!opened) release.set_value();
    opened = true;
  };
  struct OpenOnExit {  // also when an assertion ends the test early
    explicit OpenOnExit(std::function<void()> f) : open(std::move(f)) {}
    OpenOnExit(const OpenOnExit&) = delete;
    OpenOnExit& operator=(const OpenOnExit&) = delete;
    ~OpenOnExit() { open(); }
    std::function<void()> open;
  } open_on_exit{open};
  robot.post([&executor, &held, released] {
    executor.set_value(std::this_thread::get_id());
    held.set_value();
    released.wait();
  });
  held.get_future().wait();
  auto result = req.request(wait);
  EXPECT_TRUE(cnc_rec.wait([&] { return req.counterpart_state() == InteractionState::Active; }))
      << "the robot's ACTIVE waited for its executor";
  EXPECT_NE(result.wait_for(0ms), std::future_status::ready);  // on_request is held too
  open();
  ASSERT_EQ(result.wait_for(kTimeout), std::future_status::ready);
  EXPECT_EQ(result.get().outcome, Outcome::Completed);
  const auto executor_thread = executor.get_future().get();
  std::lock_guard<std::mutex> lock(threads_mutex);
  ASSERT_FALSE(callback_threads.empty());
  for (const auto t : callback_threads) EXPECT_EQ(t, executor_thread);
}

}  // namespace
}  // namespace mtc::dds::testing
