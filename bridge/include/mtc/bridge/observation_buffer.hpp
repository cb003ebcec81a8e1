// Sequence-numbered ring of observations, as an MTConnect agent keeps them.
//
// - Sequence numbers start at 1 and strictly increase; the ring keeps the
//   last `capacity` observations (any capacity >= 2).
// - latest(slot) answers /current, including items whose last change fell
//   out of the ring.
// - state_at(seq) answers /current?at=seq: the state of every item as of a
//   sequence still in the ring. It starts from the nearest checkpoint at or
//   below seq (a full copy of the state taken every `checkpoint_interval`
//   appends, plus a base checkpoint just below the ring's first entry that
//   absorbs evicted observations) and replays at most checkpoint_interval
//   observations, so its cost is O(items + checkpoint_interval), not
//   O(buffer).
//
// Not synchronised: the agent guards it together with the model.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

namespace mtc::bridge {

struct Observation {
  std::uint64_t sequence = 0;  // 0: "never observed" (in per-item state)
  std::uint32_t slot = 0;
  std::int64_t time_ns = 0;  // ns since the epoch, UTC
  std::string value;
};

class ObservationBuffer {
 public:
  explicit ObservationBuffer(std::size_t capacity, std::size_t checkpoint_interval = 1024);

  // Appends; returns the observation's sequence number.
  std::uint64_t append(std::uint32_t slot, std::string value, std::int64_t time_ns);

  std::size_t capacity() const noexcept { return ring_.size(); }
  // Oldest sequence still in the ring (== next_sequence() while empty).
  std::uint64_t first_sequence() const noexcept { return first_; }
  std::uint64_t next_sequence() const noexcept { return next_; }
  // Sequence of the newest observation (0 while empty).
  std::uint64_t last_sequence() const noexcept { return next_ - 1; }
  bool empty() const noexcept { return next_ == first_; }

  // The observation with this sequence, or nullptr when outside the ring.
  const Observation* find(std::uint64_t sequence) const noexcept;
  // Latest observation of a slot, or nullptr when it never had one.
  const Observation* latest(std::uint32_t slot) const noexcept;
  // Number of slots that ever had an observation.
  std::size_t slot_count() const noexcept { return latest_.size(); }

  // State as of `sequence` (first_sequence() <= sequence <= last_sequence()):
  // per slot, its last observation with a sequence <= `sequence`
  // (sequence == 0 where there is none).
  std::vector<Observation> state_at(std::uint64_t sequence) const;

 private:
  struct Checkpoint {
    std::uint64_t sequence = 0;  // state after applying this sequence
    std::vector<Observation> state;
  };
  static void apply(std::vector<Observation>& state, const Observation& o);

  std::vector<Observation> ring_;
  std::uint64_t first_ = 1;
  std::uint64_t next_ = 1;
  std::size_t checkpoint_interval_;
  std::vector<Observation> latest_;
  Checkpoint base_;                     // state just below first_
  std::deque<Checkpoint> checkpoints_;  // ascending, all >= base_.sequence
};

}  // namespace mtc::bridge
