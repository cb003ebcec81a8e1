// Internal: the incarnations (participants) of counterpart devices that said
// they are leaving, for the Equipment and the DomainObserver alike. Whatever
// of theirs arrives after the leave is not news: a value that crossed the
// leave on another topic, or a disposal delivered late by a writer that
// lingers after its participant (Cyclone DDS does that). Bounded: the
// oldest are forgotten first, so a cell that restarts devices all day keeps
// a fixed footprint.
#pragma once

#include <cstddef>
#include <deque>
#include <set>

#include "mw/wire.hpp"

namespace mtc::dds::detail {

class LeftIncarnations {
 public:
  static constexpr std::size_t kRemembered = 256;

  // True when `writer` belongs to an incarnation that left. A writer the
  // middleware did not name (all zero) belongs to none.
  bool wrote(const Handle& writer) const {
    return writer != Handle{} && left_.count(participant_of(writer)) != 0;
  }
  void remember(const Handle& writer) {
    if (writer == Handle{}) return;
    const auto participant = participant_of(writer);
    if (!left_.insert(participant).second) return;
    order_.push_back(participant);
    if (order_.size() > kRemembered) {
      left_.erase(order_.front());
      order_.pop_front();
    }
  }

 private:
  std::set<ParticipantKey> left_;
  std::deque<ParticipantKey> order_;
};

}  // namespace mtc::dds::detail
