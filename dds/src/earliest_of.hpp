// Internal: the earliest of many instants, one per id, where one instant
// changes at a time. The executor asks the equipment for its next wake
// after every step, and a step moves the time limits of one interface: with
// 100 interfaces, asking each of them again was a walk over 100 cache lines
// per step. Here a change costs O(log n) and the answer O(1), with no
// allocation once every id has been seen.
#pragma once

#include <chrono>
#include <cstddef>
#include <utility>
#include <vector>

namespace mtc::dds::detail {

class EarliestOf {
 public:
  using TimePoint = std::chrono::steady_clock::time_point;

  // Sets the instant of `id` (ids are small indices; a new one joins).
  void set(std::size_t id, TimePoint at) {
    if (id >= position_.size()) {
      position_.resize(id + 1, kAbsent);
      at_.resize(id + 1, TimePoint::max());
    }
    at_[id] = at;
    if (position_[id] == kAbsent) {
      position_[id] = heap_.size();
      heap_.push_back(id);
    }
    sift_down(sift_up(position_[id]));
  }

  // The earliest instant of all ids; TimePoint::max() when there is none.
  TimePoint earliest() const { return heap_.empty() ? TimePoint::max() : at_[heap_.front()]; }
  TimePoint at(std::size_t id) const { return id < at_.size() ? at_[id] : TimePoint::max(); }

 private:
  static constexpr std::size_t kAbsent = static_cast<std::size_t>(-1);

  bool before(std::size_t a, std::size_t b) const { return at_[heap_[a]] < at_[heap_[b]]; }

  void swap_places(std::size_t a, std::size_t b) {
    std::swap(heap_[a], heap_[b]);
    position_[heap_[a]] = a;
    position_[heap_[b]] = b;
  }

  std::size_t sift_up(std::size_t place) {
    while (place > 0) {
      const std::size_t parent = (place - 1) / 2;
      if (!before(place, parent)) break;
      swap_places(place, parent);
      place = parent;
    }
    return place;
  }

  void sift_down(std::size_t place) {
    for (;;) {
      const std::size_t left = 2 * place + 1;
      if (left >= heap_.size()) return;
      std::size_t first = left;
      if (left + 1 < heap_.size() && before(left + 1, left)) first = left + 1;
      if (!before(first, place)) return;
      swap_places(place, first);
      place = first;
    }
  }

  std::vector<std::size_t> heap_;      // ids, a binary min-heap on at_
  std::vector<std::size_t> position_;  // id -> its place in heap_
  std::vector<TimePoint> at_;          // id -> its instant
};

}  // namespace mtc::dds::detail
