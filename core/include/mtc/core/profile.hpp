// Which edition of Part 5 the machines follow, and the time limits an
// integrator configures.
#pragma once

#include <chrono>
#include <cstdint>

#include "mtc/core/time.hpp"

namespace mtc::core {

// V1_6 is the full model of Part 5 1.6 (Tables 5 and 6, scenarios 1-6); 1.8
// defines the same model, so V1_6 covers it. V1_3 follows the 2014 text where
// it differs:
//  * the requester returns to READY (not FAIL) when the responder fails or
//    leaves ACTIVE early;
//  * the responder's FAIL is acknowledged by the request leaving ACTIVE;
//  * FAIL returns to READY on its own after TimeLimits::fail_reset;
//  * loss of communication fails only a service in progress (ACTIVE/COMPLETE);
//    an idle side stays as it is and re-reads its counterpart on reconnection.
enum class Profile : std::uint8_t { V1_6, V1_3 };

// Time limits. A zero duration disables that limit.
struct TimeLimits {
  // Requester: request ACTIVE and the responder has not gone ACTIVE.
  // Expiry => requester FAIL (TimedOut, Reason::ResponseTimeout).
  Duration response{0};
  // Requester: request ACTIVE without the responder reaching COMPLETE.
  // Responder: response ACTIVE without the application completing.
  // Expiry => FAIL (TimedOut, Reason::ServiceTimeout).
  Duration service{0};
  // Responder: COMPLETE and the request has not returned to READY. The
  // response MUST stay COMPLETE, so expiry only reports (TimedOut,
  // Reason::CompletionAckTimeout) once.
  Duration completion_ack{0};
  // FAIL and the counterpart has not acknowledged it. Expiry reports
  // (TimedOut, Reason::FailAckTimeout) and from then on recover() is allowed
  // without the acknowledgement, so a silent counterpart cannot pin a side in
  // FAIL forever.
  Duration fail_ack{0};
  // V1_3 only: FAIL returns to READY by itself after this period (1.3:
  // "to avoid both sides being stuck in FAIL"). Ignored under V1_6.
  Duration fail_reset{std::chrono::seconds(10)};
};

// Options of one service machine (one side of one service).
struct MachineOptions {
  Profile profile = Profile::V1_6;
  TimeLimits limits{};
  // False for a counterpart with no FAIL state (1.3: simple logic controls).
  // Such a counterpart signals failure by leaving ACTIVE early, which is
  // handled as a FAIL in every profile anyway; the flag changes what counts as
  // acknowledging OUR FAIL: the counterpart being out of ACTIVE/COMPLETE
  // instead of being in FAIL.
  bool counterpart_has_fail = true;
  // Initial own state: READY when true (the text's initial condition),
  // NOT_READY otherwise. A precondition hook can still hold it NOT_READY.
  bool start_ready = true;
};

}  // namespace mtc::core
