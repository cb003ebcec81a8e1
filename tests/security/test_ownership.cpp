// Without DDS-Security the runtime still checks what it can (issue 11): a
// value or announcement for a device from a participant other than the one
// that announced it is an ownership conflict, reported and ignored, by the
// Equipment (its state machines do not move) and by the DomainObserver (the
// bridge's view does not change).
#include <gtest/gtest.h>

#include <mutex>

#include "../dds/equipment_fixture.hpp"
#include "../dds/raw_peer.hpp"
#include "mtc/dds/domain_observer.hpp"

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
      return contains(d, "ownership conflict") && contains(d, "own-robot");
    });
  })) << cnc_rec.dump();
  EXPECT_EQ(load.counterpart_state(), InteractionState::Ready);
  EXPECT_EQ(load.state(), InteractionState::Ready) << cnc_rec.dump();
  // Reported once, not on every heartbeat of the rogue.
  rogue.set(InteractionState::Complete);
  RequestOptions wait;
  wait.wait_for_ready = 10s;
  EXPECT_EQ(load.request(wait).get().outcome, Outcome::Completed) << cnc_rec.dump();
  std::lock_guard<std::mutex> lock(m);
  EXPECT_EQ(std::count_if(diagnostics.begin(), diagnostics.end(),
                          [](const std::string& d) { return contains(d, "ownership conflict"); }),
            1);
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
  DomainObserverOptions oo;
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

}  // namespace
}  // namespace mtc::dds::testing
