// Failure injection for `mtc respond` and `mtc request`: decides, per
// handshake, whether and where this side goes FAIL, so failure scenarios 1-3
// of Part 5 section 5.1 can be driven across processes. (Scenarios 4 and 5
// need a peer that breaks Tables 5/6, which the runtime never does; the
// tests play that peer themselves.)
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

struct FailDecision {
  FailStep step = FailStep::None;
  bool fails() const { return step != FailStep::None; }
};

std::optional<FailStep> parse_fail_step(std::string_view text);
std::string_view to_string(FailStep step);

class FailPlan {
 public:
  FailPlan() = default;
  // step: where the configured failure (going FAIL) happens. only_on: 1-based handshake numbers it
  // applies to (empty = all). rate > 0: each handshake fails with that
  // probability instead (at `step`, or at a random step when step is None).
  FailPlan(FailStep step, std::vector<std::uint64_t> only_on, double rate, std::uint64_t seed);

  // Decision for handshake number n (1-based); call once per handshake, in order.
  FailDecision decide(std::uint64_t n);

 private:
  FailStep step_ = FailStep::None;
  std::vector<std::uint64_t> only_on_;
  double rate_ = 0;
  std::mt19937_64 rng_;
};

}  // namespace mtc::cli
