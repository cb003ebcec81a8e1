// Internal: when a participant announces all of its endpoints again
// (detail::Publisher::reannounce says why). Executor thread only.
//
// A pass runs as soon as a counterpart is lost: on a cable pull that is
// always before the far side can acknowledge it again, which is what makes
// its rediscovery complete. It is repeated, with a doubling backoff, while
// anything stays lost (a flapping link can let the far side acknowledge a
// pass and drop us later without a new loss here), and slowly in the
// background for a peer that dropped us while we have no link with it
// (a bridge that dropped a robot is invisible to the robot's links).
#pragma once

#include <algorithm>
#include <chrono>

namespace mtc::dds::detail {

class ReannounceSchedule {
 public:
  using Clock = std::chrono::steady_clock;
  // Backoff from one participant lease up to kMaxBackoffLeases of them; the
  // background pass every kBackgroundLeases.
  static constexpr int kMaxBackoffLeases = 8;
  static constexpr int kBackgroundLeases = 10;

  // From here on passes are due; before (entities still being created), a
  // loss schedules nothing.
  void arm(Clock::time_point now, std::chrono::milliseconds participant_lease) {
    lease_ = participant_lease;
    backoff_ = lease_;
    next_ = now + kBackgroundLeases * lease_;
    armed_ = true;
  }
  // A counterpart was lost: a pass is due now (losses handled in one batch
  // share it), and the backoff starts over.
  void lost(Clock::time_point now) {
    if (!armed_) return;
    next_ = std::min(next_, now);
    backoff_ = lease_;
  }
  Clock::time_point next() const { return armed_ ? next_ : Clock::time_point::max(); }
  bool due(Clock::time_point now) const { return armed_ && now >= next_; }
  // A pass ran: the next one after the backoff while something is still
  // lost, else in the background period.
  void passed(Clock::time_point now, bool still_lost) {
    if (still_lost) {
      next_ = now + backoff_;
      backoff_ = std::min(2 * backoff_, kMaxBackoffLeases * lease_);
    } else {
      next_ = now + kBackgroundLeases * lease_;
      backoff_ = lease_;
    }
  }

 private:
  bool armed_ = false;
  std::chrono::milliseconds lease_{0};
  std::chrono::milliseconds backoff_{0};
  Clock::time_point next_ = Clock::time_point::max();
};

}  // namespace mtc::dds::detail
