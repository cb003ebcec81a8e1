// Hostile peers (issue 10): a device on the domain that writes what the
// Part 5 vocabulary or the wire contract forbids, or floods its topic. The
// test process plays that device (RoguePeer) against real `mtc` processes:
// every such sample is reported by name as a protocol violation, never
// crashes the counterpart nor moves it wrongly, and other pairs carry on.
// Over Cyclone DDS (MTC_TEST_MIDDLEWARE=cyclone) a number outside an IDL
// enum never reaches the runtime: Cyclone 0.10's deserializer drops the
// sample, so there is nothing to report and nothing moves.
// Domain ids 190-194 (tools tests, third range; see mtc_fixture.hpp).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <iostream>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "mtc_fixture.hpp"
#include "rogue_peer.hpp"

namespace mtc::test {
namespace {

using core::InteractionState;
constexpr milliseconds kStep{20000};

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// `action_ms` as `mtc respond --action-ms` takes it: a duration per handshake.
std::unique_ptr<ChildProcess> start_machine(int domain, const std::string& device,
                                            const std::string& robot,
                                            const std::string& action_ms = "10") {
  return start_responder(domain,
                         {"--device", device, "--interface", "mh", "--service", "MATERIAL_LOAD",
                          "--counterpart", robot, "--action-ms", action_ms});
}

// One MATERIAL_LOAD handshake driven by the rogue robot against an `mtc
// respond` machine already seen READY; returns the machine's outcome line.
std::optional<std::string> rogue_handshake(RoguePeer& robot, ChildProcess& machine, int n) {
  robot.set_state(InteractionState::Ready);
  robot.set_state(InteractionState::Active);
  if (!robot.wait_counterpart(InteractionState::Complete, kStep)) return std::nullopt;
  robot.set_state(InteractionState::Ready);
  return wait_outcome(machine, n);
}

TEST(HostilePeer, StateOutsideTheVocabularyIsAProtocolViolationByName) {
  constexpr int kDomain = 190;
  // Fast DDS delivers the 7: the machine must still be ACTIVE when it comes,
  // so the first action outlasts the test (a 10 ms one could end first on a
  // slow run, under TSan, and the machine would COMPLETE). Cyclone drops the
  // 7, and the machine completes as if it never came.
  const bool cyclone = test_middleware_is_cyclone();
  auto machine = start_machine(kDomain, "machine-1", "robot-1", cyclone ? "10" : "60000,10");
  RoguePeer robot(kDomain, "robot-1", "mh", core::Service::MaterialLoad, core::SubType::Request,
                  "machine-1");
  robot.set_state(InteractionState::Ready);
  ASSERT_TRUE(robot.wait_counterpart(InteractionState::Ready, kStep)) << machine->transcript();
  robot.set_state(InteractionState::Active);
  ASSERT_TRUE(robot.wait_counterpart(InteractionState::Active, kStep)) << machine->transcript();
  robot.set_raw_state(7);
  if (cyclone) {
    ASSERT_TRUE(robot.wait_counterpart(InteractionState::Complete, kStep)) << machine->transcript();
    robot.set_state(InteractionState::Ready);
    const auto first = wait_outcome(*machine, 1);
    ASSERT_TRUE(first) << machine->transcript();
    EXPECT_EQ(json_field(*first, "result"), "COMPLETE") << machine->transcript();
    EXPECT_FALSE(contains(machine->stderr_text(), "outside its vocabulary"))
        << machine->transcript();
    return;
  }
  // Not taken for UNAVAILABLE (which would be a comms matter): the service
  // fails as Tables 5/6 say for an unknown value, and the report names it.
  ASSERT_TRUE(robot.wait_counterpart(InteractionState::Fail, kStep)) << machine->transcript();
  const auto first = wait_outcome(*machine, 1);
  ASSERT_TRUE(first) << machine->transcript();
  EXPECT_EQ(json_field(*first, "result"), "FAIL");
  EXPECT_TRUE(contains(machine->stderr_text(), "protocol violation: device 'robot-1' item") &&
              contains(machine->stderr_text(), "state 7 is outside its vocabulary"))
      << machine->transcript();
  EXPECT_FALSE(contains(machine->stdout_text(), "peer_lost")) << machine->transcript();

  // The requester follows the FAIL; the next handshake completes.
  robot.set_state(InteractionState::Fail);
  ASSERT_TRUE(robot.wait_counterpart(InteractionState::Ready, kStep)) << machine->transcript();
  const auto second = rogue_handshake(robot, *machine, 2);
  ASSERT_TRUE(second) << machine->transcript();
  EXPECT_EQ(json_field(*second, "result"), "COMPLETE");
}

TEST(HostilePeer, ServiceOutsideTheVocabularyIsReportedAndIgnored) {
  constexpr int kDomain = 191;
  auto machine = start_machine(kDomain, "machine-1", "robot-1");
  RoguePeer robot(kDomain, "robot-1", "mh", core::Service::MaterialLoad, core::SubType::Request,
                  "machine-1");
  robot.set_state(InteractionState::Ready);
  ASSERT_TRUE(robot.wait_counterpart(InteractionState::Ready, kStep)) << machine->transcript();
  // ACTIVE for a service number no edition of Part 5 has: no machine may
  // take it. The valid samples after it (same writer, delivered in order)
  // then run one clean handshake.
  robot.set_raw_service(99);
  robot.set_state(InteractionState::Active);
  // KEEP_LAST 1: the next change of the item could replace this one before
  // it is sent, so wait until the machine has had it (over Cyclone it is
  // dropped on arrival: nothing to wait for).
  const bool cyclone = test_middleware_is_cyclone();
  if (!cyclone) {
    EXPECT_TRUE(machine->wait_for_stderr("carries a service outside the vocabulary", kStep))
        << machine->transcript();
  }
  robot.set_service(core::Service::MaterialLoad);
  const auto outcome = rogue_handshake(robot, *machine, 1);
  ASSERT_TRUE(outcome) << machine->transcript();
  EXPECT_EQ(json_field(*outcome, "result"), "COMPLETE") << machine->transcript();
  EXPECT_EQ(contains(machine->stderr_text(), "device 'robot-1' item") &&
                contains(machine->stderr_text(), "carries a service outside the vocabulary"),
            !cyclone)
      << machine->transcript();
}

TEST(HostilePeer, ChangeNumbersThatLeapOrGoBackAreReportedOnce) {
  constexpr int kDomain = 192;
  auto machine = start_machine(kDomain, "machine-1", "robot-1");
  RoguePeer robot(kDomain, "robot-1", "mh", core::Service::MaterialLoad, core::SubType::Request,
                  "machine-1");
  robot.set_state(InteractionState::Ready);
  ASSERT_TRUE(robot.wait_counterpart(InteractionState::Ready, kStep)) << machine->transcript();
  // The machine has taken a first number of the item (its READY answers on
  // its own, so wait for its view of ours). Each change below then waits for
  // its report: KEEP_LAST 1 could replace it by the next before it is sent.
  ASSERT_TRUE(machine->wait_for_line({"\"side\":\"request\"", "\"state\":\"READY\""}, kStep))
      << machine->transcript();
  robot.set_next_sequence(std::numeric_limits<std::uint64_t>::max() - 8,
                          InteractionState::NotReady);
  ASSERT_TRUE(machine->wait_for_stderr("change number leapt from", kStep)) << machine->transcript();
  robot.set_next_sequence(3, InteractionState::Ready);
  ASSERT_TRUE(machine->wait_for_stderr("change number went back from", kStep))
      << machine->transcript();
  robot.set_next_sequence(2, InteractionState::NotReady);  // again: no second report
  // The values still apply in the order they came: a clean handshake.
  const auto outcome = rogue_handshake(robot, *machine, 1);
  ASSERT_TRUE(outcome) << machine->transcript();
  EXPECT_EQ(json_field(*outcome, "result"), "COMPLETE") << machine->transcript();
  const std::string err = machine->stderr_text();
  EXPECT_TRUE(contains(err, "change number leapt from")) << machine->transcript();
  EXPECT_TRUE(contains(err, "change number went back from")) << machine->transcript();
  EXPECT_EQ(err.find("went back from"), err.rfind("went back from")) << machine->transcript();
}

// A requester whose process exits right after COMPLETE, before its READY
// got out (the vendor example does so once in a while on a loaded machine):
// the responder's handshake is over, and `respond --count 1` exits.
TEST(HostilePeer, RequesterLeavingRightAfterCompleteEndsTheHandshake) {
  constexpr int kDomain = 194;
  auto machine = start_responder(
      kDomain, {"--device", "machine-1", "--interface", "mh", "--service", "MATERIAL_LOAD",
                "--counterpart", "robot-1", "--action-ms", "10", "--count", "1"});
  {
    RoguePeer robot(kDomain, "robot-1", "mh", core::Service::MaterialLoad, core::SubType::Request,
                    "machine-1");
    robot.set_state(InteractionState::Ready);
    robot.set_state(InteractionState::Active);
    ASSERT_TRUE(robot.wait_counterpart(InteractionState::Complete, kStep)) << machine->transcript();
  }  // gone without READY
  const auto outcome = wait_outcome(*machine, 1);
  ASSERT_TRUE(outcome) << machine->transcript();
  EXPECT_EQ(json_field(*outcome, "result"), "COMPLETE");
  EXPECT_EQ(machine->wait_exit(kHandshakeTimeout), 0) << machine->transcript();
}

// Reads the output of children nobody waits on, so that their pipes never
// fill (a child blocked on a full stdout would look like a stuck runtime).
// It consumes no line: what a child printed meanwhile (an outcome the test
// looks for next) is still there for wait_for_line once the drainer stops.
class Drainer {
 public:
  explicit Drainer(std::vector<ChildProcess*> children)
      : children_(std::move(children)), thread_([this] { run(); }) {}
  ~Drainer() { stop(); }
  Drainer(const Drainer&) = delete;
  Drainer& operator=(const Drainer&) = delete;
  void stop() {
    running_ = false;
    if (thread_.joinable()) thread_.join();
  }

 private:
  void run() {
    while (running_) {
      for (auto* child : children_) {
        child->read_for(milliseconds(20));
      }
    }
  }
  std::vector<ChildProcess*> children_;
  std::atomic<bool> running_{true};
  std::thread thread_;
};

// 10,000 changes as fast as the rogue can write them, against one machine,
// while another robot and machine run their handshakes on the same domain.
TEST(HostilePeer, AFloodingPeerLeavesOtherPairsAlone) {
  constexpr int kDomain = 193;
  constexpr int kFlood = 10000;
  constexpr int kHandshakes = 40;
  auto flooded = start_machine(kDomain, "machine-1", "robot-1");
  auto machine = start_machine(kDomain, "machine-2", "robot-2");
  RoguePeer rogue(kDomain, "robot-1", "mh", core::Service::MaterialLoad, core::SubType::Request,
                  "machine-1");
  auto robot = start_mtc(
      "request", kDomain,
      {"--device", "robot-2", "--interface", "mh", "--service", "MATERIAL_LOAD", "--counterpart",
       "machine-2", "--count", std::to_string(kHandshakes), "--timeout", "30s"});
  ASSERT_TRUE(
      robot->wait_for_line({"\"event\":\"outcome\"", "\"handshake\":1,"}, kHandshakeTimeout))
      << robot->transcript();
  Drainer drainer({flooded.get(), machine.get()});
  // The flood runs beside the handshakes (each of which takes longer than
  // writing 10,000 samples takes in total on a quiet machine, so the pair
  // is mid-run throughout).
  std::atomic<long long> flood_ms{-1};
  std::thread flood([&] {
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < kFlood; ++i) {
      rogue.set_state(i % 2 == 0 ? InteractionState::NotReady : InteractionState::Ready);
    }
    flood_ms =
        std::chrono::duration_cast<milliseconds>(std::chrono::steady_clock::now() - start).count();
  });
  const auto exit_code = robot->wait_exit(kHandshakeTimeout * 2);
  flood.join();
  std::cout << "flood: " << kFlood << " changes in " << flood_ms << " ms\n";
  ASSERT_EQ(exit_code, 0) << robot->transcript();
  const auto out = outcomes(*robot);
  ASSERT_EQ(out.size(), static_cast<std::size_t>(kHandshakes)) << robot->transcript();
  for (std::size_t i = 0; i < out.size(); ++i) {
    EXPECT_EQ(out[i].handshake, static_cast<int>(i) + 1);
    EXPECT_EQ(out[i].result, "COMPLETE") << out[i].line;
  }
  // The flooded machine is alive and was moved by nothing but the flood's
  // values: its next handshake with the rogue completes. The drainer reads
  // on until the machine has answered: on a loaded machine it may still be
  // printing the flood's transitions, and with nobody reading, a full pipe
  // would block it before it could answer.
  rogue.set_state(InteractionState::Ready);
  rogue.set_state(InteractionState::Active);
  const bool answered = rogue.wait_counterpart(InteractionState::Complete, kStep);
  rogue.set_state(InteractionState::Ready);
  drainer.stop();
  ASSERT_TRUE(flooded->running()) << flooded->transcript();
  ASSERT_TRUE(answered) << flooded->transcript();
  const auto outcome = wait_outcome(*flooded, 1);
  ASSERT_TRUE(outcome) << flooded->transcript();
  EXPECT_EQ(json_field(*outcome, "result"), "COMPLETE") << flooded->transcript();
  EXPECT_EQ(flooded->stderr_text().find("protocol violation"), std::string::npos)
      << "legal changes are no violation, however many";
}

}  // namespace
}  // namespace mtc::test
