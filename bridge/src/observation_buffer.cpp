#include "mtc/bridge/observation_buffer.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace mtc::bridge {

ObservationBuffer::ObservationBuffer(std::size_t capacity, std::size_t checkpoint_interval)
    : checkpoint_interval_(std::max<std::size_t>(1, checkpoint_interval)) {
  if (capacity < 2) throw std::invalid_argument("observation buffer needs at least 2 entries");
  ring_.resize(capacity);
}

void ObservationBuffer::apply(std::vector<Observation>& state, const Observation& o) {
  if (state.size() <= o.slot) state.resize(o.slot + 1);
  state[o.slot] = o;
}

std::uint64_t ObservationBuffer::append(std::uint32_t slot, std::string value,
                                        std::int64_t time_ns) {
  const std::uint64_t seq = next_;
  Observation& cell = ring_[seq % ring_.size()];
  if (next_ - first_ == ring_.size()) {
    // The oldest entry leaves the ring: fold it into the base checkpoint so
    // state_at() can still start below the new first sequence.
    apply(base_.state, cell);
    base_.sequence = first_;
    ++first_;
    while (!checkpoints_.empty() && checkpoints_.front().sequence < first_) {
      checkpoints_.pop_front();
    }
  }
  cell.sequence = seq;
  cell.slot = slot;
  cell.time_ns = time_ns;
  cell.value = std::move(value);
  apply(latest_, cell);
  ++next_;
  if (seq % checkpoint_interval_ == 0) checkpoints_.push_back(Checkpoint{seq, latest_});
  return seq;
}

const Observation* ObservationBuffer::find(std::uint64_t sequence) const noexcept {
  if (sequence < first_ || sequence >= next_) return nullptr;
  return &ring_[sequence % ring_.size()];
}

const Observation* ObservationBuffer::latest(std::uint32_t slot) const noexcept {
  if (slot >= latest_.size() || latest_[slot].sequence == 0) return nullptr;
  return &latest_[slot];
}

std::vector<Observation> ObservationBuffer::state_at(std::uint64_t sequence) const {
  if (empty() || sequence < first_ || sequence >= next_) {
    throw std::out_of_range("sequence outside the buffer");
  }
  if (sequence == next_ - 1) return latest_;
  // Nearest checkpoint at or below `sequence`, else the base below the ring.
  const Checkpoint* start = &base_;
  auto it = std::upper_bound(checkpoints_.begin(), checkpoints_.end(), sequence,
                             [](std::uint64_t s, const Checkpoint& c) { return s < c.sequence; });
  if (it != checkpoints_.begin()) start = &*std::prev(it);
  std::vector<Observation> state = start->state;
  std::uint64_t from = std::max(start->sequence + 1, first_);
  for (std::uint64_t s = from; s <= sequence; ++s) apply(state, ring_[s % ring_.size()]);
  return state;
}

}  // namespace mtc::bridge
