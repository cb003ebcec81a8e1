// The demo's stage: a machine tool requesting MATERIAL_LOAD from a robot,
// each side an mtc::core machine, linked by instantaneous delivery on a
// simulated clock. Every step that does something is printed.
#pragma once

#include <cstdio>
#include <string>

#include "mtc/core/requester.hpp"
#include "mtc/core/responder.hpp"

namespace mtc::demo {

class Stage {
 public:
  Stage(core::Profile profile, const core::MachineOptions& requester_options,
        const core::MachineOptions& responder_options);

  core::Requester& cnc() { return requester_; }
  core::Responder& robot() { return responder_; }
  core::TimePoint now() const { return now_; }
  core::Profile profile() const { return profile_; }

  // Prints a step of either machine (skips steps that did nothing).
  void show(const core::StepResult& r);
  void say(const std::string& text);
  // Moves the simulated clock and fires any expired time limit.
  void advance(std::chrono::milliseconds d);
  // Shows each side the other's current value, then fires due deadlines.
  void to_robot();
  void to_cnc();
  // Delivers both ways until nothing changes.
  void settle();
  // The applications clear FAIL once allowed, the way section 5.1 describes,
  // until both sides are READY/NOT_READY again.
  void recover_both();
  // Interface-level loss of communication on both sides.
  void lose_link();
  // Prints both sides' final published values.
  void finish();

 private:
  void tick();
  core::Profile profile_;
  core::Requester requester_;
  core::Responder responder_;
  core::TimePoint now_{};
};

}  // namespace mtc::demo
