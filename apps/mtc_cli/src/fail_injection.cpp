#include "fail_injection.hpp"

#include <algorithm>

namespace mtc::cli {

std::optional<FailStep> parse_fail_step(std::string_view text) {
  if (text == "none") {
    return FailStep::None;
  }
  if (text == "accept") {
    return FailStep::Accept;
  }
  if (text == "active") {
    return FailStep::Active;
  }
  if (text == "complete") {
    return FailStep::Complete;
  }
  return std::nullopt;
}

std::string_view to_string(FailStep step) {
  switch (step) {
    case FailStep::None:
      return "none";
    case FailStep::Accept:
      return "accept";
    case FailStep::Active:
      return "active";
    case FailStep::Complete:
      return "complete";
  }
  return "none";
}

FailPlan::FailPlan(FailStep step, std::vector<std::uint64_t> only_on, double rate,
                   std::uint64_t seed)
    : step_(step), only_on_(std::move(only_on)), rate_(rate), rng_(seed) {}

FailDecision FailPlan::decide(std::uint64_t n) {
  if (rate_ > 0) {
    // Draw both numbers every time so the sequence depends only on the seed.
    std::uniform_real_distribution<double> coin(0.0, 1.0);
    std::uniform_int_distribution<int> pick(1, 3);
    const bool hit = coin(rng_) < rate_;
    const auto random_step = static_cast<FailStep>(pick(rng_));
    if (!hit) {
      return {};
    }
    return {step_ == FailStep::None ? random_step : step_};
  }
  if (step_ == FailStep::None) {
    return {};
  }
  if (!only_on_.empty() && std::find(only_on_.begin(), only_on_.end(), n) == only_on_.end()) {
    return {};
  }
  return {step_};
}

}  // namespace mtc::cli
