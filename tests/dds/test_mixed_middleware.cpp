// Equipment on Cyclone DDS, alone and beside equipment on Fast DDS
// (EquipmentOptions::middleware; issue 9 section 3): the wire contract is
// the IDL and the QoS, so a robot and a machine complete every service,
// report a failure and take a graceful end as a leave, whichever middleware
// each runs on. Fast DDS with Fast DDS is what every other test runs.
//
// Domain 142 (registry: tests/dds/CMakeLists.txt), the cases one at a time
// (a resource lock), each pair of middlewares in a case of its own.
#include <gtest/gtest.h>

#include <atomic>
#include <condition_variable>
#include <future>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "equipment_fixture.hpp"
#include "mtc/dds/domain_observer.hpp"

namespace mtc::dds::testing {
namespace {

using core::InterfaceType;
using core::Reason;

constexpr int kDomain = 142;

struct Pair {
  Middleware robot;
  Middleware machine;
};

std::string name_of(const ::testing::TestParamInfo<Pair>& info) {
  const auto n = [](Middleware m) { return m == Middleware::FastDds ? "FastDds" : "Cyclone"; };
  return std::string("Robot") + n(info.param.robot) + "Machine" + n(info.param.machine);
}

EquipmentOptions on(Middleware m, const std::string& uuid) {
  auto o = options(kDomain, uuid, qos::Transport::LoopbackUdp);
  o.middleware = m;
  return o;
}

std::vector<LinkEvent> links_to(Recorder& rec, LinkState state) {
  std::vector<LinkEvent> out;
  for (const auto& l : rec.links()) {
    if (l.current == state) out.push_back(l);
  }
  return out;
}

class MixedCell : public ::testing::TestWithParam<Pair> {
 protected:
  // The robot requests, the machine responds, on one material handler.
  std::unique_ptr<Equipment> robot() {
    auto cb = robot_rec_.callbacks();
    // Counted apart: Recorder::wait's predicate runs under its lock.
    cb.on_link = [this, record = cb.on_link](const LinkEvent& e) {
      if (e.current == LinkState::Lost) robot_lost_.fetch_add(1);
      record(e);
    };
    auto e = std::make_unique<Equipment>(on(GetParam().robot, "robot-mx"), cb);
    e->add_interface({"mh", InterfaceType::MaterialHandler, "", {"machine-mx", "mh"}});
    return e;
  }
  std::unique_ptr<Equipment> machine() {
    auto e =
        std::make_unique<Equipment>(on(GetParam().machine, "machine-mx"), machine_rec_.callbacks());
    e->add_interface({"mh", InterfaceType::MaterialHandler, "", {"robot-mx", "mh"}});
    return e;
  }
  std::string dump() { return "robot:\n" + robot_rec_.dump() + "machine:\n" + machine_rec_.dump(); }

  Recorder robot_rec_;
  Recorder machine_rec_;
  std::atomic<int> robot_lost_{0};  // the robot's links that became Lost
};

TEST_P(MixedCell, EveryServiceCompletes) {
  auto m = machine();
  auto r = robot();
  std::vector<Requester*> requesters;
  for (auto service : core::kAllServices) {
    ResponderCallbacks serve;
    serve.on_request = [](Responder& resp) { resp.complete(); };
    m->add_responder("mh", service, serve);
    requesters.push_back(&r->add_requester("mh", service));
  }
  m->start();
  r->start();
  RequestOptions wait;
  wait.wait_for_ready = kTimeout;
  std::vector<std::future<RequestResult>> results;
  results.reserve(requesters.size());
  for (auto* q : requesters) results.push_back(q->request(wait));
  for (std::size_t i = 0; i < results.size(); ++i) {
    SCOPED_TRACE(std::string(core::to_string(core::kAllServices[i])));
    ASSERT_EQ(results[i].wait_for(kTimeout), std::future_status::ready) << dump();
    const auto result = results[i].get();
    EXPECT_EQ(result.outcome, Outcome::Completed) << core::describe(result.reason) << "\n"
                                                  << dump();
  }
}

// Scenario 2: the responder fails while ACTIVE; the requester is told so.
TEST_P(MixedCell, AResponderFailureReachesTheRequester) {
  auto m = machine();
  auto r = robot();
  ResponderCallbacks serve;
  serve.on_request = [](Responder& resp) { resp.fail(); };
  m->add_responder("mh", Service::PartChange, serve);
  auto& change = r->add_requester("mh", Service::PartChange);
  m->start();
  r->start();
  RequestOptions wait;
  wait.wait_for_ready = kTimeout;
  auto result = change.request(wait);
  ASSERT_EQ(result.wait_for(kTimeout), std::future_status::ready) << dump();
  const auto got = result.get();
  EXPECT_EQ(got.outcome, Outcome::Failed) << dump();
  EXPECT_EQ(got.reason, Reason::CounterpartFail) << dump();
}

// The machine ends gracefully: the robot is told a leave, once, and not a
// comms loss (across vendors the leave travels as the leaving heartbeat:
// Cyclone drops Fast DDS's disposals). A new machine that serves the robot
// again is the fence: whatever the first one's end caused came before.
TEST_P(MixedCell, AGracefulEndIsALeave) {
  ResponderCallbacks serve;
  serve.on_request = [](Responder& resp) { resp.complete(); };
  auto m = machine();
  m->add_responder("mh", Service::MaterialLoad, serve);
  auto r = robot();
  auto& load = r->add_requester("mh", Service::MaterialLoad);
  m->start();
  r->start();
  RequestOptions wait;
  wait.wait_for_ready = kTimeout;
  ASSERT_EQ(load.request(wait).get().outcome, Outcome::Completed) << dump();
  m.reset();
  ASSERT_TRUE(robot_rec_.wait([&] { return robot_lost_.load() > 0; })) << dump();

  auto again = machine();
  again->add_responder("mh", Service::MaterialLoad, serve);
  again->start();
  ASSERT_EQ(load.request(wait).get().outcome, Outcome::Completed) << dump();
  const auto lost = links_to(robot_rec_, LinkState::Lost);
  ASSERT_EQ(lost.size(), 1u) << dump();
  EXPECT_EQ(lost[0].cause, "heartbeat leaving") << dump();
}

INSTANTIATE_TEST_SUITE_P(Middlewares, MixedCell,
                         ::testing::Values(Pair{Middleware::Cyclone, Middleware::Cyclone},
                                           Pair{Middleware::Cyclone, Middleware::FastDds},
                                           Pair{Middleware::FastDds, Middleware::Cyclone}),
                         name_of);

// The announcement carries every interface an Equipment may declare, each
// as full as an interface gets: the IDL's bounds are the wire contract, and
// each vendor holds to them (Cyclone refuses to write beyond a bound, and
// drops a sample received beyond it). Before the bounds and the refusal
// matched, an equipment with 100 interfaces could not start on Cyclone
// ("dds_write (device announcement) failed: Bad Parameter"), and its
// announcement from Fast DDS never reached a Cyclone reader. Each writer with
// each reader; Fast DDS with Fast DDS over shared memory (a sample of some
// 500 KB), the others over UDP.
class FullAnnouncement : public ::testing::TestWithParam<Pair> {};

TEST_P(FullAnnouncement, EveryInterfaceAndItemReachesAnObserver) {
  std::mutex mutex;
  std::condition_variable seen;
  std::optional<ObservedDevice> device;
  DomainObserverCallbacks cb;
  cb.on_device = [&](const ObservedDevice& d) {
    if (d.device_uuid != "cell-wide") return;
    std::lock_guard<std::mutex> lock(mutex);
    device = d;
    seen.notify_all();
  };
  const bool fast_only =
      GetParam().robot == Middleware::FastDds && GetParam().machine == Middleware::FastDds;
  const auto transport = fast_only ? qos::Transport::Loopback : qos::Transport::LoopbackUdp;
  auto oo = mtc::test::loopback<DomainObserverOptions>();
  oo.domain_id = kDomain;
  oo.transport = transport;
  oo.middleware = GetParam().machine;
  DomainObserver observer(oo, cb);

  auto eo = on(GetParam().robot, "cell-wide");
  eo.transport = transport;
  Equipment wide(eo);
  // A door and a chuck state, and both roles of every service: 23 items.
  for (std::size_t k = 0; k < kMaxInterfacesPerDevice; ++k) {
    InterfaceConfig full{"if" + std::to_string(k), InterfaceType::Door, "", {}};
    full.publishes_door_state = true;
    full.publishes_chuck_state = true;
    wide.add_interface(full);
    for (const auto service : core::kAllServices) {
      wide.add_requester(full.id, service);
      wide.add_responder(full.id, service, ResponderCallbacks{});
    }
  }
  EXPECT_THROW(wide.add_interface({"one-more", InterfaceType::MaterialHandler, "", {}}),
               ConfigError);
  wide.start();

  std::unique_lock<std::mutex> lock(mutex);
  ASSERT_TRUE(seen.wait_for(lock, kTimeout, [&] { return device.has_value(); }));
  ASSERT_EQ(device->interfaces.size(), kMaxInterfacesPerDevice);
  for (const auto& itf : device->interfaces) {
    EXPECT_EQ(itf.data_items.size(), 3 + 2 * core::kAllServices.size()) << itf.id;
  }
  EXPECT_EQ(device->interfaces.back().id, "if" + std::to_string(kMaxInterfacesPerDevice - 1));
}

INSTANTIATE_TEST_SUITE_P(Middlewares, FullAnnouncement,
                         ::testing::Values(Pair{Middleware::FastDds, Middleware::FastDds},
                                           Pair{Middleware::Cyclone, Middleware::Cyclone},
                                           Pair{Middleware::Cyclone, Middleware::FastDds},
                                           Pair{Middleware::FastDds, Middleware::Cyclone}),
                         name_of);

// A build without the Cyclone backend says so; this one has it.
TEST(Middleware, SpellingsRoundTripAndThisBuildHasBoth) {
  for (const auto m : kAllMiddlewares) {
    EXPECT_EQ(parse_middleware(to_string(m)), m);
    EXPECT_TRUE(middleware_available(m));
  }
  EXPECT_FALSE(parse_middleware("Cyclone"));
  EXPECT_FALSE(parse_middleware(""));
}

// Every tool words its refusal from here, so a misspelling reads the same in
// mtc, mtc-cell and the bridge's configuration.
TEST(Middleware, ChoosingNamesTheSpellingsWhenRefused) {
  for (const auto m : kAllMiddlewares) {
    const auto choice = choose_middleware(to_string(m));
    EXPECT_EQ(choice.middleware, m);
    EXPECT_EQ(choice.problem, "");
  }
  const auto refused = choose_middleware("Cyclone");
  EXPECT_FALSE(refused.middleware);
  EXPECT_EQ(refused.problem, "unknown middleware 'Cyclone' (fastdds or cyclone)");
  EXPECT_NE(missing_backend_message(Middleware::Cyclone).find("-DMTC_CYCLONE=ON"),
            std::string::npos);
}

}  // namespace
}  // namespace mtc::dds::testing
