// Scenario 6 and packet loss, with real transports: intra-process delivery
// is off, so every sample crosses the Fast DDS test UDP transport, which cuts
// one participant's traffic (outage) or drops a share of DATA submessages.
#include <gtest/gtest.h>

#include <thread>

#include "equipment_fixture.hpp"
#include "mtc/dds/domain_observer.hpp"

namespace mtc::dds::testing {
namespace {

using core::InterfaceType;
using core::Reason;

class CommsLoss : public ::testing::Test {
 protected:
  void SetUp() override { qos::set_intraprocess_delivery(false); }
  void TearDown() override { qos::set_intraprocess_delivery(true); }
};

EquipmentOptions lossy(int domain, const std::string& uuid,
                       std::shared_ptr<std::atomic<bool>> outage = nullptr,
                       std::uint8_t drop_percent = 0) {
  auto o = options(domain, uuid, qos::Transport::LoopbackTest);
  o.faults.outage = std::move(outage);
  o.faults.drop_data_percent = drop_percent;
  return o;
}

std::int64_t ms_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - t)
      .count();
}

// A cable pull between the two (both participants' traffic cut) while idle: both detect the loss
// within the lease (+ margin), both go FAIL, the observer reports the robot's
// items lost; after the outage both recover to READY by themselves and a new
// handshake completes, with neither process restarted.
TEST_F(CommsLoss, OutageFailsBothSidesAndRecoversToReady) {
  auto cut = std::make_shared<std::atomic<bool>>(false);
  Recorder cnc_rec;
  Recorder robot_rec;
  Equipment cnc(lossy(50, "cnc-6", cut), cnc_rec.callbacks());
  Equipment robot(lossy(50, "robot-6", cut), robot_rec.callbacks());
  cnc.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"robot-6", "mh1"}});
  robot.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"cnc-6", "mh1"}});
  auto& req = cnc.add_requester("mh1", core::Service::MaterialLoad);
  ResponderCallbacks cb;
  cb.on_request = [](Responder& r) { r.complete(); };
  auto& resp = robot.add_responder("mh1", core::Service::MaterialLoad, cb);

  std::mutex m;
  std::condition_variable cv;
  std::vector<std::string> lost_items;
  bool observed_robot = false;
  DomainObserverCallbacks ocb;
  ocb.on_value = [&](const ObservedValue& v) {
    std::lock_guard<std::mutex> l(m);
    observed_robot = observed_robot || v.data_item_id == "mh1_material_load_response";
    cv.notify_all();
  };
  std::chrono::steady_clock::time_point observer_lost_at{};
  ocb.on_items_lost = [&](const std::string& dev, const std::vector<std::string>& items) {
    std::lock_guard<std::mutex> l(m);
    if (dev == "robot-6") {
      lost_items.insert(lost_items.end(), items.begin(), items.end());
      if (observer_lost_at == std::chrono::steady_clock::time_point{}) {
        observer_lost_at = std::chrono::steady_clock::now();
      }
    }
    cv.notify_all();
  };
  int robot_beats = 0;
  ocb.on_heartbeat = [&](const ObservedHeartbeat& h) {
    std::lock_guard<std::mutex> l(m);
    if (h.device_uuid == "robot-6") ++robot_beats;
    cv.notify_all();
  };
  DomainObserverOptions oo;
  oo.domain_id = 50;
  oo.transport = qos::Transport::LoopbackUdp;
  DomainObserver observer(oo, ocb);

  cnc.start();
  robot.start();
  ASSERT_TRUE(cnc_rec.wait_link(cnc, "mh1", LinkState::Up));
  ASSERT_TRUE(robot_rec.wait_link(robot, "mh1", LinkState::Up));
  // Each side (and the observer) must have seen the other before the cut:
  // a machine that never saw its counterpart has nothing to lose.
  ASSERT_TRUE(cnc_rec.wait([&] { return req.counterpart_state() == InteractionState::Ready; }));
  ASSERT_TRUE(robot_rec.wait([&] { return resp.counterpart_state() == InteractionState::Ready; }));
  {
    std::unique_lock<std::mutex> l(m);
    // The observer's loss detection rides on the robot's heartbeat: it
    // must have heard one (a value alone can arrive first).
    ASSERT_TRUE(cv.wait_for(l, kTimeout, [&] { return observed_robot && robot_beats > 0; }));
  }

  const auto start = std::chrono::steady_clock::now();
  cut->store(true);
  ASSERT_TRUE(cnc_rec.wait_link(cnc, "mh1", LinkState::Lost));
  const auto cnc_detect = ms_since(start);
  ASSERT_TRUE(robot_rec.wait_link(robot, "mh1", LinkState::Lost));
  const auto robot_detect = ms_since(start);
  RecordProperty("cnc_detection_ms", static_cast<int>(cnc_detect));
  RecordProperty("robot_detection_ms", static_cast<int>(robot_detect));
  // Lease 300 ms; generous bound for 2 busy cores.
  EXPECT_LT(cnc_detect, 2000) << cnc_rec.dump();
  EXPECT_LT(robot_detect, 2000) << robot_rec.dump();
  EXPECT_TRUE(cnc_rec.wait_state(req, InteractionState::Fail)) << cnc_rec.dump();
  EXPECT_TRUE(robot_rec.wait_state(resp, InteractionState::Fail)) << robot_rec.dump();
  EXPECT_EQ(req.counterpart_state(), InteractionState::Unavailable);
  {
    std::unique_lock<std::mutex> l(m);
    EXPECT_TRUE(cv.wait_for(l, kTimeout, [&] {
      return std::find(lost_items.begin(), lost_items.end(), "mh1_material_load_response") !=
             lost_items.end();
    }));
    // The observer (what the bridge runs) must not keep the cut robot's items
    // AVAILABLE until the participant lease (2 s).
    const auto observer_detect =
        std::chrono::duration_cast<std::chrono::milliseconds>(observer_lost_at - start).count();
    RecordProperty("observer_detection_ms", static_cast<int>(observer_detect));
    EXPECT_LT(observer_detect, 2000);
  }

  const auto restored = std::chrono::steady_clock::now();
  cut->store(false);
  ASSERT_TRUE(cnc_rec.wait_state(req, InteractionState::Ready)) << cnc_rec.dump();
  ASSERT_TRUE(robot_rec.wait_state(resp, InteractionState::Ready)) << robot_rec.dump();
  RecordProperty("ready_after_restore_ms", static_cast<int>(ms_since(restored)));
  EXPECT_TRUE(cnc_rec.saw_notice(core::Notice::CommsLost, Reason::CommsLost));
  RequestOptions wait;
  wait.wait_for_ready = 10s;
  EXPECT_EQ(req.request(wait).get().outcome, Outcome::Completed);
}

// A long cable pull (longer than the 2 s participant lease and the 2 s
// fail_ack limit): the peers forget each other, rediscover each other when
// the cable is back, and still recover to READY on their own.
TEST_F(CommsLoss, LongOutageRediscoversAndRecovers) {
  auto cut = std::make_shared<std::atomic<bool>>(false);
  Recorder cnc_rec;
  Recorder robot_rec;
  Equipment cnc(lossy(54, "cnc-10", cut), cnc_rec.callbacks());
  Equipment robot(lossy(54, "robot-10", cut), robot_rec.callbacks());
  cnc.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"robot-10", "mh1"}});
  robot.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"cnc-10", "mh1"}});
  auto& req = cnc.add_requester("mh1", core::Service::MaterialChange);
  ResponderCallbacks cb;
  cb.on_request = [](Responder& r) { r.complete(); };
  auto& resp = robot.add_responder("mh1", core::Service::MaterialChange, cb);
  cnc.start();
  robot.start();
  ASSERT_TRUE(cnc_rec.wait([&] { return req.counterpart_state() == InteractionState::Ready; }));
  ASSERT_TRUE(robot_rec.wait([&] { return resp.counterpart_state() == InteractionState::Ready; }));
  cut->store(true);
  ASSERT_TRUE(cnc_rec.wait_state(req, InteractionState::Fail));
  ASSERT_TRUE(robot_rec.wait_state(resp, InteractionState::Fail));
  // The fail_ack limit (2 s) expires while still cut off: an event, not a sleep.
  ASSERT_TRUE(cnc_rec.wait_notice(core::Notice::TimedOut, Reason::FailAckTimeout));
  ASSERT_TRUE(robot_rec.wait_notice(core::Notice::TimedOut, Reason::FailAckTimeout));
  EXPECT_EQ(req.state(), InteractionState::Fail);  // no recovery while the link is down
  cut->store(false);
  ASSERT_TRUE(cnc_rec.wait_state(req, InteractionState::Ready)) << cnc_rec.dump();
  ASSERT_TRUE(robot_rec.wait_state(resp, InteractionState::Ready)) << robot_rec.dump();
  RequestOptions wait;
  wait.wait_for_ready = 10s;
  EXPECT_EQ(req.request(wait).get().outcome, Outcome::Completed);
}

// A one-way outage (only the robot's sending cut) longer than the participant
// lease: the cnc drops the robot's participant, the robot keeps the cnc's
// (it still hears it). When the robot is heard again the cnc rediscovers it
// and asks for all of its endpoint announcements, which Fast DDS 2.9.1 does
// not send again (the robot's discovery writers hold them as acknowledged
// by the cnc already). The same state arises from a two-way cable pull when
// one side's participant lease expires and the other's has not yet (the
// multihost cable pull). Both sides must still come back to READY.
TEST_F(CommsLoss, OneWayOutageBeyondParticipantLeaseRecovers) {
  auto robot_cut = std::make_shared<std::atomic<bool>>(false);
  Recorder cnc_rec;
  Recorder robot_rec;
  Equipment cnc(lossy(49, "cnc-11"), cnc_rec.callbacks());
  Equipment robot(lossy(49, "robot-11", robot_cut), robot_rec.callbacks());
  cnc.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"robot-11", "mh1"}});
  robot.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"cnc-11", "mh1"}});
  auto& req = cnc.add_requester("mh1", core::Service::MaterialChange);
  ResponderCallbacks cb;
  cb.on_request = [](Responder& r) { r.complete(); };
  auto& resp = robot.add_responder("mh1", core::Service::MaterialChange, cb);
  cnc.start();
  robot.start();
  ASSERT_TRUE(cnc_rec.wait([&] { return req.counterpart_state() == InteractionState::Ready; }));
  ASSERT_TRUE(robot_rec.wait([&] { return resp.counterpart_state() == InteractionState::Ready; }));
  robot_cut->store(true);
  ASSERT_TRUE(cnc_rec.wait_state(req, InteractionState::Fail));
  ASSERT_TRUE(robot_rec.wait_state(resp, InteractionState::Fail));
  // The fault itself: out for twice the participant lease after the cnc's
  // FAIL, so that the cnc has dropped the robot's participant for certain.
  std::this_thread::sleep_for(2 * qos::Timing{}.participant_lease);
  robot_cut->store(false);
  ASSERT_TRUE(cnc_rec.wait_state(req, InteractionState::Ready)) << cnc_rec.dump();
  ASSERT_TRUE(robot_rec.wait_state(resp, InteractionState::Ready)) << robot_rec.dump();
  RequestOptions wait;
  wait.wait_for_ready = 10s;
  EXPECT_EQ(req.request(wait).get().outcome, Outcome::Completed);
}

// Two interfaces with different heartbeats on the same pair of devices: a
// cable pull is detected per interface, each within its own lease.
TEST_F(CommsLoss, PerInterfaceTimingSetsEachDetectionTime) {
  auto cut = std::make_shared<std::atomic<bool>>(false);
  qos::Timing slow;
  slow.heartbeat = 400ms;  // lease 1.2 s
  Recorder cnc_rec;
  Recorder robot_rec;
  Equipment cnc(lossy(55, "cnc-t", cut), cnc_rec.callbacks());
  Equipment robot(lossy(55, "robot-t", cut), robot_rec.callbacks());
  InterfaceConfig fast_cnc{"fast", InterfaceType::MaterialHandler, "", {"robot-t", "fast"}};
  InterfaceConfig slow_cnc{"slow", InterfaceType::BarFeeder, "", {"robot-t", "slow"}};
  slow_cnc.timing = slow;
  InterfaceConfig fast_robot{"fast", InterfaceType::MaterialHandler, "", {"cnc-t", "fast"}};
  InterfaceConfig slow_robot{"slow", InterfaceType::BarFeeder, "", {"cnc-t", "slow"}};
  slow_robot.timing = slow;
  cnc.add_interface(fast_cnc);
  cnc.add_interface(slow_cnc);
  robot.add_interface(fast_robot);
  robot.add_interface(slow_robot);
  auto& load = cnc.add_requester("fast", core::Service::MaterialLoad);
  auto& feed = cnc.add_requester("slow", core::Service::MaterialFeed);
  ResponderCallbacks cb;
  cb.on_request = [](Responder& r) { r.complete(); };
  robot.add_responder("fast", core::Service::MaterialLoad, cb);
  robot.add_responder("slow", core::Service::MaterialFeed, cb);
  cnc.start();
  robot.start();
  RequestOptions wait;
  wait.wait_for_ready = 10s;
  EXPECT_EQ(load.request(wait).get().outcome, Outcome::Completed);
  EXPECT_EQ(feed.request(wait).get().outcome, Outcome::Completed);
  const auto start = std::chrono::steady_clock::now();
  cut->store(true);
  ASSERT_TRUE(cnc_rec.wait_link(cnc, "fast", LinkState::Lost));
  const auto fast_ms = ms_since(start);
  ASSERT_TRUE(cnc_rec.wait_link(cnc, "slow", LinkState::Lost));
  const auto slow_ms = ms_since(start);
  RecordProperty("fast_detection_ms", static_cast<int>(fast_ms));
  RecordProperty("slow_detection_ms", static_cast<int>(slow_ms));
  EXPECT_LT(fast_ms, 2000);
  EXPECT_GT(slow_ms, fast_ms);
  for (const auto& l : cnc_rec.links()) {
    if (l.interface_id == "slow" && l.current == LinkState::Lost) {
      EXPECT_GE(l.silence, 600ms) << "lost after " << l.silence.count() / 1000000 << " ms";
    }
  }
  cut->store(false);
  EXPECT_TRUE(cnc_rec.wait_state(load, InteractionState::Ready));
  EXPECT_TRUE(cnc_rec.wait_state(feed, InteractionState::Ready));
  EXPECT_EQ(feed.request(wait).get().outcome, Outcome::Completed);
}

// Outage while a request is ACTIVE: the request ends CommsLost, the
// responder is told to abort, and both recover afterwards.
TEST_F(CommsLoss, OutageDuringServiceAbortsBothSides) {
  auto cut = std::make_shared<std::atomic<bool>>(false);
  Recorder cnc_rec;
  Recorder robot_rec;
  Equipment cnc(lossy(51, "cnc-7", cut), cnc_rec.callbacks());
  Equipment robot(lossy(51, "robot-7", cut), robot_rec.callbacks());
  cnc.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"robot-7", "mh1"}});
  robot.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"cnc-7", "mh1"}});
  auto& req = cnc.add_requester("mh1", core::Service::MaterialUnload);
  std::atomic<int> aborted{-1};
  ResponderCallbacks cb;
  cb.on_request = [](Responder&) {};
  cb.on_abort = [&](Responder&, Reason why) {
    aborted = static_cast<int>(why);
    robot_rec.notify();
  };
  auto& resp = robot.add_responder("mh1", core::Service::MaterialUnload, cb);
  cnc.start();
  robot.start();
  RequestOptions wait;
  wait.wait_for_ready = 10s;
  auto outcome = req.request(wait);
  ASSERT_TRUE(robot_rec.wait_state(resp, InteractionState::Active));
  ASSERT_TRUE(cnc_rec.wait([&] { return req.counterpart_state() == InteractionState::Active; }));
  cut->store(true);
  ASSERT_EQ(outcome.wait_for(kTimeout), std::future_status::ready);
  const auto r = outcome.get();
  EXPECT_EQ(r.outcome, Outcome::CommsLost);
  ASSERT_TRUE(robot_rec.wait([&] { return aborted.load() >= 0; }));
  EXPECT_EQ(aborted.load(), static_cast<int>(Reason::CommsLost));
  cut->store(false);
  EXPECT_TRUE(cnc_rec.wait_state(req, InteractionState::Ready)) << cnc_rec.dump();
  EXPECT_TRUE(robot_rec.wait_state(resp, InteractionState::Ready)) << robot_rec.dump();
}

// The robot process "dies" (its Equipment is destroyed) and comes back as a
// new object with the same uuid: the machine tool fails, then recovers.
TEST_F(CommsLoss, CounterpartDestroyedAndRecreated) {
  Recorder cnc_rec;
  Equipment cnc(lossy(52, "cnc-8"), cnc_rec.callbacks());
  cnc.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"robot-8", "mh1"}});
  auto& req = cnc.add_requester("mh1", core::Service::MaterialLoad);
  cnc.start();
  auto make_robot = [] {
    auto robot = std::make_unique<Equipment>(lossy(52, "robot-8"));
    robot->add_interface({"mh1", InterfaceType::MaterialHandler, "", {"cnc-8", "mh1"}});
    ResponderCallbacks cb;
    cb.on_request = [](Responder& r) { r.complete(); };
    robot->add_responder("mh1", core::Service::MaterialLoad, cb);
    robot->start();
    return robot;
  };
  auto robot = make_robot();
  ASSERT_TRUE(cnc_rec.wait([&] { return req.counterpart_state() == InteractionState::Ready; }));
  const auto start = std::chrono::steady_clock::now();
  robot.reset();
  ASSERT_TRUE(cnc_rec.wait_state(req, InteractionState::Fail));
  RecordProperty("graceful_detection_ms", static_cast<int>(ms_since(start)));
  EXPECT_LT(ms_since(start), 2000);
  robot = make_robot();
  ASSERT_TRUE(cnc_rec.wait_state(req, InteractionState::Ready));
  RequestOptions wait;
  wait.wait_for_ready = 10s;
  EXPECT_EQ(req.request(wait).get().outcome, Outcome::Completed);
}

// 15 % of DATA submessages dropped in both directions: reliable delivery
// with the 20 ms RTPS heartbeat still completes every handshake, in order.
TEST_F(CommsLoss, PacketLossStillCompletesHandshakesInOrder) {
  Recorder cnc_rec;
  Equipment cnc(lossy(53, "cnc-9", nullptr, 15), cnc_rec.callbacks());
  Equipment robot(lossy(53, "robot-9", nullptr, 15));
  cnc.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"robot-9", "mh1"}});
  robot.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"cnc-9", "mh1"}});
  auto& req = cnc.add_requester("mh1", core::Service::MaterialLoad);
  ResponderCallbacks cb;
  cb.on_request = [](Responder& r) { r.complete(); };
  robot.add_responder("mh1", core::Service::MaterialLoad, cb);
  cnc.start();
  robot.start();
  RequestOptions wait;
  wait.wait_for_ready = 10s;
  constexpr int kHandshakes = 20;
  for (int i = 0; i < kHandshakes; ++i) {
    auto f = req.request(wait);
    ASSERT_EQ(f.wait_for(kTimeout), std::future_status::ready) << "handshake " << i;
    const auto r = f.get();
    ASSERT_EQ(r.outcome, Outcome::Completed)
        << "handshake " << i << ": " << core::describe(r.reason);
  }
  // No protocol violation was ever seen by the requester.
  for (const auto& e : cnc_rec.transitions()) {
    EXPECT_NE(e.step.notice, core::Notice::ProtocolViolation) << core::describe(e.step.reason);
  }
}

}  // namespace
}  // namespace mtc::dds::testing
