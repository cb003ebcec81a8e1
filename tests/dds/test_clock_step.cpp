// The wall clock is not a stopwatch. CLOCK_REALTIME steps under a running
// cell: NTP corrects a drifted controller, an operator sets the time, a VM
// restored from a snapshot jumps ahead (CI saw a 10 s jump give a false LOST
// on three links at once). Silence must be measured on the steady clock, so
// that a step forward reports no loss and a step back hides none, in the
// equipment and in the observer alike. The step is made by
// tests/support/realtime_shift.cpp: every reading of CLOCK_REALTIME in this
// process moves, Fast DDS's included; the kernel's clock does not.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <condition_variable>
#include <map>
#include <mutex>
#include <string>

#include "equipment_fixture.hpp"
#include "loss_peer_process.hpp"
#include "mtc/dds/detail/topics.hpp"
#include "mtc/dds/domain_observer.hpp"
#include "realtime_shift.hpp"

namespace mtc::dds::testing {
namespace {

using core::InterfaceType;

constexpr auto kStep = std::chrono::seconds(10);

// Restores the wall clock after each case: a failed assertion leaves early.
class ClockStep : public ::testing::Test {
 protected:
  // The shim is in effect: the library's wall clock moves with a step.
  void SetUp() override {
    const auto before = detail::topics::realtime_ns();
    step(std::chrono::hours(1));
    const auto after = detail::topics::realtime_ns();
    step(-std::chrono::hours(1));
    ASSERT_GE(std::chrono::nanoseconds(after - before), std::chrono::hours(1))
        << "CLOCK_REALTIME did not step: is mtc_test_realtime_shift linked ahead of libc?";
  }
  void TearDown() override { mtc_test_shift_realtime(-mtc_test_realtime_offset()); }
  static void step(std::chrono::nanoseconds by) { mtc_test_shift_realtime(by.count()); }
};

// What an observer saw: heartbeats per device (a clock made of the
// protocol's own events) and every loss it reported.
class ObserverLog : private Guarded {
 public:
  DomainObserverCallbacks callbacks() {
    DomainObserverCallbacks cb;
    cb.on_heartbeat = [this](const ObservedHeartbeat& h) { add([&] { ++beats_[h.device_uuid]; }); };
    cb.on_items_lost = [this](const std::string& device, const std::vector<std::string>&) {
      add([&] { lost_.push_back(device); });
    };
    return cb;
  }
  int beats(const std::string& device) {
    std::lock_guard<std::mutex> lock(mutex_);
    return beats_[device];
  }
  // Until each device has sent `n` more heartbeats than `since` counted.
  bool wait_beats(const std::map<std::string, int>& since, int n) {
    std::unique_lock<std::mutex> lock(mutex_);
    return cv_.wait_for(lock, kTimeout, [&] {
      return std::all_of(since.begin(), since.end(),
                         [&](const auto& d) { return beats_[d.first] >= d.second + n; });
    });
  }
  bool wait_lost(const std::string& device, std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    return cv_.wait_for(lock, timeout, [&] {
      return std::find(lost_.begin(), lost_.end(), device) != lost_.end();
    });
  }
  std::vector<std::string> lost() {
    std::lock_guard<std::mutex> lock(mutex_);
    return lost_;
  }

 private:
  std::map<std::string, int> beats_;
  std::vector<std::string> lost_;
};

EquipmentOptions short_lease(int domain, const std::string& uuid) {
  auto o = options(domain, uuid);
  o.timing.heartbeat = std::chrono::milliseconds(50);
  o.timing.missed_heartbeats = 5;  // lease 250 ms
  return o;
}

DomainObserverOptions observer_options(int domain) {
  auto o = mtc::test::loopback<DomainObserverOptions>();
  o.domain_id = domain;
  return o;
}

std::size_t count_lost(const std::vector<LinkEvent>& links) {
  return static_cast<std::size_t>(std::count_if(
      links.begin(), links.end(), [](const LinkEvent& l) { return l.current == LinkState::Lost; }));
}

// A step forward, then back: each followed at once by a handshake (whose
// steps wake the executors before the next heartbeat could refresh what
// they last heard) and by three leases' worth of heartbeats. Nothing is
// lost, and every handshake completes.
TEST_F(ClockStep, StepsForwardAndBackReportNoLossAndHandshakesComplete) {
  constexpr int kDomain = 156;
  Recorder machine_rec;
  Recorder robot_rec;
  ObserverLog seen;
  DomainObserver observer(observer_options(kDomain), seen.callbacks());
  Equipment machine(short_lease(kDomain, "machine-cs"), machine_rec.callbacks());
  Equipment robot(short_lease(kDomain, "robot-cs"), robot_rec.callbacks());
  machine.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"robot-cs", "mh1"}});
  robot.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"machine-cs", "mh1"}});
  auto& req = machine.add_requester("mh1", Service::MaterialLoad);
  ResponderCallbacks cb;
  cb.on_request = [](Responder& r) { r.complete(); };
  robot.add_responder("mh1", Service::MaterialLoad, cb);
  machine.start();
  robot.start();
  ASSERT_TRUE(machine_rec.wait_link(machine, "mh1", LinkState::Up)) << machine_rec.dump();
  ASSERT_TRUE(robot_rec.wait_link(robot, "mh1", LinkState::Up)) << robot_rec.dump();
  ASSERT_TRUE(machine_rec.wait([&] { return req.counterpart_state() == InteractionState::Ready; }));
  ASSERT_TRUE(seen.wait_beats({{"machine-cs", 0}, {"robot-cs", 0}}, 2));
  RequestOptions wait;
  wait.wait_for_ready = kTimeout;
  ASSERT_EQ(req.request(wait).get().outcome, Outcome::Completed) << machine_rec.dump();

  const auto lease = short_lease(kDomain, "x").timing.lease();
  const int beats_per_lease = static_cast<int>(lease / std::chrono::milliseconds(50));
  for (const auto by : {std::chrono::nanoseconds(kStep), -std::chrono::nanoseconds(kStep)}) {
    const std::map<std::string, int> before{{"machine-cs", seen.beats("machine-cs")},
                                            {"robot-cs", seen.beats("robot-cs")}};
    step(by);
    EXPECT_EQ(req.request(wait).get().outcome, Outcome::Completed) << machine_rec.dump();
    ASSERT_TRUE(seen.wait_beats(before, 3 * beats_per_lease));
  }
  EXPECT_EQ(count_lost(machine_rec.links()), 0U) << machine_rec.dump();
  EXPECT_EQ(count_lost(robot_rec.links()), 0U) << robot_rec.dump();
  EXPECT_TRUE(seen.lost().empty()) << "the observer reported " << seen.lost().size() << " losses";
}

// A counterpart hangs (SIGSTOP), and the wall clock steps back a minute
// right after its last heartbeat: measured on that clock, the silence
// would not start for a minute. Both the equipment and the observer report
// the loss within two leases all the same (steady time; the bound is as
// generous as LossDetection's).
TEST_F(ClockStep, StepBackHidesNoLoss) {
  constexpr int kDomain = 157;
  Recorder rec;
  ObserverLog seen;
  auto o = options(kDomain, "watch-ld", qos::Transport::LoopbackUdp);
  o.timing.missed_heartbeats = 5;  // lease 500 ms, as the peer's
  const auto lease = o.timing.lease();
  auto oo = observer_options(kDomain);
  oo.transport = qos::Transport::LoopbackUdp;
  oo.timing = o.timing;  // its liveliness lease must cover the peer's
  DomainObserver observer(oo, seen.callbacks());
  Equipment watcher(o, rec.callbacks());
  watcher.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"peer-ld", "mh1"}});
  watcher.add_requester("mh1", Service::MaterialLoad);
  watcher.start();
  const pid_t peer = start_loss_peer(kDomain);
  ASSERT_GT(peer, 0);
  if (!rec.wait_link(watcher, "mh1", LinkState::Up) || !seen.wait_beats({{"peer-ld", 0}}, 2)) {
    reap(peer);
    FAIL() << "the peer never came up: " << rec.dump();
  }
  const auto stopped = std::chrono::steady_clock::now();
  kill(peer, SIGSTOP);
  step(-std::chrono::minutes(1));
  const bool equipment_saw = rec.wait_link(watcher, "mh1", LinkState::Lost, 2 * lease);
  const auto equipment_after = std::chrono::steady_clock::now() - stopped;
  const bool observer_saw =
      seen.wait_lost("peer-ld", std::chrono::duration_cast<std::chrono::milliseconds>(
                                    2 * lease - (std::chrono::steady_clock::now() - stopped)));
  reap(peer);
  EXPECT_TRUE(equipment_saw)
      << "no loss after "
      << std::chrono::duration_cast<std::chrono::milliseconds>(equipment_after).count() << " ms:\n"
      << rec.dump();
  EXPECT_TRUE(observer_saw) << "the observer reported no loss of peer-ld";
}

}  // namespace
}  // namespace mtc::dds::testing
