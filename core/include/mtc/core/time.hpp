// Time as the interaction model sees it: an injected value, never a clock read.
//
// Every step of a state machine receives `now`; machines report the earliest
// instant at which they need to be woken (`next_deadline()`) and the runtime
// arms one timer and calls `on_tick(now)`. Tests and the demo drive a
// simulated clock the same way, so nothing in core/ ever sleeps.
#pragma once

#include <chrono>

namespace mtc::core {

using Clock = std::chrono::steady_clock;
using TimePoint = Clock::time_point;
using Duration = Clock::duration;

// "No deadline armed". Comparisons against it are always later than any now.
inline constexpr TimePoint kNever = TimePoint::max();

}  // namespace mtc::core
