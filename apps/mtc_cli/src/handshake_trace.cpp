#include "handshake_trace.hpp"

#include <cstdio>

#include "exit_codes.hpp"

namespace mtc::cli {

std::string_view to_string(Result r) {
  switch (r) {
    case Result::Complete:
      return "COMPLETE";
    case Result::Fail:
      return "FAIL";
    case Result::Timeout:
      return "TIMEOUT";
    case Result::CommsLost:
      return "COMMS_LOST";
    case Result::NotReady:
      return "NOT_READY";
    case Result::Interrupted:
      return "INTERRUPTED";
    case Result::Excluded:
      return "EXCLUDED";
  }
  return "FAIL";
}

int exit_code(Result r) {
  switch (r) {
    case Result::Complete:
      return ExitOk;
    case Result::Fail:
      return ExitFail;
    case Result::Timeout:
      return ExitTimeout;
    case Result::CommsLost:
      return ExitCommsLost;
    case Result::NotReady:
      return ExitNotReady;
    case Result::Interrupted:
      return ExitInterrupted;
    case Result::Excluded:
      return ExitExcluded;
  }
  return ExitError;
}

void HandshakeTrace::begin(std::uint64_t n, core::Service service) {
  n_ = n;
  service_ = service;
  start_ = std::chrono::steady_clock::now();
  steps_.clear();
}

double HandshakeTrace::elapsed_ms() const {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_)
      .count();
}

std::string HandshakeTrace::side(bool own) const {
  const bool request = (role_ == core::Role::Requester) == own;
  return request ? "request" : "response";
}

void HandshakeTrace::transition(bool own, const LinkEvent& e) {
  const double t = active() ? elapsed_ms() : 0.0;
  if (active()) {
    steps_.push_back({own, e.state, t});
  }
  const std::int64_t latency = own ? 0 : e.reception_time_ns - e.source_time_ns;
  const std::string state(core::to_string(e.state));
  if (json_) {
    JsonLine line;
    line.field("event", "transition")
        .field("handshake", n_)
        .field("service", core::to_string(e.service))
        .field("side", side(own))
        .field("state", state)
        .field("t_ms", t);
    if (!own) {
      // redelivered: not a new change but the last known value, handed
      // over again when the link came back after a loss.
      line.field("latency_ms", static_cast<double>(latency) / 1e6)
          .field("source_time_ns", e.source_time_ns)
          .field("sequence", e.sequence_number)
          .field("redelivered", e.redelivered);
    }
    out_.line(line.field("time_ns", e.reception_time_ns).str());
    return;
  }
  char buf[160];
  if (!active()) {
    std::snprintf(buf, sizeof buf, "  idle                     %-8s -> %-10s", side(own).c_str(),
                  state.c_str());
  } else if (waiting_) {
    std::snprintf(buf, sizeof buf, "  #%-4llu (waiting)          %-8s -> %-10s",
                  static_cast<unsigned long long>(n_), side(own).c_str(), state.c_str());
  } else {
    std::snprintf(buf, sizeof buf, "  #%-4llu +%10.3f ms      %-8s -> %-10s",
                  static_cast<unsigned long long>(n_), t, side(own).c_str(), state.c_str());
  }
  std::string text = buf;
  text += "  " + std::string(core::to_string(e.service));
  if (!own) {
    text += "  (latency " + format_ms(latency) + ")";
  }
  out_.line(text);
}

std::optional<double> HandshakeTrace::first_ms(bool own, core::InteractionState s) const {
  for (const auto& step : steps_) {
    if (step.own == own && step.state == s) {
      return step.t_ms;
    }
  }
  return std::nullopt;
}

void HandshakeTrace::outcome(Result result, const std::string& reason) {
  const double total = elapsed_ms();
  const auto accepted = first_ms(role_ == core::Role::Responder, core::InteractionState::Active);
  const auto completed = first_ms(role_ == core::Role::Responder, core::InteractionState::Complete);
  if (json_) {
    JsonLine line;
    line.field("event", "outcome")
        .field("handshake", n_)
        .field("service", core::to_string(service_))
        .field("result", to_string(result))
        .field("reason", reason)
        .field("total_ms", total);
    if (accepted) {
      line.field("response_active_ms", *accepted);
    }
    if (completed) {
      line.field("response_complete_ms", *completed);
    }
    out_.line(line.str());
    return;
  }
  char buf[200];
  std::snprintf(buf, sizeof buf, "handshake %llu %s: %s after %.3f ms",
                static_cast<unsigned long long>(n_), std::string(core::to_string(service_)).c_str(),
                std::string(to_string(result)).c_str(), total);
  std::string text = buf;
  if (accepted) {
    text += ", response ACTIVE at +" + format_ms(static_cast<std::int64_t>(*accepted * 1e6));
  }
  if (completed) {
    text += ", COMPLETE at +" + format_ms(static_cast<std::int64_t>(*completed * 1e6));
  }
  if (!reason.empty()) {
    text += " (" + reason + ")";
  }
  out_.line(text);
}

void HandshakeTrace::note(const std::string& event, const std::string& detail) {
  if (json_) {
    JsonLine line;
    out_.line(line.field("event", event)
                  .field("handshake", n_)
                  .field("detail", detail)
                  .field("time_ns", now_ns())
                  .str());
  } else {
    out_.line("  #" + std::to_string(n_) + " " + event + ": " + detail);
  }
}

}  // namespace mtc::cli
