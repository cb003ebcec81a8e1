// EquipmentOptions::inline_steps: values stepped on the middleware's thread
// and commands on the caller's when the equipment is idle. The handshake and
// failure behaviour must be exactly that of the executor-only runtime, and
// callbacks still run one at a time.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
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

}  // namespace
}  // namespace mtc::dds::testing
