#include "request_runner.hpp"

#include <algorithm>
#include <cmath>

namespace mtc::cli {

namespace {
using core::InteractionState;
using Clock = std::chrono::steady_clock;

bool idle(InteractionState s) {
  return s == InteractionState::Ready || s == InteractionState::NotReady;
}
}  // namespace

RequestRunner::RequestRunner(RequestConfig config, Context& context, EquipmentLink& link,
                             EventQueue& events)
    : config_(std::move(config)),
      context_(context),
      link_(link),
      events_(events),
      service_(config_.equipment.services.front()),
      trace_(context.out, config_.equipment.common.json, core::Role::Requester) {}

bool RequestRunner::next_event(TimePoint deadline, LinkEvent& event) {
  if (context_.shutdown.requested()) {
    return false;
  }
  auto e = events_.pop_until(deadline);
  if (!e) {
    return false;
  }
  event = *e;
  const bool interface_wide = event.kind == LinkEvent::Kind::CounterpartLost ||
                              event.kind == LinkEvent::Kind::CounterpartRestored ||
                              !event.detail.empty();
  if (event.service != service_ && !interface_wide) {
    return true;
  }
  switch (event.kind) {
    case LinkEvent::Kind::OwnState:
      if (event.state == own_) {
        break;
      }
      own_ = event.state;
      if (own_ == InteractionState::Fail) {
        failed_at_ = Clock::now();
      }
      trace_.transition(true, event);
      break;
    case LinkEvent::Kind::CounterpartState:
      if (event.state == peer_) {
        break;
      }
      peer_ = event.state;
      trace_.transition(false, event);
      break;
    case LinkEvent::Kind::CounterpartLost:
      peer_lost_ = true;
      peer_ = InteractionState::Unavailable;
      trace_.note("peer_lost", event.detail);
      break;
    case LinkEvent::Kind::CounterpartRestored:
      peer_lost_ = false;
      trace_.note("peer_restored", config_.equipment.counterpart);
      break;
    case LinkEvent::Kind::RequestDone:
      done_ = event.result;
      break;
    case LinkEvent::Kind::Notice:
    case LinkEvent::Kind::Excluded:
    case LinkEvent::Kind::Readmitted:
      on_notice(event);
      break;
    case LinkEvent::Kind::RequestObserved:
    case LinkEvent::Kind::Aborted:
      break;
  }
  if (event.reason != core::Reason::None && event.notice != core::Notice::Rejected) {
    last_reason_ = event.reason;
  }
  return true;
}

// A diagnostic; or the responder paired with another requester, or with us
// (or nobody) again.
void RequestRunner::on_notice(const LinkEvent& event) {
  if (event.kind == LinkEvent::Kind::Notice) {
    if (!event.detail.empty()) {
      context_.err.line("mtc request: " + event.detail);
    }
    return;
  }
  if (event.kind == LinkEvent::Kind::Readmitted) {
    excluded_.clear();
    trace_.note("readmitted", event.detail);
    return;
  }
  // detail: "robot-2/mh: machine-1/mh is paired with robot-1/mh"
  const auto colon = event.detail.find(": ");
  excluded_ = colon == std::string::npos ? event.detail : event.detail.substr(colon + 2);
  trace_.note("excluded", event.detail);
  context_.err.line("mtc request: " + event.detail);
}

Result RequestRunner::wait_until_ready(TimePoint deadline) {
  if (config_.equipment.disabled) {
    return Result::NotReady;  // our own request stays NOT_READY while DISABLED
  }
  LinkEvent e;
  while (!(own_ == InteractionState::Ready && peer_ == InteractionState::Ready)) {
    if (!excluded_.empty()) {
      return Result::Excluded;
    }
    if (own_ == InteractionState::Fail) {
      try_recover();
    }
    if (!next_event(deadline, e)) {
      if (context_.shutdown.requested()) {
        return Result::Interrupted;
      }
      if (Clock::now() >= deadline) {
        return peer_ == InteractionState::NotReady ? Result::NotReady : Result::Timeout;
      }
    }
  }
  return Result::Complete;
}

void RequestRunner::inject(const FailDecision& decision) {
  const auto refused = link_.fail(service_);
  trace_.note("inject", "request -> FAIL at " + std::string(to_string(decision.step)) +
                            (refused ? " refused: " + *refused : ""));
}

Result RequestRunner::handshake(TimePoint deadline) {
  const FailDecision decision = config_.fail_plan.decide(trace_.number());
  done_.reset();
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
  trace_.restart_clock();
  link_.request(service_, std::max(left, std::chrono::milliseconds(0)));
  bool injected = false;
  LinkEvent e;
  while (true) {
    if (done_) {
      return *done_;
    }
    if (decision.fails() && !injected && peer_ == InteractionState::Active) {
      inject(decision);
      injected = true;
      continue;
    }
    if (!next_event(deadline, e)) {
      if (context_.shutdown.requested()) {
        return Result::Interrupted;
      }
      if (Clock::now() >= deadline) {
        link_.fail(service_);  // giving up is a requester failure (Table 5, FAIL condition 1)
        return Result::Timeout;
      }
    }
  }
}

void RequestRunner::try_recover() {
  // recover() is refused until the responder acknowledged our FAIL or the
  // fail-ack time limit passed; retried on every event and at that limit.
  // Never while the responder is gone: scenario 6 wants both sides to meet
  // again in FAIL, not to assume the other is still READY.
  if (own_ != InteractionState::Fail || peer_lost_) {
    return;
  }
  link_.recover(service_);
}

bool RequestRunner::close_cycle(TimePoint deadline, bool last) {
  LinkEvent e;
  while (!(idle(own_) && idle(peer_) && !peer_lost_)) {
    // After the last outcome a vanished responder (e.g. `respond --count`
    // exiting) leaves nothing to wait for.
    if (peer_lost_ && last) {
      trace_.note("closed", "responder gone after the last handshake");
      return false;
    }
    if (own_ == InteractionState::Fail) {
      try_recover();
    }
    auto wake = deadline;
    const auto retry =
        failed_at_ + config_.equipment.fail_ack_timeout + std::chrono::milliseconds(50);
    if (own_ == InteractionState::Fail && retry > Clock::now()) {
      wake = std::min(deadline, retry);
    }
    if (!next_event(wake, e)) {
      if (context_.shutdown.requested() || Clock::now() >= deadline) {
        return false;
      }
    }
  }
  trace_.note("closed", "request " + std::string(core::to_string(own_)) + ", response " +
                            std::string(core::to_string(peer_)));
  return true;
}

namespace {
// Nearest-rank percentile of an unsorted sample (0 when empty).
double percentile(std::vector<double> v, double p) {
  if (v.empty()) {
    return 0;
  }
  std::sort(v.begin(), v.end());
  const auto rank =
      static_cast<std::size_t>(std::lround(p / 100.0 * static_cast<double>(v.size() - 1)));
  return v[std::min(rank, v.size() - 1)];
}
}  // namespace

void RequestRunner::print_summary() {
  std::uint64_t counts[7] = {0, 0, 0, 0, 0, 0, 0};
  for (auto r : results_) {
    ++counts[static_cast<int>(r)];
  }
  const double p50 = percentile(complete_ms_, 50);
  const double p99 = percentile(complete_ms_, 99);
  const double max = percentile(complete_ms_, 100);
  const double accept_p50 = percentile(accept_ms_, 50);
  const double accept_p99 = percentile(accept_ms_, 99);
  if (config_.equipment.common.json) {
    JsonLine line;
    line.field("event", "summary")
        .field("count", static_cast<std::uint64_t>(results_.size()))
        .field("complete", counts[0])
        .field("fail", counts[1])
        .field("timeout", counts[2])
        .field("comms_lost", counts[3])
        .field("not_ready", counts[4])
        .field("excluded", counts[6])
        .field("p50_ms", p50)
        .field("p99_ms", p99)
        .field("max_ms", max)
        .field("response_active_p50_ms", accept_p50)
        .field("response_active_p99_ms", accept_p99);
    context_.out.line(line.str());
    return;
  }
  context_.out.line(
      std::to_string(results_.size()) + " handshake(s): " + std::to_string(counts[0]) +
      " COMPLETE, " + std::to_string(counts[1]) + " FAIL, " + std::to_string(counts[2]) +
      " TIMEOUT, " + std::to_string(counts[3]) + " COMMS_LOST" +
      (counts[6] != 0 ? ", " + std::to_string(counts[6]) + " EXCLUDED" : std::string()) +
      "; time to COMPLETE p50 " + format_ms(static_cast<std::int64_t>(p50 * 1e6)) + ", p99 " +
      format_ms(static_cast<std::int64_t>(p99 * 1e6)) + ", max " +
      format_ms(static_cast<std::int64_t>(max * 1e6)) + "; request ACTIVE -> response ACTIVE p50 " +
      format_ms(static_cast<std::int64_t>(accept_p50 * 1e6)) + ", p99 " +
      format_ms(static_cast<std::int64_t>(accept_p99 * 1e6)));
}

int RequestRunner::run() {
  int code = 0;
  own_ = link_.state(service_);
  for (std::uint64_t n = 1; n <= config_.count; ++n) {
    const auto deadline = Clock::now() + config_.timeout;
    trace_.begin(n, service_);
    trace_.set_waiting();
    last_reason_ = core::Reason::None;
    Result result = wait_until_ready(deadline);
    std::string reason;
    if (result == Result::Complete) {
      result = handshake(deadline);
    } else if (result == Result::NotReady) {
      reason = config_.equipment.disabled ? "this interface is DISABLED (--disabled)"
                                          : "responder NOT_READY";
    } else if (result == Result::Timeout) {
      reason = "responder not READY within --timeout";
    }
    if (result == Result::Excluded) {
      reason = excluded_.empty() ? "the responder is paired with another requester" : excluded_;
    }
    if (result == Result::Fail && reason.empty()) {
      reason = last_reason_ != core::Reason::None
                   ? std::string(core::describe(last_reason_))
                   : (peer_ == InteractionState::Fail ? "responder FAIL" : "request FAIL");
    }
    if (result == Result::CommsLost) {
      reason = "counterpart lost (no heartbeat within the lease)";
    }
    trace_.outcome(result, reason);
    results_.push_back(result);
    if (result == Result::Complete) {
      complete_ms_.push_back(trace_.elapsed_ms());
      if (auto a = trace_.first_ms(false, InteractionState::Active)) {
        accept_ms_.push_back(*a);
      }
    }
    if (code == 0) {
      code = exit_code(result);
    }
    const bool more = n < config_.count && (config_.keep_going || result == Result::Complete);
    if (result == Result::Interrupted) {
      break;
    }
    // Excluded: nothing to close with a responder that never read us.
    if ((result != Result::CommsLost && result != Result::Excluded) || more) {
      close_cycle(Clock::now() + config_.timeout, !more);
    }
    if (!more) {
      break;
    }
  }
  print_summary();
  return context_.shutdown.requested() ? exit_code(Result::Interrupted) : code;
}

}  // namespace mtc::cli
