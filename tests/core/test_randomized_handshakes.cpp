// A requester and a responder driven against each other through a channel
// with random delays (FIFO per direction, as a reliable DDS writer/reader
// pair), random interleavings of application commands, injected failures,
// INTERFACE_STATE toggles and loss of communication. Thousands of seeded,
// deterministic runs; every step checks the safety invariants, and every run
// ends with a settle phase that must bring both sides back to READY or
// NOT_READY (no deadlock) and then complete one more service.
#include <gtest/gtest.h>

#include <cstdio>
#include <deque>
#include <ostream>
#include <random>
#include <sstream>
#include <string>

#include "machine_fixtures.hpp"

namespace mtc::core::testing_support {
namespace {

using S = InteractionState;
using N = Notice;
using namespace std::chrono_literals;

// What a family of runs exercised, so the test cannot pass vacuously.
struct Coverage {
  int completed = 0;  // requester saw COMPLETE and returned to READY
  int failures = 0;   // entries into FAIL
  int recoveries = 0;
  int comms_losses = 0;
  int violations = 0;  // reported ProtocolViolation notices
  int timeouts = 0;
};

struct Message {
  TimePoint deliver_at;
  S value;
};

// One direction of the link.
struct Channel {
  std::deque<Message> queue;
  void send(S value, TimePoint now, Duration delay) {
    TimePoint at = now + delay;
    if (!queue.empty() && queue.back().deliver_at > at) at = queue.back().deliver_at;  // FIFO
    queue.push_back({at, value});
  }
  bool ready(TimePoint now) const { return !queue.empty() && queue.front().deliver_at <= now; }
};

struct RunConfig {
  Profile profile = Profile::V1_6;
  // Chaos: INTERFACE_STATE toggles and applications that react instantly,
  // faster than the network. Genuinely inconsistent views then arise (a late
  // FAIL is indistinguishable from a new one) and are reported as protocol
  // violations; only safety and liveness are asserted. Without chaos the
  // equipment is slower than the network (recovery >= 1 s, delivery
  // <= 300 ms) and two conforming machines must never see a violation.
  bool chaos = false;
  int steps = 300;
};

class Simulation {
 public:
  Simulation(std::uint32_t seed, const RunConfig& cfg, Coverage& cov)
      : cov_(cov),
        rng_(seed),
        cfg_(cfg),
        rq_(Service::MaterialLoad, options()),
        rs_(Service::MaterialLoad, options()) {
    publish_initial();
  }

  // Returns an empty string on success, otherwise what went wrong.
  std::string run() {
    for (int i = 0; i < cfg_.steps && error_.empty(); ++i) random_step(true);
    settle();
    if (error_.empty()) final_service();
    return error_;
  }

 private:
  MachineOptions options() {
    MachineOptions o;
    o.profile = cfg_.profile;
    o.limits.response = pick(0, 3) == 0 ? 0s : 3s;
    o.limits.service = pick(0, 3) == 0 ? 0s : 8s;
    o.limits.completion_ack = pick(0, 1) == 0 ? 0s : 5s;
    o.limits.fail_ack = pick(0, 2) == 0 ? 0s : 12s;
    o.limits.fail_reset = 10s;
    return o;
  }

  int pick(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
  bool chance(int percent) { return pick(1, 100) <= percent; }

  void publish_initial() {
    to_rs_.send(rq_.state(), now_, 0ms);
    to_rq_.send(rs_.state(), now_, 0ms);
  }

  void record(const StepResult& r) {
    std::ostringstream os;
    os << "t=" << std::chrono::duration_cast<std::chrono::milliseconds>(now_ - TimePoint{}).count()
       << "ms " << to_string(r.role) << " " << to_string(r.event) << " " << to_string(r.previous)
       << "->" << to_string(r.current) << " " << to_string(r.notice) << "/" << to_string(r.reason);
    trace_.push_back(os.str());
    if (trace_.size() > 40) trace_.pop_front();
  }

 public:
  std::string trace() const {
    std::string out;
    for (const auto& line : trace_) out += "  " + line + "\n";
    return out;
  }

 private:
  void fail(const std::string& what, const StepResult& r) {
    if (!error_.empty()) return;
    std::ostringstream os;
    os << what << " at t=" << (now_ - TimePoint{}).count() << " [" << to_string(r.role) << " "
       << to_string(r.event) << " " << to_string(r.previous) << "->" << to_string(r.current) << " "
       << to_string(r.notice) << "/" << to_string(r.reason) << "]";
    error_ = os.str();
  }

  // Invariants on every result, then publication of the new value.
  void handle(const StepResult& r) {
    record(r);
    if (r.role == Role::Requester && r.notice == N::Completed) ++cov_.completed;
    if (r.entered_fail()) ++cov_.failures;
    if (r.notice == N::Recovered) ++cov_.recoveries;
    if (r.notice == N::TimedOut) ++cov_.timeouts;
    ServiceMachine& self = r.role == Role::Requester ? static_cast<ServiceMachine&>(rq_)
                                                     : static_cast<ServiceMachine&>(rs_);
    bool& saw_ack = r.role == Role::Requester ? rq_saw_ack_ : rs_saw_ack_;
    if (r.rejected() && r.changed()) fail("rejection changed state", r);
    if (r.role == Role::Requester && r.current == S::Complete) fail("request COMPLETE", r);
    if (r.changed() && r.role == Role::Responder && r.current == S::Active &&
        rs_.counterpart() != S::Active) {
      fail("responder ACTIVE without an ACTIVE request", r);
    }
    if (r.changed() && r.current == S::Complete && r.previous != S::Active) {
      fail("COMPLETE without ACTIVE", r);
    }
    if (r.role == Role::Requester && r.changed() && r.current == S::Active) rq_saw_active_ = false;
    if (r.role == Role::Requester && r.event == Event::SeenActive) rq_saw_active_ = true;
    if (r.role == Role::Requester && r.notice == N::Completed && !rq_saw_active_) {
      fail("requester completed without having seen the response ACTIVE", r);
    }
    if (r.violation()) {
      ++cov_.violations;
      if (!cfg_.chaos) fail("protocol violation between two conforming machines", r);
    }
    // Tables 5/6 ACTIONS: FAIL is left only after the counterpart's
    // acknowledgement, its fail_ack limit, or the 1.3 reset.
    if (r.entered_fail()) saw_ack = self.counterpart() == S::Fail;
    if (self.state() == S::Fail && r.notice == N::FailAcknowledged) saw_ack = true;
    if (self.state() == S::Fail && r.notice == N::TimedOut) saw_ack = true;
    if (r.previous == S::Fail && r.current != S::Fail && r.notice == N::Recovered &&
        cfg_.profile == Profile::V1_6 && !saw_ack) {
      fail("left FAIL without acknowledgement", r);
    }
    if (r.changed() && link_up_) {
      auto& ch = r.role == Role::Requester ? to_rs_ : to_rq_;
      ch.send(r.current, now_, std::chrono::milliseconds(pick(0, 300)));
    }
  }

  void deliver(bool to_requester) {
    auto& ch = to_requester ? to_rq_ : to_rs_;
    const S value = ch.queue.front().value;
    ch.queue.pop_front();
    handle(to_requester ? rq_.on_counterpart(value, now_) : rs_.on_counterpart(value, now_));
  }

  void tick() {
    while (rq_.next_deadline() <= now_) handle(rq_.on_tick(now_));
    while (rs_.next_deadline() <= now_) handle(rs_.on_tick(now_));
  }

  void lose_link() {
    ++cov_.comms_losses;
    link_up_ = false;
    to_rq_.queue.clear();
    to_rs_.queue.clear();
    handle(rq_.on_counterpart_lost(now_));
    handle(rs_.on_counterpart_lost(now_));
  }

  // On reconnection each side reads the other's current value.
  void restore_link() {
    link_up_ = true;
    to_rs_.send(rq_.state(), now_, std::chrono::milliseconds(pick(0, 300)));
    to_rq_.send(rs_.state(), now_, std::chrono::milliseconds(pick(0, 300)));
  }

  // How long the equipment takes to reset after a failure, or to perform
  // the service. Zero in chaos runs.
  Duration reset_time() const { return cfg_.chaos ? 0ms : 1000ms; }
  bool waited(const ServiceMachine& m, Duration d) const { return now_ - m.phase_since() >= d; }

  void requester_app(bool chaotic) {
    const int roll = pick(0, 9);
    if (rq_.state() == S::Fail) {
      if (waited(rq_, reset_time())) handle(rq_.recover(roll < 8 ? S::Ready : S::NotReady, now_));
    } else if (rq_.state() == S::NotReady && !rq_.disabled()) {
      if (waited(rq_, reset_time())) handle(rq_.set_ready(now_));
    } else if (chaotic && roll == 0) {
      handle(rq_.fail(now_));
    } else if (chaotic && roll == 1) {
      handle(rq_.set_not_ready(now_));
    } else if (chaotic) {
      handle(rq_.request(now_));  // rejected unless READY and the response READY
    }
  }

  void responder_app(bool chaotic) {
    const int roll = pick(0, 9);
    switch (rs_.state()) {
      case S::Fail:
        if (waited(rs_, reset_time())) {
          handle(rs_.recover(roll < 8 ? S::Ready : S::NotReady, now_));
        }
        break;
      case S::NotReady:
        if (!rs_.disabled() && waited(rs_, reset_time())) handle(rs_.set_ready(now_));
        break;
      case S::Active:
        if (chaotic && roll == 0) {
          handle(rs_.fail(now_));
        } else if (waited(rs_, std::chrono::milliseconds(cfg_.chaos ? 0 : 400))) {
          handle(rs_.complete(now_));
        }
        break;
      default:
        if (chaotic && roll == 0) {
          handle(rs_.fail(now_));
        } else if (chaotic && roll == 1) {
          handle(rs_.set_not_ready(now_));
        } else {
          handle(rs_.accept(now_));  // rejected unless the request is ACTIVE
        }
    }
  }

  // Everything due is delivered, the two directions interleaved at random.
  void deliver_due() {
    for (;;) {
      const bool a = to_rq_.ready(now_);
      const bool b = to_rs_.ready(now_);
      if (!a && !b) return;
      deliver(a && (!b || chance(50)));
    }
  }

  void random_step(bool chaotic) {
    now_ += std::chrono::milliseconds(pick(0, 150));
    deliver_due();
    tick();
    switch (pick(0, 9)) {
      case 0:
      case 1:
      case 2:
        requester_app(chaotic);
        break;
      case 3:
      case 4:
      case 5:
        responder_app(chaotic);
        break;
      case 6:
        if (!chaotic) break;
        if (link_up_ && chance(5)) {
          lose_link();
        } else if (!link_up_ && chance(20)) {
          restore_link();
        }
        break;
      case 7:
        if (!chaotic || !cfg_.chaos || !chance(10)) break;
        {
          ServiceMachine& m =
              chance(50) ? static_cast<ServiceMachine&>(rq_) : static_cast<ServiceMachine&>(rs_);
          handle(m.disabled() ? m.enable(now_) : m.disable(now_));
        }
        break;
      default:
        break;
    }
  }

  static bool idle(S s) { return s == S::Ready || s == S::NotReady; }

  void settle() {
    if (!link_up_) restore_link();
    for (ServiceMachine* m :
         {static_cast<ServiceMachine*>(&rq_), static_cast<ServiceMachine*>(&rs_)}) {
      if (m->disabled()) handle(m->enable(now_));
    }
    for (int i = 0; i < 4000 && error_.empty(); ++i) {
      random_step(false);
      if (idle(rq_.state()) && idle(rs_.state()) && to_rq_.queue.empty() && to_rs_.queue.empty()) {
        return;
      }
    }
    if (error_.empty()) {
      std::ostringstream os;
      os << "deadlock: requester " << to_string(rq_.state()) << " responder "
         << to_string(rs_.state()) << " queued " << to_rq_.queue.size() << "/"
         << to_rs_.queue.size();
      error_ = os.str();
    }
  }

  // After recovery the pair must still be able to do real work.
  void final_service() {
    for (int i = 0; i < 4000 && error_.empty(); ++i) {
      if (rq_.state() == S::Ready && rs_.state() == S::Ready && rq_.counterpart() == S::Ready &&
          rs_.counterpart() == S::Ready) {
        handle(rq_.request(now_));
        break;
      }
      random_step(false);
    }
    for (int i = 0; i < 4000 && error_.empty(); ++i) {
      random_step(false);
      if (completed_ok()) return;
    }
    if (error_.empty()) error_ = "no service completed after recovery";
  }

  bool completed_ok() const {
    return rq_.state() == S::Ready && rs_.state() == S::Ready && to_rq_.queue.empty() &&
           to_rs_.queue.empty() && rq_.phase_since() > TimePoint{};
  }

  Coverage& cov_;
  std::mt19937 rng_;
  RunConfig cfg_;
  Requester rq_;
  Responder rs_;
  Channel to_rs_;
  Channel to_rq_;
  TimePoint now_{};
  bool link_up_ = true;
  bool rq_saw_active_ = false;
  bool rq_saw_ack_ = false;
  bool rs_saw_ack_ = false;
  std::deque<std::string> trace_;
  std::string error_;
};

struct Family {
  const char* name;
  RunConfig cfg;
  std::uint32_t first_seed;
  int runs;
};

// What gtest lists for the parameter: a stable name, not a byte dump.
void PrintTo(const Family& f, std::ostream* os) {
  *os << f.name;
}

class Randomized : public ::testing::TestWithParam<Family> {};

TEST_P(Randomized, InvariantsHoldAndEveryRunRecovers) {
  const Family& f = GetParam();
  Coverage cov;
  for (int i = 0; i < f.runs; ++i) {
    const std::uint32_t seed = f.first_seed + static_cast<std::uint32_t>(i);
    Simulation sim(seed, f.cfg, cov);
    const std::string error = sim.run();
    ASSERT_TRUE(error.empty()) << f.name << " seed " << seed << ": " << error << "\nlast steps:\n"
                               << sim.trace();
  }
  std::printf(
      "%s: %d runs, %d services completed, %d FAIL entries, %d recoveries, "
      "%d comms losses, %d time limits, %d violations reported\n",
      f.name, f.runs, cov.completed, cov.failures, cov.recoveries, cov.comms_losses, cov.timeouts,
      cov.violations);
  EXPECT_GT(cov.completed, f.runs) << "too few services completed";
  EXPECT_GT(cov.failures, f.runs) << "too few failures injected";
  EXPECT_GT(cov.comms_losses, f.runs / 10) << "too few losses of communication";
  EXPECT_GT(cov.recoveries, f.runs / 2);
  if (!f.cfg.chaos) {
    EXPECT_EQ(cov.violations, 0);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Seeds, Randomized,
    ::testing::Values(Family{"clean_16", {Profile::V1_6, false, 400}, 1000, 1500},
                      Family{"clean_13", {Profile::V1_3, false, 400}, 5000, 1500},
                      Family{"chaos_16", {Profile::V1_6, true, 400}, 9000, 1500},
                      Family{"chaos_13", {Profile::V1_3, true, 400}, 13000, 1500}),
    [](const ::testing::TestParamInfo<Family>& param_info) {
      return std::string(param_info.param.name);
    });

}  // namespace
}  // namespace mtc::core::testing_support

namespace mtc::core::testing_support {
namespace {

// Arbitrary inputs, including values outside every enum, never break a
// machine: every result is well-formed and the Table 5/6 invariants hold.
void fuzz(ServiceMachine& m, std::mt19937& rng, int steps) {
  std::uniform_int_distribution<int> any_event(0, static_cast<int>(kEventCount) + 3);
  std::uniform_int_distribution<int> any_value(0, 8);
  std::uniform_int_distribution<int> kind(0, 3);
  std::uniform_int_distribution<int> dt(0, 3000);
  TimePoint now{};
  for (int i = 0; i < steps; ++i) {
    now += std::chrono::milliseconds(dt(rng));
    StepResult r;
    switch (kind(rng)) {
      case 0:
        r = m.on_counterpart(static_cast<S>(any_value(rng)), now);
        break;
      case 1:
        r = m.on_tick(now);
        break;
      default:
        r = m.step(static_cast<Event>(any_event(rng)), now);
        break;
    }
    ASSERT_EQ(r.current, m.state()) << "step " << i;
    ASSERT_EQ(r.role, m.role());
    ASSERT_LE(static_cast<int>(r.current), static_cast<int>(S::Fail));
    if (r.rejected()) {
      ASSERT_FALSE(r.changed()) << "step " << i;
    }
    if (m.role() == Role::Requester) {
      ASSERT_NE(m.state(), S::Complete);
    }
    if (r.changed() && r.current == S::Active && m.role() == Role::Responder) {
      ASSERT_EQ(m.counterpart(), S::Active);
    }
    if (r.changed() && r.current == S::Complete) {
      ASSERT_EQ(r.previous, S::Active);
    }
    if (m.disabled()) {
      ASSERT_EQ(m.state(), S::NotReady);
    }
    const TimePoint next = m.next_deadline();
    ASSERT_TRUE(next == kNever || next >= m.phase_since());
  }
}

TEST(Fuzz, ArbitraryInputsKeepEveryMachineWellFormed) {
  for (const auto profile : {Profile::V1_6, Profile::V1_3}) {
    for (std::uint32_t seed = 0; seed < 40; ++seed) {
      std::mt19937 rng(seed);
      MachineOptions o;
      o.profile = profile;
      o.counterpart_has_fail = seed % 3 != 0;
      o.limits.response = std::chrono::seconds(seed % 2 != 0 ? 2 : 0);
      o.limits.service = std::chrono::seconds(5);
      o.limits.completion_ack = std::chrono::seconds(seed % 4 != 0 ? 3 : 0);
      o.limits.fail_ack = std::chrono::seconds(seed % 5 != 0 ? 4 : 0);
      Requester rq(Service::OpenDoor, o);
      Responder rs(Service::CloseChuck, o);
      SCOPED_TRACE(::testing::Message() << "seed " << seed);
      fuzz(rq, rng, 2000);
      fuzz(rs, rng, 2000);
    }
  }
}

}  // namespace
}  // namespace mtc::core::testing_support
