// Failure injection for `mtc respond` and `mtc request`: decides, per
// handshake, whether and where this side misbehaves, so the failure
// scenarios of Part 5 section 5.1 can be driven across processes.
// Deterministic: the same --seed gives the same sequence of decisions.
#pragma once

#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <vector>

namespace mtc::cli {

// Where in a handshake the failure happens.
enum class FailStep : std::uint8_t {
  None,
  Accept,    // responder: FAIL instead of ACTIVE (scenario 1)
  Active,    // while ACTIVE, half-way through the action (scenarios 2-5)
  Complete,  // responder: when the action would complete (scenario 2, late)
};

// What the misbehaving side changes its state to.
enum class FailTarget : std::uint8_t {
  Fail,      // FAIL (scenarios 1, 2, 3)
  NotReady,  // unexpected NOT_READY (scenario 5; requester: scenario 4 note)
  Ready,     // requester only: unexpected READY (scenario 4)
};

struct FailDecision {
  FailStep step = FailStep::None;
  FailTarget target = FailTarget::Fail;
  bool fails() const { return step != FailStep::None; }
};

std::optional<FailStep> parse_fail_step(std::string_view text);
std::optional<FailTarget> parse_fail_target(std::string_view text);
std::string_view to_string(FailStep step);
std::string_view to_string(FailTarget target);

class FailPlan {
 public:
  FailPlan() = default;
  // step/target: the configured failure. only_on: 1-based handshake numbers it
  // applies to (empty = all). rate > 0: each handshake fails with that
  // probability instead (at `step`, or at a random step when step is None).
  FailPlan(FailStep step, FailTarget target, std::vector<std::uint64_t> only_on, double rate,
           std::uint64_t seed);

  // Decision for handshake number n (1-based); call once per handshake, in order.
  FailDecision decide(std::uint64_t n);

 private:
  FailStep step_ = FailStep::None;
  FailTarget target_ = FailTarget::Fail;
  std::vector<std::uint64_t> only_on_;
  double rate_ = 0;
  std::mt19937_64 rng_;
};

}  // namespace mtc::cli
