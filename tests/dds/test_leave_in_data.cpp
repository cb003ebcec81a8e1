// The leave said in data (docs/design/middleware-layer.md, step 6): a
// device's last heartbeat of each group, period_ms 0, is its leave, told as
// a disposal is, for readers that never get the disposal (a Cyclone reader
// of a Fast DDS device: Fast DDS 2.9 disposes by the key's MD5 hash alone).
// The DomainObserver's side is in test_domain_observer.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <mutex>
#include <string>
#include <vector>

#include "equipment_fixture.hpp"
#include "mtc/dds/domain_observer.hpp"
#include "raw_peer.hpp"
#include "transport.hpp"

namespace mtc::dds::testing {
namespace {

using core::InterfaceType;
using core::SubType;

bool mentions(const std::string& text, const std::string& what) {
  return text.find(what) != std::string::npos;
}

std::vector<LinkEvent> links_to(Recorder& rec, LinkState state) {
  auto links = rec.links();
  links.erase(std::remove_if(links.begin(), links.end(),
                             [&](const LinkEvent& l) { return l.current != state; }),
              links.end());
  return links;
}

// A raw peer that beats, then writes its leaving heartbeat and never
// disposes: the Equipment takes the leave from the heartbeat, at once, not
// a loss after its lease. The lease is long (2 s) so that only the leave
// can end the link within the wait (a loss cue would come 2 s after the
// last beat and name a deadline or a liveliness lapse).
TEST(LeaveInData, ALeavingHeartbeatWithoutDisposalIsTheLeave) {
  constexpr int kDomain = 151;
  Recorder rec;
  auto o = options(kDomain, "robot-lv");
  o.timing.missed_heartbeats = 20;  // the raw peer beats every 100 ms
  Equipment robot(o, rec.callbacks());
  robot.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"cnc-lv", "mh1"}});
  robot.add_responder("mh1", Service::MaterialLoad, {});
  robot.start();
  RawPeer cnc(kDomain, "cnc-lv", SubType::Request, Service::MaterialLoad);
  cnc.set(InteractionState::Ready);
  ASSERT_TRUE(rec.wait_link(robot, "mh1", LinkState::Up)) << rec.dump();
  const auto left_at = std::chrono::steady_clock::now();
  cnc.leave_without_disposal();
  ASSERT_TRUE(rec.wait_link(robot, "mh1", LinkState::Lost, 1500ms)) << rec.dump();
  const auto told_after = std::chrono::steady_clock::now() - left_at;
  const auto lost = links_to(rec, LinkState::Lost);
  ASSERT_EQ(lost.size(), 1u) << rec.dump();
  EXPECT_EQ(lost[0].cause, "heartbeat leaving") << rec.dump();
  EXPECT_LT(told_after, o.timing.lease()) << rec.dump();
}

// Observer callbacks of one device, counted.
struct DeviceLosses {
  std::mutex mutex;
  std::vector<std::string> lost;
  std::vector<std::string> announced;

  DomainObserverCallbacks callbacks(Recorder& wake) {
    DomainObserverCallbacks cb;
    cb.on_device_lost = [this, &wake](const std::string& d) {
      add(lost, d);
      wake.notify();
    };
    cb.on_device = [this, &wake](const ObservedDevice& d) {
      add(announced, d.device_uuid);
      wake.notify();
    };
    return cb;
  }
  void add(std::vector<std::string>& to, const std::string& device) {
    std::lock_guard<std::mutex> lock(mutex);
    to.push_back(device);
  }
  std::size_t count(const std::vector<std::string>& of, const std::string& device) {
    std::lock_guard<std::mutex> lock(mutex);
    return static_cast<std::size_t>(std::count(of.begin(), of.end(), device));
  }
};

// A real Equipment's graceful end: the leaving heartbeat first, then the
// disposals; the pairing is freed once, the link lost once, the observer
// tells the device gone once. A second robot arriving afterwards is the
// fence: the leave was acknowledged before the first robot's destructor
// returned, and each reader handles its events in order.
TEST(LeaveInData, AGracefulEndIsToldAsALeaveOnce) {
  constexpr int kDomain = 152;
  Recorder machine_rec;
  DeviceLosses seen;
  auto oo = mtc::test::loopback<DomainObserverOptions>();
  oo.domain_id = kDomain;
  DomainObserver observer(oo, seen.callbacks(machine_rec));
  auto mo = options(kDomain, "m-lv");
  mo.pairing_settle = 500ms;
  Equipment machine(mo, machine_rec.callbacks());
  machine.add_interface({"mh", InterfaceType::MaterialHandler, "", {}});
  ResponderCallbacks serve;
  serve.on_request = [](Responder& r) { r.complete(); };
  machine.add_responder("mh", Service::MaterialLoad, serve);
  machine.start();
  RequestOptions wait;
  wait.wait_for_ready = 15s;
  {
    Equipment robot1(options(kDomain, "robot-lv1"));
    robot1.add_interface({"mh", InterfaceType::MaterialHandler, "", {"m-lv", ""}});
    auto& load1 = robot1.add_requester("mh", Service::MaterialLoad);
    robot1.start();
    EXPECT_EQ(load1.request(wait).get().outcome, Outcome::Completed) << machine_rec.dump();
    ASSERT_TRUE(machine_rec.wait([&] { return seen.count(seen.announced, "robot-lv1") > 0; }));
  }
  Equipment robot2(options(kDomain, "robot-lv2"));
  robot2.add_interface({"mh", InterfaceType::MaterialHandler, "", {"m-lv", ""}});
  auto& load2 = robot2.add_requester("mh", Service::MaterialLoad);
  robot2.start();
  EXPECT_EQ(load2.request(wait).get().outcome, Outcome::Completed) << machine_rec.dump();
  ASSERT_TRUE(machine_rec.wait([&] { return seen.count(seen.announced, "robot-lv2") > 0; }));

  const auto unpaired = links_to(machine_rec, LinkState::Unpaired);
  ASSERT_EQ(unpaired.size(), 1u) << machine_rec.dump();
  EXPECT_TRUE(mentions(unpaired[0].cause, "robot-lv1/mh left")) << machine_rec.dump();
  EXPECT_TRUE(mentions(unpaired[0].cause, "said it is leaving")) << machine_rec.dump();
  const auto lost = links_to(machine_rec, LinkState::Lost);
  ASSERT_EQ(lost.size(), 1u) << machine_rec.dump();
  EXPECT_EQ(lost[0].cause, "heartbeat leaving");
  EXPECT_EQ(seen.count(seen.lost, "robot-lv1"), 1u);
  EXPECT_EQ(seen.count(seen.lost, "robot-lv2"), 0u);
}

// What a device writes after its leave crossed it on another topic (a value
// written before the leaving heartbeat, delivered after it; a lingering
// writer's disposal) is not news: that incarnation has left. A new
// incarnation under the same uuid is heard as usual, and is the fence: the
// late value was acknowledged, so the robot had it before the newcomer's.
TEST(LeaveInData, WhatALeftIncarnationWritesLaterIsNotNews) {
  constexpr int kDomain = 153;
  Recorder rec;
  auto o = options(kDomain, "robot-lv3");
  o.timing.missed_heartbeats = 20;
  Equipment robot(o, rec.callbacks());
  robot.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"cnc-lv3", "mh1"}});
  robot.add_responder("mh1", Service::MaterialLoad, {});
  robot.start();
  RawPeer cnc(kDomain, "cnc-lv3", SubType::Request, Service::MaterialLoad, "robot-lv3");
  cnc.set(InteractionState::Ready);
  ASSERT_TRUE(rec.wait_link(robot, "mh1", LinkState::Up)) << rec.dump();
  cnc.leave_without_disposal();
  ASSERT_TRUE(rec.wait_link(robot, "mh1", LinkState::Lost)) << rec.dump();
  cnc.set(InteractionState::Active);
  ASSERT_TRUE(cnc.acknowledged(std::chrono::seconds(10))) << rec.dump();

  RawPeer again(kDomain, "cnc-lv3", SubType::Request, Service::MaterialLoad, "robot-lv3");
  again.set(InteractionState::Ready);
  ASSERT_TRUE(rec.wait_link(robot, "mh1", LinkState::Up)) << rec.dump();
  ASSERT_EQ(links_to(rec, LinkState::Lost).size(), 1u) << rec.dump();
  for (const auto& t : rec.transitions()) {
    EXPECT_NE(std::string(core::to_string(t.step.event)), "SeenActive") << rec.dump();
  }
}

}  // namespace
}  // namespace mtc::dds::testing
