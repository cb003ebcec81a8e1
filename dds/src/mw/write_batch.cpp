#include "write_batch.hpp"

#include <algorithm>
#include <utility>
#include <vector>

namespace mtc::dds::mw {

namespace {

struct Deferred {
  WriteBatch::Flush flush;
  std::int64_t handle;
  bool operator==(const Deferred& other) const noexcept {
    return flush == other.flush && handle == other.handle;
  }
};

// Per thread: how many batches are open, and which writers hold samples.
thread_local int t_depth = 0;
thread_local std::vector<Deferred> t_deferred;

}  // namespace

WriteBatch::WriteBatch() noexcept {
  ++t_depth;
}

WriteBatch::~WriteBatch() {
  if (--t_depth == 0) send_now();
}

void WriteBatch::send_now() {
  if (t_deferred.empty()) return;
  // Swapped out first: a flush that wrote again (it does not) would land in
  // a fresh list instead of the one being walked.
  std::vector<Deferred> due;
  due.swap(t_deferred);
  for (const auto& d : due) d.flush(d.handle);
  due.clear();
  // The storage is kept for the next batch of this thread.
  if (t_deferred.empty()) t_deferred.swap(due);
}

bool WriteBatch::defer(Flush flush, std::int64_t handle) {
  if (t_depth == 0) return false;
  const Deferred d{flush, handle};
  // A burst is mostly one or two writers: a short list, searched in full.
  if (std::find(t_deferred.begin(), t_deferred.end(), d) == t_deferred.end()) {
    t_deferred.push_back(d);
  }
  return true;
}

}  // namespace mtc::dds::mw
