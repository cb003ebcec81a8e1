// mtc-test-step-party: one side of a MATERIAL_LOAD handshake across hosts,
// for the cable-pull test (tests/multihost/multihost_cell.sh). It uses the
// Network transport (on Fast DDS: its built-in transports) and can hold at one
// point of Part 5 Table 1 so the test pulls the cable exactly there:
//   1 requester, before request()             (step 1 is written while cut off)
//   2 responder, request ACTIVE received       (step 2 is detected while cut off)
//   3 responder, request detected, not accepted (step 3 is written while cut off)
//   4 responder, ACTIVE written, not complete  (step 4 is written while cut off)
//   5 requester, COMPLETE received             (steps 5-6 happen while cut off)
//   6 requester, back at READY (step 6 written) (step 6 may not cross)
//   7 responder, request READY received        (steps 7-8 happen while cut off)
//   8 requester, response READY received       (handshake over, idle cut)
// At its hold point it prints "WAIT HOLD <n>" and waits for the line "go" on
// GO_FIFO before going on; the requester also waits for "begin" ("WAIT
// BEGIN") once paired, before its first handshake. It prints "SEEN <state>"
// for every counterpart REQUEST/RESPONSE value. Every line it prints carries
// CLOCK_REALTIME ns.
// The requester runs one handshake, waits for FAIL and then READY with the
// link up, runs a second handshake and exits 0 if that one completes. The
// responder serves until SIGINT/SIGTERM.
//
// usage: mtc-test-step-party requester|responder DOMAIN DEVICE COUNTERPART HOLD GO_FIFO
// [MIDDLEWARE]
//   HOLD 0 = no hold; the hold point must belong to the given role.
//   MIDDLEWARE fastdds (the default) or cyclone: the cable pulled between
//   vendors (issue 9 section 3).
#include <signal.h>
#include <sys/prctl.h>

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <iostream>
#include <mutex>
#include <optional>
#include <string>

#include "mtc/dds/equipment.hpp"
#include "mtc/dds/middleware.hpp"

namespace {

using mtc::core::InteractionState;
namespace dds = mtc::dds;

std::int64_t now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}

std::mutex out_mutex;
void say(const std::string& line) {
  std::lock_guard<std::mutex> lock(out_mutex);
  std::printf("%s %lld\n", line.c_str(), static_cast<long long>(now_ns()));
  std::fflush(stdout);
}

// The one hold of this run: fires once, at its point, then never again.
class Hold {
 public:
  Hold(int point, std::string fifo) : point_(point), fifo_(std::move(fifo)) {}
  // The line `word` from the FIFO: the test's "go on". Opening blocks until
  // the test opens it for writing; an open that meets the close of an
  // earlier writer reads end-of-file at once, so read until the word comes
  // (an empty read once let a hold go before the cable was pulled).
  void wait_for_test(const std::string& what, const std::string& word) {
    say("WAIT " + what);
    for (;;) {
      std::ifstream go(fifo_);
      if (!go.is_open()) {
        say("NO_FIFO " + fifo_);  // the test is gone: go on rather than spin
        return;
      }
      std::string line;
      while (std::getline(go, line)) {
        if (line == word) return;
      }
    }
  }
  void at(int point) {
    if (point != point_ || done_) return;
    done_ = true;
    wait_for_test("HOLD " + std::to_string(point), "go");
    say("GO " + std::to_string(point));
  }

 private:
  int point_;
  std::string fifo_;
  bool done_ = false;
};

// Own state and link, for the requester's waits.
struct Watch {
  std::mutex m;
  std::condition_variable cv;
  InteractionState state = InteractionState::Unavailable;
  bool failed = false;
  bool link_up = false;
};

dds::EquipmentOptions options(int domain, const std::string& device, dds::Middleware middleware) {
  dds::EquipmentOptions o;
  o.domain_id = domain;
  o.middleware = middleware;
  o.device_uuid = device;
  o.transport = mtc::qos::Transport::Network;  // explicitly: the cell spans hosts
  o.timing.missed_heartbeats = 10;             // 1 s lease: a loaded 2-core CI machine
  o.recovery = dds::RecoveryPolicy::Always;    // every FAIL of the pull clears itself
  return o;
}

dds::EquipmentCallbacks callbacks(Watch& watch, Hold& hold, bool requester) {
  dds::EquipmentCallbacks cb;
  cb.on_transition = [&watch, &hold, requester](const dds::TransitionEvent& e) {
    if (e.step.previous == e.step.current) return;
    say(std::string("STATE ") + std::string(mtc::core::to_string(e.step.current)));
    {
      std::lock_guard<std::mutex> lock(watch.m);
      watch.state = e.step.current;
      watch.failed = watch.failed || e.step.current == InteractionState::Fail;
    }
    watch.cv.notify_all();
    if (requester && e.step.notice == mtc::core::Notice::Completed) hold.at(6);
  };
  cb.on_diagnostic = [](const std::string& text) { say("DIAG " + text); };
  cb.on_link = [&watch](const dds::LinkEvent& e) {
    const auto silence = std::chrono::duration_cast<std::chrono::milliseconds>(e.silence);
    say(std::string("LINK ") + std::string(dds::to_string(e.current)) + " " +
        std::to_string(silence.count()));
    {
      std::lock_guard<std::mutex> lock(watch.m);
      watch.link_up = e.current == dds::LinkState::Up;
    }
    watch.cv.notify_all();
  };
  // Only values that arrive mid-handshake count (the READY seen at pairing
  // does not): `busy` is set by ACTIVE (responder) or COMPLETE (requester).
  cb.on_counterpart_value = [&hold, requester,
                             busy = false](const mtc::core::ObservedValue& v) mutable {
    const auto s = v.state.interaction();
    if (!s) return;
    // multihost_cell.sh waits for SEEN READY on both sides (why: there).
    say(std::string("SEEN ") + std::string(mtc::core::to_string(*s)) +
        (v.redelivered ? " redelivered" : ""));
    if (v.redelivered) return;
    if (!requester && *s == InteractionState::Active) {
      busy = true;
      hold.at(2);
    }
    if (requester && *s == InteractionState::Complete) {
      busy = true;
      hold.at(5);
    }
    if (busy && *s == InteractionState::Ready) hold.at(requester ? 8 : 7);
  };
  return cb;
}

int run_requester(dds::Equipment& eq, Watch& watch, Hold& hold) {
  auto& load = *eq.requester("mh", mtc::core::Service::MaterialLoad);
  const dds::RequestOptions wait{std::chrono::seconds(15)};
  {
    // Paired first, so that a pull at step 1 cuts a handshake, not discovery.
    std::unique_lock<std::mutex> lock(watch.m);
    if (!watch.cv.wait_for(lock, std::chrono::seconds(30), [&] { return watch.link_up; })) {
      say("NO_LINK");
      return 1;
    }
  }
  // The test lets us begin once the bridge knows both devices, so that its
  // stream holds every transition of this run.
  hold.wait_for_test("BEGIN", "begin");
  hold.at(1);
  const auto first = load.request(wait).get();
  say(std::string("RESULT1 ") + std::string(dds::to_string(first.outcome)));
  {
    // The pull fails both sides; Always recovery brings this side back to
    // READY once the link is up again, with no restart.
    std::unique_lock<std::mutex> lock(watch.m);
    if (!watch.cv.wait_for(lock, std::chrono::seconds(30), [&] { return watch.failed; })) {
      say("NO_FAIL");
      return 1;
    }
    if (!watch.cv.wait_for(lock, std::chrono::seconds(20), [&] {
          return watch.link_up && watch.state == InteractionState::Ready;
        })) {
      say("NO_RECOVERY");
      return 1;
    }
  }
  say("RECOVERED");
  const auto second = load.request(wait).get();
  say(std::string("RESULT2 ") + std::string(dds::to_string(second.outcome)));
  return second.outcome == dds::Outcome::Completed ? 0 : 1;
}

int run_responder(dds::Equipment& eq, Hold& hold) {
  (void)eq;
  (void)hold;
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  int sig = 0;
  sigwait(&set, &sig);
  say("STOP");
  return 0;
}

// TEXT as a whole decimal number from LOW to HIGH, else nothing: atoi would
// turn a typo into 0, a valid domain and "no hold".
std::optional<int> number_in(const char* text, long low, long high) {
  char* end = nullptr;
  const long value = std::strtol(text, &end, 10);
  if (end == text || *end != '\0' || value < low || value > high) return std::nullopt;
  return static_cast<int>(value);
}

int usage(std::ostream& out, int code) {
  out << "usage: mtc-test-step-party requester|responder DOMAIN DEVICE COUNTERPART HOLD GO_FIFO "
         "[MIDDLEWARE]\n"
         "  One side of MATERIAL_LOAD over the Network transport, holding at Table 1\n"
         "  point HOLD (1-8, 0 = none) until the line \"go\" is read from GO_FIFO.\n"
         "  MIDDLEWARE: fastdds (default) or cyclone.\n";
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && std::string(argv[1]) == "--help") return usage(std::cout, 0);
  if (argc != 7 && argc != 8) return usage(std::cerr, 2);
  const std::string role = argv[1];
  if (role != "requester" && role != "responder") return usage(std::cerr, 2);
  const bool requester = role == "requester";
  const auto domain = number_in(argv[2], 0, 232);
  const auto point = number_in(argv[5], 0, 8);
  if (!domain || !point) return usage(std::cerr, 2);
  const auto middleware = dds::choose_middleware(argc == 8 ? argv[7] : "fastdds");
  if (!middleware.middleware) {
    std::cerr << "mtc-test-step-party: " << middleware.problem << "\n";
    return 2;
  }
  prctl(PR_SET_PDEATHSIG, SIGKILL);  // dies with the test that started it
  // Signals go to sigwait (responder) rather than killing the process.
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &set, nullptr);

  Watch watch;
  Hold hold(*point, argv[6]);
  dds::Equipment eq(options(*domain, argv[3], *middleware.middleware),
                    callbacks(watch, hold, requester));
  eq.add_interface({"mh", mtc::core::InterfaceType::MaterialHandler, "", {argv[4], "mh"}});
  if (requester) {
    eq.add_requester("mh", mtc::core::Service::MaterialLoad);
  } else {
    dds::ServiceOptions so;
    so.auto_accept = false;
    dds::ResponderCallbacks rc;
    rc.on_request = [&eq, &hold](dds::Responder& r) {
      hold.at(3);
      r.accept();
      // Queued behind the accept: runs once ACTIVE is written.
      eq.post([&hold, &r] {
        hold.at(4);
        r.complete();
      });
    };
    eq.add_responder("mh", mtc::core::Service::MaterialLoad, rc, so);
  }
  eq.start();
  say("STARTED");
  return requester ? run_requester(eq, watch, hold) : run_responder(eq, hold);
}
