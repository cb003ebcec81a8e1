// The 1.3 profile over DDS (core covers the tables; this runs them through
// the runtime and two participants): the requester returns to READY when
// the responder fails, and a FAIL nobody recovers returns to READY by itself
// after TimeLimits::fail_reset. Domain 47.
#include <gtest/gtest.h>

#include <atomic>

#include "equipment_fixture.hpp"

namespace mtc::dds::testing {
namespace {

using core::InterfaceType;
using core::Notice;
using core::Reason;

TEST(Profile13, RequesterReadyAfterResponderFailAndFailResetsToReady) {
  Recorder cnc_rec;
  Recorder robot_rec;
  auto cnc_options = options(47, "cnc-13");
  auto robot_options = options(47, "robot-13");
  for (auto* o : {&cnc_options, &robot_options}) {
    o->profile = core::Profile::V1_3;
    o->recovery = RecoveryPolicy::Manual;  // only fail_reset may clear a FAIL
  }
  Equipment cnc(cnc_options, cnc_rec.callbacks());
  Equipment robot(robot_options, robot_rec.callbacks());
  cnc.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"robot-13", "mh1"}});
  robot.add_interface({"mh1", InterfaceType::MaterialHandler, "", {"cnc-13", "mh1"}});
  ServiceOptions service_options;
  service_options.limits.fail_reset = 500ms;
  auto& load = cnc.add_requester("mh1", Service::MaterialLoad, service_options);
  std::atomic<int> requests{0};
  ResponderCallbacks cb;
  cb.on_request = [&requests](Responder& r) {
    if (requests.fetch_add(1) == 0) {
      r.fail();  // the first one fails while ACTIVE
    } else {
      r.complete();
    }
  };
  auto& serve = robot.add_responder("mh1", Service::MaterialLoad, cb, service_options);
  cnc.start();
  robot.start();

  RequestOptions wait;
  wait.wait_for_ready = 10s;
  auto first = load.request(wait);
  ASSERT_EQ(first.wait_for(kTimeout), std::future_status::ready);
  EXPECT_EQ(first.get().outcome, Outcome::Failed) << cnc_rec.dump() << robot_rec.dump();
  // 1.3: the request goes back to READY, never FAIL.
  EXPECT_TRUE(cnc_rec.wait_state(load, InteractionState::Ready)) << cnc_rec.dump();
  for (const auto& t : cnc_rec.transitions()) {
    EXPECT_NE(t.step.current, InteractionState::Fail) << cnc_rec.dump();
  }
  // The responder's FAIL: nobody recovers it, fail_reset does.
  EXPECT_TRUE(robot_rec.wait_notice(Notice::Recovered, Reason::FailResetTimeout))
      << robot_rec.dump();
  EXPECT_TRUE(robot_rec.wait_state(serve, InteractionState::Ready)) << robot_rec.dump();
  // And the pair works again.
  auto second = load.request(wait);
  ASSERT_EQ(second.wait_for(kTimeout), std::future_status::ready);
  EXPECT_EQ(second.get().outcome, Outcome::Completed) << cnc_rec.dump() << robot_rec.dump();
}

}  // namespace
}  // namespace mtc::dds::testing
