// Comms loss of a counterpart process, as it happens on a shop floor: the
// process is SIGKILLed (crash) or SIGSTOPped (hung), then restarted under
// the same uuid. Every loss is detected within two leases (a generous bound
// for 2 busy cores; mtc-bench-detection measures the distribution against
// lease + 25 %), and nothing else is ever reported lost: not the healthy
// link, not a restarted peer when its dead predecessor's participant expires.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <condition_variable>
#include <initializer_list>
#include <iostream>
#include <memory>
#include <mutex>
#include <streambuf>
#include <string>
#include <utility>

#include "equipment_fixture.hpp"
#include "loss_peer_process.hpp"
#include "mtc/dds/detail/topics.hpp"

namespace mtc::dds::testing {
namespace {

constexpr int kDomain = 58;

TEST(LossDetection, KilledOrStoppedPeerIsLostWithinTwoLeasesAndNothingElse) {
  Recorder rec;
  auto o = options(kDomain, "watch-ld", qos::Transport::LoopbackUdp);
  o.timing.missed_heartbeats = 5;  // lease 500 ms, as the peer's
  const auto lease = o.timing.lease();
  Equipment watcher(o, rec.callbacks());
  watcher.add_interface({"mh1", core::InterfaceType::MaterialHandler, "", {"peer-ld", "mh1"}});
  watcher.add_requester("mh1", Service::MaterialLoad);
  watcher.start();

  constexpr int kRounds = 6;
  std::size_t losses = 0;
  for (int round = 0; round < kRounds; ++round) {
    const int signal = round % 2 == 0 ? SIGKILL : SIGSTOP;
    const pid_t peer = start_loss_peer(kDomain);
    ASSERT_GT(peer, 0);
    ASSERT_TRUE(rec.wait_link(watcher, "mh1", LinkState::Up)) << rec.dump();
    // Its heartbeats are arriving (the loss cue is their absence). No
    // callback reports a heartbeat: poll the counter.
    const auto beats = watcher.traffic().heartbeats_received;
    bool beating = false;
    for (int i = 0; i < 300 && !beating; ++i) {
      beating = rec.wait([&] { return watcher.traffic().heartbeats_received >= beats + 2; }, 50ms);
    }
    ASSERT_TRUE(beating);
    const auto killed_ns = detail::topics::realtime_ns();
    kill(peer, signal);
    ASSERT_TRUE(rec.wait_link(watcher, "mh1", LinkState::Lost)) << rec.dump();
    reap(peer);
    const auto links = rec.links();
    ASSERT_EQ(links.back().current, LinkState::Lost);
    const auto detection = std::chrono::nanoseconds(links.back().time_ns - killed_ns);
    RecordProperty("detection_ms_round_" + std::to_string(round),
                   static_cast<int>(detection.count() / 1000000));
    EXPECT_LT(detection, 2 * lease) << (signal == SIGKILL ? "SIGKILL" : "SIGSTOP") << " round "
                                    << round << ": " << links.back().cause;
    ++losses;
  }
  // The last peer's participant expires (2 s lease) with the link already
  // lost; before that, each restart met its predecessor's expiry.
  const auto links = rec.links();
  const auto lost = std::count_if(links.begin(), links.end(),
                                  [](const LinkEvent& l) { return l.current == LinkState::Lost; });
  EXPECT_EQ(static_cast<std::size_t>(lost), losses) << rec.dump();
}

// std::cerr into a string, for what a thread other than the test's writes
// there; restores std::cerr when it goes. Make it before the equipments
// whose threads write, so that it outlives them.
class CerrCapture : public std::streambuf {
 public:
  CerrCapture() : previous_(std::cerr.rdbuf(this)) {}
  ~CerrCapture() override { std::cerr.rdbuf(previous_); }
  CerrCapture(const CerrCapture&) = delete;
  CerrCapture& operator=(const CerrCapture&) = delete;
  std::string text() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return text_;
  }
  // Whether every needle was written within `timeout`.
  bool wait_for(std::initializer_list<const char*> needles, std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    return written_.wait_for(lock, timeout, [&] {
      return std::all_of(needles.begin(), needles.end(),
                         [&](const char* n) { return text_.find(n) != std::string::npos; });
    });
  }

 protected:
  int_type overflow(int_type c) override {
    if (c != traits_type::eof()) {
      const char ch = traits_type::to_char_type(c);
      xsputn(&ch, 1);
    }
    return c;
  }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      text_.append(s, static_cast<std::size_t>(n));
    }
    written_.notify_all();
    return n;
  }

 private:
  std::streambuf* previous_;
  mutable std::mutex mutex_;
  std::condition_variable written_;
  std::string text_;
};

// A hung executor (here: a posted task that blocks) must not be hidden by
// the heartbeat thread: the watchdog withholds the heartbeat once the
// executor has made no progress for a lease, the peer declares the link
// lost, and when the executor moves again the heartbeat and the link return.
// The hung process says so on stderr at once (its diagnostics callback must
// wait for the executor).
TEST(LossDetection, HungExecutorStopsItsHeartbeat) {
  CerrCapture cerr;
  Recorder cnc_rec;
  Recorder robot_rec;
  std::mutex diag_mutex;
  std::string diagnostics;
  auto robot_cb = robot_rec.callbacks();
  robot_cb.on_diagnostic = [&](const std::string& text) {
    {
      std::lock_guard<std::mutex> lock(diag_mutex);
      diagnostics += text + "\n";
    }
    robot_rec.notify();
  };
  Equipment cnc(options(59, "cnc-hang"), cnc_rec.callbacks());
  Equipment robot(options(59, "robot-hang"), robot_cb);
  cnc.add_interface({"mh1", core::InterfaceType::MaterialHandler, "", {"robot-hang", "mh1"}});
  robot.add_interface({"mh1", core::InterfaceType::MaterialHandler, "", {"cnc-hang", "mh1"}});
  cnc.start();
  robot.start();
  ASSERT_TRUE(cnc_rec.wait_link(cnc, "mh1", LinkState::Up)) << cnc_rec.dump();

  // The robot's executor blocks in a task until released (also when an
  // assertion ends the test early: the destructor joins that executor).
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
  // Owns one release: copying it would release twice, so it cannot be copied.
  struct ReleaseOnExit {
    explicit ReleaseOnExit(std::shared_ptr<Gate> g) : gate(std::move(g)) {}
    ReleaseOnExit(const ReleaseOnExit&) = delete;
    ReleaseOnExit& operator=(const ReleaseOnExit&) = delete;
    ~ReleaseOnExit() { gate->release(); }
    std::shared_ptr<Gate> gate;
  } release_on_exit{gate};
  robot.post([gate] {
    std::unique_lock<std::mutex> lock(gate->m);
    gate->cv.wait(lock, [&] { return gate->open; });
  });
  ASSERT_TRUE(cnc_rec.wait_link(cnc, "mh1", LinkState::Lost)) << cnc_rec.dump();
  // Still hung: only stderr can have said it.
  EXPECT_TRUE(cerr.wait_for({"robot-hang: heartbeat group 0 withheld", "said at once"}, kTimeout))
      << cerr.text();
  const auto lost = cnc_rec.links().back();
  // A real silence (the loss rule: a lease less half a heartbeat).
  const auto& t = robot.options().timing;
  EXPECT_GE(lost.silence, t.lease() - t.heartbeat / 2) << lost.cause;
  gate->release();
  ASSERT_TRUE(cnc_rec.wait_link(cnc, "mh1", LinkState::Up)) << cnc_rec.dump();
  EXPECT_EQ(cnc_rec.links().back().cause, "heartbeat resumed");
  // The robot says why, once its executor runs again.
  const auto said = [&](const char* word) {
    std::lock_guard<std::mutex> lock(diag_mutex);
    return diagnostics.find(word) != std::string::npos;
  };
  EXPECT_TRUE(robot_rec.wait([&] { return said("withheld") && said("resumed"); })) << diagnostics;
}

}  // namespace
}  // namespace mtc::dds::testing
