// What a step wrote, while a callback of that step runs (issue 9):
// EquipmentOptions::pack_callback_writes lets inline_steps' callbacks, which
// run on the middleware's thread and promise never to block, hold the step's
// writes until they return, so that they leave with what the callbacks wrote.
// Over Cyclone DDS, which holds a writer's samples until they are flushed, a
// responder's ACTIVE then leaves in one message with the COMPLETE its
// callback wrote. Without the option the ACTIVE leaves before the callback
// runs; Fast DDS sends every write at once either way.
//
// The responder runs in a child process (mtc-test-loss-peer --inline-steps).
// One handshake first, so that nothing of the pairing is still being
// written (another thread's write of the same writer would send what a step
// holds); in the second the responder freezes itself (SIGSTOP) inside the
// callback that follows its ACTIVE (hold point 3) and completes once
// continued. While it is frozen, this process (the requester) sees the
// ACTIVE, except over Cyclone DDS with the option; there it arrives only
// after SIGCONT.
#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "equipment_fixture.hpp"
#include "mtc/dds/detail/topics.hpp"

namespace mtc::dds::testing {
namespace {

using mtc::test::ChildProcess;

// One domain per case: ctest runs the cases in parallel (the Cyclone ones
// below: 175, 176).
constexpr int kFastDdsDomain = 159;
constexpr int kHeartbeatMs = 200;  // a lease of 1 s: the freeze below is far shorter
// How long the frozen responder is watched for an ACTIVE that must not come
// (Cyclone DDS): over loopback a sent sample arrives in well under 1 ms.
constexpr std::chrono::milliseconds kFrozenWindow{300};

// The requester's step that saw the response ACTIVE, from events[from] on;
// nullptr before it.
const TransitionEvent* seen_active(const std::vector<TransitionEvent>& events, std::size_t from) {
  const auto start = events.begin() + static_cast<std::ptrdiff_t>(std::min(from, events.size()));
  const auto it = std::find_if(start, events.end(), [](const TransitionEvent& e) {
    return e.step.event == core::Event::SeenActive;
  });
  return it == events.end() ? nullptr : &*it;
}

enum class Writes { AtOnce, Packed };  // the peer's pack_callback_writes

// The responder "resp-<tag>", paired with "req-<tag>", held in its second request.
std::vector<std::string> peer_args(int domain, Middleware middleware, Writes writes,
                                   const std::string& tag) {
  std::vector<std::string> args = {MTC_LOSS_PEER_PATH,
                                   std::to_string(domain),
                                   "--role",
                                   "responder",
                                   "--uuid",
                                   "resp-" + tag,
                                   "--counterpart",
                                   "req-" + tag,
                                   "--transport",
                                   "loopback-udp",
                                   "--heartbeat-ms",
                                   std::to_string(kHeartbeatMs),
                                   "--hold-at-step",
                                   "3",
                                   "--hold-in-request",
                                   "2",
                                   "--middleware",
                                   std::string(to_string(middleware)),
                                   "--inline-steps"};
  if (writes == Writes::Packed) args.emplace_back("--pack-callback-writes");
  return args;
}

void run_case(int domain, Middleware middleware, Writes writes, const std::string& tag) {
  const std::string self = "req-" + tag;
  const std::string peer_uuid = "resp-" + tag;
  ChildProcess peer(peer_args(domain, middleware, writes, tag));
  Recorder rec;
  auto o = options(domain, self, qos::Transport::LoopbackUdp);
  o.middleware = middleware;
  o.timing.heartbeat = std::chrono::milliseconds(kHeartbeatMs);
  o.timing.missed_heartbeats = 5;
  Equipment cnc(o, rec.callbacks());
  cnc.add_interface({"mh1", core::InterfaceType::MaterialHandler, "", {peer_uuid, "mh1"}});
  auto& req = cnc.add_requester("mh1", Service::MaterialLoad);
  cnc.start();
  RequestOptions wait;
  wait.wait_for_ready = 20s;
  ASSERT_EQ(req.request(wait).get().outcome, Outcome::Completed) << rec.dump();
  ASSERT_TRUE(rec.wait([&] { return req.counterpart_state() == InteractionState::Ready; }));
  const auto before = rec.transitions().size();
  auto result = req.request(wait);

  ASSERT_TRUE(peer.wait_for_line({"hold 3"}, kTimeout)) << peer.transcript() << rec.dump();
  ASSERT_TRUE(peer.wait_stopped()) << peer.transcript();
  const bool held = writes == Writes::Packed && middleware == Middleware::Cyclone;
  const bool seen_while_frozen =
      rec.wait([&] { return req.counterpart_state() == InteractionState::Active; },
               held ? kFrozenWindow : kTimeout);
  const auto continued_ns = detail::topics::realtime_ns();
  peer.send_signal(SIGCONT);
  if (held) {
    EXPECT_FALSE(seen_while_frozen) << "the ACTIVE left before its step's callback returned\n"
                                    << rec.dump();
  } else {
    EXPECT_TRUE(seen_while_frozen) << "the ACTIVE was due before the callback\n" << rec.dump();
  }

  ASSERT_EQ(result.wait_for(kTimeout), std::future_status::ready) << rec.dump();
  EXPECT_EQ(result.get().outcome, Outcome::Completed) << rec.dump();
  const auto events = rec.transitions();
  const auto* active = seen_active(events, before);
  ASSERT_NE(active, nullptr) << rec.dump();
  ASSERT_NE(active->trigger_receive_time_ns, 0);
  if (held) {
    EXPECT_GT(active->trigger_receive_time_ns, continued_ns);
  } else {
    EXPECT_LT(active->trigger_receive_time_ns, continued_ns);
  }
}

TEST(InlineWrites, FastDdsSendsTheActiveBeforeTheCallbackReturns) {
  run_case(kFastDdsDomain, Middleware::FastDds, Writes::Packed, "iwf");
}

TEST(InlineWrites, PackingNeedsInlineSteps) {
  auto o = options(kFastDdsDomain, "iw-config");
  o.pack_callback_writes = true;
  EXPECT_THROW(Equipment(o, EquipmentCallbacks{}), ConfigError);
  o.inline_steps = true;
  EXPECT_NO_THROW(Equipment(o, EquipmentCallbacks{}));
}

#ifdef MTC_TEST_WITH_CYCLONE  // an MTC_CYCLONE build
constexpr int kCycloneDomain = 175;
constexpr int kCyclonePackedDomain = 176;

TEST(InlineWrites, CycloneSendsTheActiveBeforeTheCallbackByDefault) {
  run_case(kCycloneDomain, Middleware::Cyclone, Writes::AtOnce, "iwc");
}

TEST(InlineWrites, CyclonePacksTheActiveWithWhatTheCallbackWrote) {
  run_case(kCyclonePackedDomain, Middleware::Cyclone, Writes::Packed, "iwp");
}
#endif

}  // namespace
}  // namespace mtc::dds::testing
