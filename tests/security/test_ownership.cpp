// Without DDS-Security the runtime still checks what it can (issue 11): a
// value or announcement for a device from a participant other than the one
// that announced it is an ownership conflict, reported and ignored, by the
// Equipment (its state machines do not move) and by the DomainObserver (the
// bridge's view does not change).
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <utility>

#include "../dds/equipment_fixture.hpp"
#include "../dds/raw_peer.hpp"
#include "mtc/dds/domain_observer.hpp"
#include "transport.hpp"

namespace mtc::dds::testing {
namespace {

using core::InterfaceType;
using core::SubType;

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// Domain 135: a rogue participant posing as the robot while the real one runs.
TEST(Ownership, EquipmentIgnoresValuesFromAParticipantThatDidNotAnnounceTheDevice) {
  Recorder cnc_rec;
  std::vector<std::string> diagnostics;
  std::mutex m;
  auto cb = cnc_rec.callbacks();
  cb.on_diagnostic = [&](const std::string& d) {
    {
      std::lock_guard<std::mutex> lock(m);
      diagnostics.push_back(d);
    }
    cnc_rec.notify();
  };
  Equipment cnc(options(135, "own-cnc"), cb);
  Equipment robot(options(135, "own-robot"));
  cnc.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"own-robot", "mh1"}});
  robot.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"own-cnc", "mh1"}});
  auto& load = cnc.add_requester("mh1", core::Service::MaterialLoad);
  ResponderCallbacks rcb;
  rcb.on_request = [](Responder& r) { r.complete(); };
  robot.add_responder("mh1", core::Service::MaterialLoad, rcb);
  cnc.start();
  robot.start();
  ASSERT_TRUE(cnc_rec.wait([&] { return load.counterpart_state() == InteractionState::Ready; }));

  // The rogue writes the robot's RESPONSE ACTIVE (and re-publishes it every
  // 100 ms): unchecked, the cnc would see an ACTIVE it never asked for.
  RawPeer rogue(135, "own-robot", SubType::Response, core::Service::MaterialLoad);
  rogue.set(InteractionState::Active);
  ASSERT_TRUE(cnc_rec.wait([&] {
    std::lock_guard<std::mutex> lock(m);
    return std::any_of(diagnostics.begin(), diagnostics.end(), [](const std::string& d) {
      return contains(d, "ownership conflict: a value") && contains(d, "own-robot");
    });
  })) << cnc_rec.dump();
  EXPECT_EQ(load.counterpart_state(), InteractionState::Ready);
  EXPECT_EQ(load.state(), InteractionState::Ready) << cnc_rec.dump();
  // Reported once per kind, not on every sample of the rogue.
  rogue.set(InteractionState::Complete);
  RequestOptions wait;
  wait.wait_for_ready = 10s;
  EXPECT_EQ(load.request(wait).get().outcome, Outcome::Completed) << cnc_rec.dump();
  std::lock_guard<std::mutex> lock(m);
  const auto conflicts = [&](const char* kind) {
    return std::count_if(diagnostics.begin(), diagnostics.end(), [&](const std::string& d) {
      return contains(d, std::string("ownership conflict: ") + kind);
    });
  };
  EXPECT_EQ(conflicts("a value"), 1);
  EXPECT_LE(conflicts("a heartbeat"), 1);
  EXPECT_EQ(conflicts(""), conflicts("a value") + conflicts("a heartbeat"));
}

// Domain 136: an impostor Equipment announcing the same uuid, and a rogue
// writing its items: the observer keeps the real device and its values.
TEST(Ownership, ObserverKeepsTheDeviceOfTheParticipantThatAnnouncedItFirst) {
  std::mutex m;
  std::condition_variable cv;
  std::vector<std::string> reports;
  bool active_seen = false;
  bool robot_seen = false;
  DomainObserverCallbacks ocb;
  ocb.on_value = [&](const ObservedValue& v) {
    std::lock_guard<std::mutex> lock(m);
    robot_seen = robot_seen || v.device_uuid == "own-robot-2";
    active_seen = active_seen || (v.device_uuid == "own-robot-2" &&
                                  v.state.interaction() == InteractionState::Active);
    cv.notify_all();
  };
  ocb.on_ownership_conflict = [&](const std::string&, const std::string& report) {
    std::lock_guard<std::mutex> lock(m);
    reports.push_back(report);
    cv.notify_all();
  };
  auto oo = mtc::test::loopback<DomainObserverOptions>();
  oo.domain_id = 136;
  DomainObserver observer(oo, ocb);

  auto real_options = options(136, "own-robot-2");
  real_options.device_name = "real";
  Equipment robot(real_options);
  robot.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"own-cnc-2", "mh1"}});
  ResponderCallbacks rcb;
  robot.add_responder("mh1", core::Service::MaterialLoad, rcb);
  robot.start();
  {
    std::unique_lock<std::mutex> lock(m);
    ASSERT_TRUE(cv.wait_for(lock, kTimeout, [&] { return robot_seen; }));
  }

  auto impostor_options = options(136, "own-robot-2");
  impostor_options.device_name = "impostor";
  Equipment impostor(impostor_options);
  impostor.add_interface({"arm", InterfaceType::MaterialHandler, "", {"own-cnc-2", "arm"}});
  impostor.start();
  RawPeer rogue(136, "own-robot-2", SubType::Response, core::Service::MaterialLoad);
  rogue.set(InteractionState::Active);
  {
    std::unique_lock<std::mutex> lock(m);
    ASSERT_TRUE(cv.wait_for(lock, kTimeout, [&] {
      const auto announcement = std::any_of(reports.begin(), reports.end(), [](auto& r) {
        return contains(r, "an announcement for device own-robot-2");
      });
      const auto value = std::any_of(reports.begin(), reports.end(), [](auto& r) {
        return contains(r, "a value for device own-robot-2");
      });
      return announcement && value;
    })) << ::testing::PrintToString(reports);
    EXPECT_FALSE(active_seen);
  }
  const auto devices = observer.devices();
  ASSERT_EQ(devices.size(), 1u);
  EXPECT_EQ(devices[0].name, "real");
}

// Domain 137: a device restarted under the same uuid while its old process
// still has a participant. The new one's announcement is a conflict while
// the old owner is alive; once the old one's heartbeats stop (its executor
// hangs: the watchdog withholds them) it takes over, and what it wrote
// while refused (its announcement, its values: written once) is replayed,
// to the observer and to the counterpart, whose link comes back up.
TEST(Ownership, ARestartedDeviceTakesOverOnceTheOldOwnerIsLost) {
  std::mutex m;
  std::condition_variable cv;
  std::vector<std::string> reports;
  std::vector<std::string> names;  // announcements of own-robot-3, in order
  int values_after_takeover = 0;
  DomainObserverCallbacks ocb;
  ocb.on_device = [&](const ObservedDevice& d) {
    std::lock_guard<std::mutex> lock(m);
    if (d.device_uuid == "own-robot-3") names.push_back(d.name);
    cv.notify_all();
  };
  ocb.on_value = [&](const ObservedValue& v) {
    std::lock_guard<std::mutex> lock(m);
    if (v.device_uuid == "own-robot-3" && !names.empty() && names.back() == "new") {
      ++values_after_takeover;
    }
    cv.notify_all();
  };
  ocb.on_ownership_conflict = [&](const std::string&, const std::string& report) {
    std::lock_guard<std::mutex> lock(m);
    reports.push_back(report);
    cv.notify_all();
  };
  auto oo = mtc::test::loopback<DomainObserverOptions>();
  oo.domain_id = 137;
  DomainObserver observer(oo, ocb);

  // Whether the cnc lost the old robot: noted from the callback, since a
  // Recorder::wait predicate runs under the recorder's lock (links() would
  // take it again and deadlock).
  Recorder cnc_rec;
  std::atomic<bool> cnc_lost_old{false};
  auto cnc_cb = cnc_rec.callbacks();
  cnc_cb.on_link = [&cnc_lost_old, record = cnc_cb.on_link](const LinkEvent& e) {
    if (e.current == LinkState::Lost) cnc_lost_old = true;
    record(e);
  };
  Equipment cnc(options(137, "own-cnc-3"), cnc_cb);
  cnc.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"own-robot-3", "mh1"}});
  cnc.add_requester("mh1", core::Service::MaterialLoad);
  cnc.start();

  const auto robot = [](const char* name) {
    auto o = options(137, "own-robot-3");
    o.device_name = name;
    auto e = std::make_unique<Equipment>(o);
    e->add_interface({"mh1", InterfaceType::MaterialHandler, "", {"own-cnc-3", "mh1"}});
    e->add_responder("mh1", core::Service::MaterialLoad, ResponderCallbacks{});
    e->start();
    return e;
  };
  auto old_robot = robot("old");
  ASSERT_TRUE(cnc_rec.wait_link(cnc, "mh1", LinkState::Up)) << cnc_rec.dump();
  {
    std::unique_lock<std::mutex> lock(m);
    ASSERT_TRUE(cv.wait_for(lock, kTimeout, [&] { return !names.empty(); }));
  }
  auto new_robot = robot("new");
  {
    std::unique_lock<std::mutex> lock(m);
    ASSERT_TRUE(cv.wait_for(lock, kTimeout, [&] {
      return std::any_of(reports.begin(), reports.end(), [](auto& r) {
        return contains(r, "an announcement for device own-robot-3");
      });
    })) << ::testing::PrintToString(reports);
    EXPECT_EQ(names, std::vector<std::string>{"old"});
  }
  const auto robot_name = [&] {
    for (const auto& d : observer.devices()) {
      if (d.device_uuid == "own-robot-3") return d.name;
    }
    return std::string();
  };
  EXPECT_EQ(robot_name(), "old");
  EXPECT_EQ(cnc.link_state("mh1"), LinkState::Up);

  // The old process hangs: its heartbeats stop, its participant stays.
  struct Gate {
    std::mutex m;
    std::condition_variable cv;
    bool open = false;
    void release() {
      {
        std::lock_guard<std::mutex> lock(m);
        open = true;
      }
      cv.notify_all();
    }
  };
  auto gate = std::make_shared<Gate>();
  struct ReleaseOnExit {
    explicit ReleaseOnExit(std::shared_ptr<Gate> g) : gate(std::move(g)) {}
    ~ReleaseOnExit() { gate->release(); }
    ReleaseOnExit(const ReleaseOnExit&) = delete;  // releases once
    ReleaseOnExit& operator=(const ReleaseOnExit&) = delete;
    std::shared_ptr<Gate> gate;
  } release_on_exit{gate};
  old_robot->post([gate] {
    std::unique_lock<std::mutex> lock(gate->m);
    gate->cv.wait(lock, [&] { return gate->open; });
  });
  {
    std::unique_lock<std::mutex> lock(m);
    ASSERT_TRUE(cv.wait_for(
        lock, kTimeout,
        [&] { return !names.empty() && names.back() == "new" && values_after_takeover > 0; }))
        << ::testing::PrintToString(names) << " values after: " << values_after_takeover;
  }
  EXPECT_EQ(robot_name(), "new");
  // The counterpart lost the old one and pairs on with the new one, whose
  // values it had refused.
  EXPECT_TRUE(cnc_rec.wait([&] {
    return cnc_lost_old.load() && cnc.link_state("mh1") == LinkState::Up;
  })) << cnc_rec.dump();
}

}  // namespace
}  // namespace mtc::dds::testing
