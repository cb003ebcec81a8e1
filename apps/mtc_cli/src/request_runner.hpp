// The loop behind `mtc request`: waits for the counterpart's response to be
// READY, requests, follows the handshake to its outcome (printing every
// transition with its latency), closes the cycle (acknowledge / recover to
// READY) and repeats --count times. Single-threaded: it only reacts to
// LinkEvents popped from its queue and to its own deadlines.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <vector>

#include "commands.hpp"
#include "equipment_link.hpp"
#include "fail_injection.hpp"
#include "handshake_trace.hpp"

namespace mtc::cli {

struct RequestConfig {
  EquipmentConfig equipment;
  std::uint64_t count = 1;
  std::chrono::milliseconds timeout{10000};
  bool keep_going = false;
  FailPlan fail_plan;
};

class RequestRunner {
 public:
  RequestRunner(RequestConfig config, Context& context, EquipmentLink& link, EventQueue& events);
  // Runs every handshake; returns the exit code.
  int run();

 private:
  using TimePoint = std::chrono::steady_clock::time_point;
  // Pops one event (or nothing by the deadline), tracks states, prints
  // transitions. False when the deadline passed or shutdown was requested.
  bool next_event(TimePoint deadline, LinkEvent& event);
  void on_notice(const LinkEvent& event);
  Result wait_until_ready(TimePoint deadline);
  Result handshake(TimePoint deadline);
  void inject(const FailDecision& decision);
  // Waits until both sides are idle again (recovering a FAIL on the way).
  bool close_cycle(TimePoint deadline, bool last);
  void try_recover();
  void print_summary();

  RequestConfig config_;
  Context& context_;
  EquipmentLink& link_;
  EventQueue& events_;
  core::Service service_;
  HandshakeTrace trace_;
  core::InteractionState own_ = core::InteractionState::Unavailable;
  core::InteractionState peer_ = core::InteractionState::Unavailable;
  bool peer_lost_ = false;
  // The responder serves another requester: why ("machine-1/mh is paired
  // with robot-1/mh"), empty while it names us or nobody.
  std::string excluded_;
  std::optional<Result> done_;  // the runtime's outcome of the current request()
  core::Reason last_reason_ = core::Reason::None;
  TimePoint failed_at_{};
  std::vector<Result> results_;
  std::vector<double> complete_ms_;  // request issued -> COMPLETE seen
  std::vector<double> accept_ms_;    // request issued -> response ACTIVE seen
};

}  // namespace mtc::cli
