// mtc-test-loss-peer: the counterpart process of the tests that kill, stop
// and restart a device (test_loss_detection, test_process_faults). Runs one
// Equipment with interface mh1 and one MATERIAL_LOAD service on the given
// domain until a signal ends it; dies with its parent.
//
// Without options it is the responder "peer-ld" paired with "watch-ld", over
// UDP loopback, heartbeat 100 ms x 5 (test_loss_detection). The options make
// it either side of a handshake that freezes itself (raise(SIGSTOP), the
// whole process at once) at one step of Part 5 Table 1, so that a test can
// kill or stop it exactly there:
//   --role requester|responder  which side (responder: accepts, then
//                               completes, on its own, one step at a time)
//   --uuid U, --counterpart U   this device and the device it pairs with
//   --transport NAME            loopback (UDP + shared memory) or loopback-udp
//   --heartbeat-ms N            heartbeat period; the lease is 5 of them
//   --requests N                requester: requests to make, one after the
//                               other (each waits up to 20 s for READY)
//   --hold-at-step K            1-8: freeze at step K as this side sees it
//                               (the hold_if calls below); 0: never
//   --start-on-sigusr1          requester: make the first request when
//                               SIGUSR1 comes; responder: step 1 is then
//                               (freeze idle, before the request arrives).
//                               The test sends it once it sees this peer:
//                               a process frozen before the other side has
//                               discovered it would never be seen at all.
//   --middleware fastdds|cyclone  which DDS; without it MTC_TEST_MIDDLEWARE
//                               (tests/support/transport.hpp) chooses, as for
//                               the test that starts it: Cyclone in .ci/run's
//                               cyclone phase
//   --inline-steps              EquipmentOptions::inline_steps instead of
//                               steps_on_executor (test_inline_writes: what
//                               a step wrote while its callback holds)
//   --pack-callback-writes      and EquipmentOptions::pack_callback_writes
//   --hold-in-request N         responder: hold no earlier than in the Nth
//                               request (0, the default: at the first
//                               chance), so that a test can complete
//                               handshakes first
// It prints one line per event, flushed: "started", "link <state> <cause>",
// "transition <prev> <cur> <notice> <reason>", "value <state>",
// "outcome <n> <outcome> <reason>", "abort <reason>", and
// "hold <k> <realtime ns>" just before it stops itself, "resumed" after.
//
// usage: mtc-test-loss-peer DOMAIN [options]
#include <pthread.h>
#include <signal.h>
#include <sys/prctl.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>

#include "mtc/dds/detail/topics.hpp"
#include "mtc/dds/equipment.hpp"
#include "mtc/dds/middleware.hpp"
#include "transport.hpp"

namespace {

using mtc::core::InteractionState;
namespace core = mtc::core;
namespace dds = mtc::dds;

struct PeerOptions {
  int domain = 0;
  bool requester = false;
  std::string uuid = "peer-ld";
  std::string counterpart = "watch-ld";
  mtc::qos::Transport transport = mtc::qos::Transport::LoopbackUdp;
  int heartbeat_ms = 100;
  int requests = 1;
  int hold_at_step = 0;
  int hold_in_request = 0;  // responder: hold from this request on (0: any)
  bool start_on_signal = false;
  bool inline_steps = false;
  bool pack_callback_writes = false;
  std::optional<dds::Middleware> middleware;  // none: the test middleware
};

constexpr const char* kUsage =
    "usage: mtc-test-loss-peer DOMAIN [--role requester|responder] [--uuid U]\n"
    "         [--counterpart U] [--transport loopback|loopback-udp] [--heartbeat-ms N]\n"
    "         [--requests N] [--hold-at-step K] [--start-on-sigusr1]\n"
    "         [--middleware fastdds|cyclone] [--inline-steps]\n"
    "         [--pack-callback-writes] [--hold-in-request N]\n";

bool parse_int(const std::string& text, int low, int high, int& out) {
  char* end = nullptr;
  const long value = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || value < low || value > high) return false;
  out = static_cast<int>(value);
  return true;
}

// One option and its value; false on anything it does not know.
bool parse_option(const std::string& name, const std::string& value, PeerOptions& o) {
  if (name == "--role" && (value == "requester" || value == "responder")) {
    o.requester = value == "requester";
    return true;
  }
  if (name == "--uuid" || name == "--counterpart") {
    (name == "--uuid" ? o.uuid : o.counterpart) = value;
    return !value.empty();
  }
  if (name == "--transport") {
    const auto t = mtc::qos::parse_transport(value);
    if (!t || (*t != mtc::qos::Transport::Loopback && *t != mtc::qos::Transport::LoopbackUdp)) {
      return false;
    }
    o.transport = *t;
    return true;
  }
  if (name == "--middleware") {
    const auto m = dds::parse_middleware(value);
    if (m) o.middleware = *m;
    return m.has_value();
  }
  if (name == "--heartbeat-ms") return parse_int(value, 10, 10000, o.heartbeat_ms);
  if (name == "--requests") return parse_int(value, 0, 1000, o.requests);
  if (name == "--hold-at-step") return parse_int(value, 0, 8, o.hold_at_step);
  if (name == "--hold-in-request") return parse_int(value, 0, 1000, o.hold_in_request);
  return false;
}

// The option that takes no value named `name`; nullptr if it is none.
bool* flag_option(const std::string& name, PeerOptions& o) {
  if (name == "--start-on-sigusr1") return &o.start_on_signal;
  if (name == "--inline-steps") return &o.inline_steps;
  if (name == "--pack-callback-writes") return &o.pack_callback_writes;
  return nullptr;
}

// Exit code: 0 parsed, 1 --help, 2 usage error.
int parse(int argc, char** argv, PeerOptions& o) {
  if (argc >= 2 && std::string(argv[1]) == "--help") return 1;
  if (argc < 2 || !parse_int(argv[1], 0, 232, o.domain)) return 2;
  for (int i = 2; i < argc; i += 2) {
    if (bool* flag = flag_option(argv[i], o)) {
      *flag = true;
      --i;
      continue;
    }
    if (i + 1 >= argc || !parse_option(argv[i], argv[i + 1], o)) return 2;
  }
  return 0;
}

class Peer {
 public:
  explicit Peer(const PeerOptions& o) : options_(o), equipment_(equipment_options(o), callbacks()) {
    equipment_.add_interface(
        {"mh1", core::InterfaceType::MaterialHandler, "", {o.counterpart, "mh1"}});
    if (o.requester) {
      requester_ = &equipment_.add_requester("mh1", core::Service::MaterialLoad);
      return;
    }
    dds::ResponderCallbacks rc;
    rc.on_request = [this](dds::Responder& r) {
      ++requests_seen_;
      hold_if(2);
      r.accept();
    };
    // Part 5: the responder resets its partial actions, then leaves FAIL.
    rc.on_abort = [this](dds::Responder& r, core::Reason why) {
      say("abort " + std::string(core::to_string(why)));
      r.recover();
    };
    dds::ServiceOptions so;
    so.auto_accept = false;  // accepting is step 3, apart from step 2
    responder_ = &equipment_.add_responder("mh1", core::Service::MaterialLoad, rc, so);
  }

  void start() {
    equipment_.start();
    say("started");
    if (!options_.start_on_signal) go();
  }

  // The first request, or (responder) the freeze of step 1.
  void go() {
    if (requester_ == nullptr) {
      if (options_.start_on_signal) hold_if(1);
      return;
    }
    if (options_.requests > 0) request_next();
  }

 private:
  static dds::EquipmentOptions equipment_options(const PeerOptions& o) {
    dds::EquipmentOptions e;
    e.domain_id = o.domain;
    e.device_uuid = o.uuid;
    e.transport = o.transport;
    e.middleware =
        o.middleware.value_or(mtc::test::test_middleware_is_cyclone() ? dds::Middleware::Cyclone
                                                                      : dds::Middleware::FastDds);
    e.timing.heartbeat = std::chrono::milliseconds(o.heartbeat_ms);
    e.timing.missed_heartbeats = 5;
    // The hold points freeze this side between a step and what it causes:
    // they need callbacks that run with the step, not after it (the
    // default's reports). The survivor, the side under test, keeps the
    // default.
    e.steps_on_executor = true;
    e.inline_steps = o.inline_steps;  // callbacks with the step all the same
    e.pack_callback_writes = o.pack_callback_writes;
    return e;
  }

  dds::EquipmentCallbacks callbacks() {
    dds::EquipmentCallbacks cb;
    cb.on_link = [this](const dds::LinkEvent& e) {
      say("link " + std::string(dds::to_string(e.current)) + " " + e.cause);
    };
    cb.on_transition = [this](const dds::TransitionEvent& e) { on_transition(e); };
    cb.on_counterpart_value = [this](const core::ObservedValue& v) { on_value(v); };
    return cb;
  }

  // The hold points that follow this side's own steps.
  void on_transition(const dds::TransitionEvent& e) {
    const auto& s = e.step;
    say("transition " + std::string(core::to_string(s.previous)) + " " +
        std::string(core::to_string(s.current)) + " " + std::string(core::to_string(s.notice)) +
        " " + std::string(core::to_string(s.reason)));
    if (!s.changed()) return;
    if (requester_ != nullptr) {
      if (s.current == InteractionState::Active) hold_if(1);  // step 1: request ACTIVE
      if (s.previous == InteractionState::Active && s.notice == core::Notice::Completed) {
        hold_if(6);  // step 6: request back to READY
      }
      return;
    }
    if (s.current == InteractionState::Active) {
      hold_if(3);  // step 3: response ACTIVE
      responder_->complete();
    }
    if (s.current == InteractionState::Complete) hold_if(4);  // step 4: response COMPLETE
    if (s.previous == InteractionState::Complete && s.current == InteractionState::Ready) {
      hold_if(8);  // step 8: response back to READY
    }
  }

  // The hold points where this side has seen the counterpart's step but not
  // acted on it yet (this callback runs before the transitions it causes).
  void on_value(const core::ObservedValue& v) {
    const auto state = v.state.interaction();
    if (!state || !v.sub_type) return;
    say("value " + std::string(core::to_string(*state)) + (v.redelivered ? " again" : ""));
    if (requester_ != nullptr) {
      if (*state == InteractionState::Complete && requester_->state() == InteractionState::Active) {
        hold_if(5);  // step 5: the request detects COMPLETE
      }
      return;
    }
    if (*state != InteractionState::Ready) return;
    if (responder_->state() == InteractionState::Complete) hold_if(7);  // step 7
  }

  void request_next() {
    dds::RequestOptions wait;
    wait.wait_for_ready = std::chrono::seconds(20);
    requester_->request(wait, [this](const dds::RequestResult& r) {
      const int n = ++requests_done_;
      say("outcome " + std::to_string(n) + " " + std::string(dds::to_string(r.outcome)) + " " +
          std::string(core::to_string(r.reason)));
      // Part 5: the requester resets its partial actions, then leaves FAIL.
      if (requester_->state() == InteractionState::Fail) requester_->recover();
      if (n < options_.requests) request_next();
    });
  }

  // Freezes the whole process once, at hold point `step`.
  void hold_if(int step) {
    if (step != options_.hold_at_step) return;
    if (responder_ != nullptr && requests_seen_ < options_.hold_in_request) return;
    if (held_.exchange(true)) return;
    say("hold " + std::to_string(step) + " " +
        std::to_string(mtc::dds::detail::topics::realtime_ns()));
    raise(SIGSTOP);
    say("resumed");
  }

  void say(const std::string& line) {
    std::lock_guard<std::mutex> lock(out_mutex_);
    std::cout << line << std::endl;  // flushed: the test reads it at once
  }

  PeerOptions options_;
  dds::Equipment equipment_;
  dds::Requester* requester_ = nullptr;
  dds::Responder* responder_ = nullptr;
  std::atomic<bool> held_{false};
  int requests_done_ = 0;              // executor thread only
  std::atomic<int> requests_seen_{0};  // responder: on_request calls
  std::mutex out_mutex_;
};

}  // namespace

int main(int argc, char** argv) {
  PeerOptions options;
  switch (parse(argc, argv, options)) {
    case 1:
      std::cout << kUsage;
      return 0;
    case 2:
      std::cerr << kUsage;
      return 2;
    default:
      break;
  }
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  // SIGUSR1 is taken here, by sigwait: blocked before any thread exists, so
  // every thread inherits the mask.
  sigset_t go_signal;
  sigemptyset(&go_signal);
  sigaddset(&go_signal, SIGUSR1);
  pthread_sigmask(SIG_BLOCK, &go_signal, nullptr);
  Peer peer(options);
  peer.start();
  for (;;) {  // until another signal ends the process
    int received = 0;
    if (sigwait(&go_signal, &received) == 0 && received == SIGUSR1) peer.go();
  }
}
