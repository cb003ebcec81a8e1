// `mtc --middleware`: processes on Cyclone DDS and on Fast DDS in one cell
// (issue 9 section 3). A handshake runs between a requester on one and a
// responder on the other, and a watcher on either middleware sees a device
// on the other one go UNAVAILABLE when it is killed: comms loss crosses
// vendors too. Domains 143-144 (registry: mtc_fixture.hpp).
#include <gtest/gtest.h>

#include <csignal>
#include <string>
#include <vector>

#include "mtc_fixture.hpp"

namespace mtc::test {
namespace {

struct Sides {
  const char* responder;
  const char* others;  // the requester's and the watcher's
  int domain;
};

class MixedMiddleware : public ::testing::TestWithParam<Sides> {};

std::string name_of(const ::testing::TestParamInfo<Sides>& info) {
  return std::string("Responder") + (info.param.responder[0] == 'c' ? "Cyclone" : "FastDds");
}

TEST_P(MixedMiddleware, HandshakesCompleteAndAKilledResponderIsLost) {
  const auto& sides = GetParam();
  auto watch = start_mtc("watch", sides.domain,
                         {"--transport", "loopback-udp", "--middleware", sides.others});
  ASSERT_TRUE(watch->wait_for_line({"\"event\":\"watching\""}, kStartTimeout))
      << watch->transcript();
  auto responder = start_responder(
      sides.domain, {"--device", "machine-1", "--interface", "mh", "--service", "MATERIAL_LOAD",
                     "--counterpart", "robot-1", "--action-ms", "10", "--transport", "loopback-udp",
                     "--middleware", sides.responder});
  // The handshakes take a few milliseconds: the watcher must know the
  // responder before they start to see them live.
  ASSERT_TRUE(
      watch->wait_for_line({"\"event\":\"device\"", "\"device\":\"machine-1\""}, kStartTimeout))
      << watch->transcript();
  auto requester =
      start_mtc("request", sides.domain,
                {"--device", "robot-1", "--interface", "mh", "--service", "MATERIAL_LOAD",
                 "--counterpart", "machine-1", "--count", "3", "--timeout", "30s", "--transport",
                 "loopback-udp", "--middleware", sides.others});
  ASSERT_EQ(requester->wait_exit(kHandshakeTimeout), 0)
      << requester->transcript() << responder->transcript();
  const auto out = outcomes(*requester);
  ASSERT_EQ(out.size(), 3u) << requester->transcript();
  for (const auto& o : out) EXPECT_EQ(o.result, "COMPLETE") << o.line;
  // Each names the middleware it runs on in its start line.
  const auto names = [](const char* middleware) {
    return std::string("\"middleware\":\"") + middleware + "\"";
  };
  EXPECT_NE(responder->transcript().find(names(sides.responder)), std::string::npos)
      << responder->transcript();
  EXPECT_NE(requester->transcript().find(names(sides.others)), std::string::npos)
      << requester->transcript();

  // The watcher saw the last handshake live; then the kill.
  ASSERT_TRUE(watch->wait_for_line({"\"event\":\"value\"", "\"device\":\"machine-1\"",
                                    "MATERIAL_LOAD RESPONSE", "\"value\":\"COMPLETE\""},
                                   kHandshakeTimeout))
      << watch->transcript();
  responder->send_signal(SIGKILL);
  EXPECT_TRUE(watch->wait_for_line({"\"device\":\"machine-1\"", "\"value\":\"UNAVAILABLE\""},
                                   kStartTimeout))
      << watch->transcript();
  watch->send_signal(SIGINT);
  EXPECT_EQ(watch->wait_exit(kStartTimeout), 0) << watch->transcript();
}

INSTANTIATE_TEST_SUITE_P(Cell, MixedMiddleware,
                         ::testing::Values(Sides{"cyclone", "fastdds", 143},
                                           Sides{"fastdds", "cyclone", 144}),
                         name_of);

TEST(MiddlewareOption, AnUnknownMiddlewareIsAUsageError) {
  auto p = start_mtc("list", 0, {"--middleware", "opensplice"});
  EXPECT_EQ(p->wait_exit(kStartTimeout), 2) << p->transcript();
  EXPECT_NE(
      p->stderr_text().find("--middleware: unknown middleware 'opensplice' (fastdds or cyclone)"),
      std::string::npos)
      << p->transcript();
}

}  // namespace
}  // namespace mtc::test
