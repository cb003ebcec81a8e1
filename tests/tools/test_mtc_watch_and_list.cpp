// `mtc watch` and `mtc list` against live peers in other processes: the
// watcher sees each transition with its latency, marks a killed device's
// items UNAVAILABLE and shows a graceful end as the device's leaving
// heartbeat; list finds the devices and their interfaces.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <cstdio>
#include <string>

#include "mtc_fixture.hpp"

namespace mtc::test {
namespace {

using Clock = std::chrono::steady_clock;

TEST(Watch, ShowsTransitionsWithLatencyAndUnavailableOnLoss) {
  constexpr int kDomain = 73;
  auto watch = start_mtc("watch", kDomain, {"--transport", "loopback-udp"});
  ASSERT_TRUE(watch->wait_for_line({"\"event\":\"watching\""}, kStartTimeout))
      << watch->transcript();
  auto responder = start_responder(
      kDomain, {"--device", "machine-1", "--interface", "mh", "--service", "MATERIAL_LOAD",
                "--counterpart", "robot-1", "--action-ms", "10", "--transport", "loopback-udp"});
  ASSERT_TRUE(
      watch->wait_for_line({"\"event\":\"device\"", "\"device\":\"machine-1\""}, kStartTimeout))
      << watch->transcript();
  auto requester = start_mtc("request", kDomain,
                             {"--device", "robot-1", "--interface", "mh", "--service",
                              "MATERIAL_LOAD", "--counterpart", "machine-1", "--timeout", "30s"});
  ASSERT_EQ(requester->wait_exit(kHandshakeTimeout), 0) << requester->transcript();

  // The response's path through the handshake, each with a latency.
  for (const char* state : {"ACTIVE", "COMPLETE"}) {
    const auto line =
        watch->wait_for_line({"\"event\":\"value\"", "\"device\":\"machine-1\"",
                              "MATERIAL_LOAD RESPONSE", std::string("\"value\":\"") + state + "\""},
                             kHandshakeTimeout);
    ASSERT_TRUE(line) << watch->transcript();
    const double latency = std::stod(json_field(*line, "latency_ms").value_or("-1"));
    EXPECT_GE(latency, -50.0);  // same host, same clock: small, never far negative
    EXPECT_LT(latency, 5000.0);
  }

  const auto t0 = Clock::now();
  responder->send_signal(SIGKILL);
  ASSERT_TRUE(watch->wait_for_line({"\"device\":\"machine-1\"", "\"value\":\"UNAVAILABLE\""},
                                   milliseconds(5000)))
      << watch->transcript();
  const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  ::testing::Test::RecordProperty("watch_unavailable_after_sigkill_ms", std::to_string(ms));
  std::printf("[ measured ] watch UNAVAILABLE after SIGKILL: %.1f ms\n", ms);

  watch->send_signal(SIGINT);
  EXPECT_EQ(watch->wait_exit(kStartTimeout), 0) << watch->transcript();
}

// A device that ends gracefully says so in its last heartbeat (period 0),
// which a peer whose disposals never arrive still reads. The watcher must
// have matched the heartbeat writer before the end: a leave only reaches the
// readers the device knows, so the test first waits for an ordinary beat
// (a requester that ends right after its handshake can be gone before a
// loaded watcher has discovered it at all).
TEST(Watch, ShowsAGracefulEndAsTheLeavingHeartbeat) {
  constexpr int kDomain = 140;
  auto watch = start_mtc("watch", kDomain, {"--transport", "loopback-udp", "--heartbeats"});
  ASSERT_TRUE(watch->wait_for_line({"\"event\":\"watching\""}, kStartTimeout))
      << watch->transcript();
  auto responder = start_responder(
      kDomain, {"--device", "machine-1", "--interface", "mh", "--service", "MATERIAL_LOAD",
                "--counterpart", "robot-1", "--transport", "loopback-udp"});
  const std::vector<std::string> beat{"\"event\":\"heartbeat\"", "\"device\":\"machine-1\""};
  ASSERT_TRUE(watch->wait_for_line(beat, kStartTimeout)) << watch->transcript();

  responder->send_signal(SIGINT);
  ASSERT_EQ(responder->wait_exit(kStartTimeout), 0) << responder->transcript();
  auto leaving = beat;
  leaving.emplace_back("\"period_ms\":0,");
  EXPECT_TRUE(watch->wait_for_line(leaving, kStartTimeout)) << watch->transcript();

  watch->send_signal(SIGINT);
  EXPECT_EQ(watch->wait_exit(kStartTimeout), 0) << watch->transcript();
}

TEST(Watch, EndsAfterDurationAndResponderPairsWithoutCounterpart) {
  constexpr int kDomain = 79;
  const auto started = Clock::now();
  auto watch = start_mtc("watch", kDomain, {"--duration", "2s"});
  ASSERT_TRUE(watch->wait_for_line({"\"event\":\"watching\""}, kStartTimeout))
      << watch->transcript();
  // No --counterpart: the responder pairs with the first requester of its
  // interface type that shows up.
  auto responder = start_responder(kDomain, {"--device", "machine-1", "--interface", "mh",
                                             "--service", "MATERIAL_UNLOAD", "--action-ms", "0"});
  auto requester = start_mtc("request", kDomain,
                             {"--device", "robot-1", "--interface", "mh", "--service",
                              "MATERIAL_UNLOAD", "--counterpart", "machine-1", "--timeout", "30s"});
  ASSERT_EQ(requester->wait_exit(kHandshakeTimeout), 0) << requester->transcript();
  // The watch stops by itself once its duration has passed, and not before.
  ASSERT_EQ(watch->wait_exit(kStartTimeout), 0) << watch->transcript();
  EXPECT_GE(std::chrono::duration_cast<milliseconds>(Clock::now() - started).count(), 2000);
}

TEST(List, FindsDevicesInterfacesAndCurrentValues) {
  constexpr int kDomain = 74;
  auto responder =
      start_responder(kDomain, {"--device", "machine-1", "--interface", "mh", "--service",
                                "MATERIAL_LOAD,MATERIAL_UNLOAD", "--counterpart", "robot-1"});
  auto list = start_mtc("list", kDomain, {"--expect-devices", "1", "--wait-ms", "20000"});
  ASSERT_EQ(list->wait_exit(kHandshakeTimeout), 0) << list->transcript();
  ASSERT_EQ(list->lines().size(), 1u) << list->transcript();
  const std::string& line = list->lines()[0];
  EXPECT_EQ(json_field(line, "device"), "machine-1") << line;
  EXPECT_NE(line.find("\"id\":\"mh\""), std::string::npos) << line;
  EXPECT_NE(line.find("MATERIAL_UNLOAD"), std::string::npos) << line;
  EXPECT_NE(line.find("\"READY\""), std::string::npos) << line;
}

}  // namespace
}  // namespace mtc::test
