#include "link_events.hpp"

namespace mtc::cli {

void EventQueue::push(LinkEvent event) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    events_.push_back(std::move(event));
  }
  cv_.notify_all();
}

void EventQueue::wake() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++wakes_;
  }
  cv_.notify_all();
}

std::optional<LinkEvent> EventQueue::pop_until(std::chrono::steady_clock::time_point deadline) {
  std::unique_lock<std::mutex> lock(mutex_);
  const std::uint64_t wakes = wakes_;
  cv_.wait_until(lock, deadline, [&] { return !events_.empty() || wakes_ != wakes; });
  if (events_.empty()) {
    return std::nullopt;
  }
  LinkEvent e = std::move(events_.front());
  events_.pop_front();
  return e;
}

}  // namespace mtc::cli
