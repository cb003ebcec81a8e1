// The loop behind `mtc respond`: for every service it serves, accepts each
// request, "performs" the action for --action-ms (a timer, not a sleep: the
// loop keeps reacting to the requester meanwhile), completes it, and waits
// for the acknowledgement. Failure injection replaces a step with FAIL; FAIL
// is recovered to READY once acknowledged.
// Single-threaded like RequestRunner.
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

struct RespondConfig {
  EquipmentConfig equipment;
  std::uint64_t count = 0;  // 0 = until Ctrl-C
  std::vector<std::chrono::milliseconds> action{std::chrono::milliseconds(500)};
  bool not_ready = false;
  FailPlan fail_plan;
};

class RespondRunner {
 public:
  RespondRunner(RespondConfig config, Context& context, EquipmentLink& link, EventQueue& events);
  int run();

 private:
  using TimePoint = std::chrono::steady_clock::time_point;
  struct Slot {
    Slot(core::Service s, Output& out, bool json)
        : service(s), trace(out, json, core::Role::Responder) {}
    core::Service service;
    HandshakeTrace trace;
    core::InteractionState own = core::InteractionState::Unavailable;
    core::InteractionState peer = core::InteractionState::Unavailable;
    bool busy = false;      // a handshake is in progress
    bool reported = false;  // its outcome was printed
    FailDecision decision;
    std::optional<TimePoint> action_end;
    std::optional<TimePoint> fail_at;
    TimePoint failed_at{};
    core::Reason last_reason = core::Reason::None;
  };

  Slot* slot_for(core::Service s);
  void on_event(const LinkEvent& e);
  void on_peer_link(const LinkEvent& e);
  static void on_state(Slot& slot, const LinkEvent& e);
  void on_request(Slot& slot);
  void on_timers(Slot& slot, TimePoint now);
  void inject(Slot& slot);
  static void report(Slot& slot, Result result, const std::string& reason);
  void maintain(Slot& slot);
  void close(Slot& slot);
  void move_door_or_chuck(Slot& slot);
  TimePoint next_wake() const;

  RespondConfig config_;
  Context& context_;
  EquipmentLink& link_;
  EventQueue& events_;
  std::vector<Slot> slots_;
  bool peer_lost_ = false;
  std::uint64_t started_ = 0;
  std::uint64_t closed_ = 0;
};

}  // namespace mtc::cli
