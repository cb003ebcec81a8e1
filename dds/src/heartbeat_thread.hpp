// Internal: the thread that writes an Equipment's heartbeats. It does nothing
// but wait for the next period and write one small sample per timing group,
// so a heartbeat never queues behind the executor's work (handshakes,
// application callbacks, a burst of samples), and under CPU starvation it is
// one short-running thread to schedule, not a queue to drain. It asks for
// SCHED_FIFO priority 1 when the process may have it (root, CAP_SYS_NICE or
// an RLIMIT_RTPRIO) and keeps its normal priority otherwise.
//
// It must not lie, though: a heartbeat says "this equipment works". The
// watchdog withholds a group's heartbeat while the executor has owed work for
// longer than that group's stall limit (about a lease), so a process whose
// executor hangs (a blocked callback, a deadlock) is still declared lost by
// its peers.
#pragma once

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "executor.hpp"

namespace mtc::dds::detail {

class HeartbeatThread {
 public:
  using Clock = std::chrono::steady_clock;

  struct Group {
    Clock::duration period{};
    // Withhold this group's heartbeat while the executor owes work this long.
    Clock::duration stall_limit{};
    // Writes one heartbeat; called on the heartbeat thread only. Must not
    // wait for the executor. May throw (reported, the thread goes on).
    std::function<void()> beat;
  };
  // Called on the heartbeat thread with a sentence for the application's
  // diagnostics (it should post it to the executor, never run callbacks).
  // `executor_stuck`: the sentence says the executor makes no progress, so a
  // post will not reach the application before it recovers, if ever.
  using Report = std::function<void(const std::string&, bool executor_stuck)>;

  // Starts the thread; the first heartbeat of every group is written at once.
  HeartbeatThread(std::vector<Group> groups, const Executor& executor, Report report);
  ~HeartbeatThread();
  HeartbeatThread(const HeartbeatThread&) = delete;
  HeartbeatThread& operator=(const HeartbeatThread&) = delete;

  // Joins the thread; no heartbeat is written after it returns. Idempotent.
  void stop();
  // Whether the thread got SCHED_FIFO (known once it has started).
  bool realtime() const;
  // The longest time a group went without a heartbeat written since the
  // last call (or start), counting the time since its newest one, and when
  // that silence began (one silence, one beginning, however often it is
  // asked for): any thread. Longer than the group's lease, less half a
  // heartbeat, and its counterparts may have declared this equipment lost
  // (the process was stopped, starved, or its executor hung and the
  // watchdog withheld).
  struct Silence {
    Clock::duration length{};
    Clock::time_point since{};
  };
  Silence take_silence(std::size_t group, Clock::time_point now);

 private:
  void run();
  void beat_group(std::size_t index, Clock::time_point now);

  std::vector<Group> groups_;
  std::vector<Clock::time_point> next_;
  std::vector<bool> withheld_;
  // Per group, written under mutex_: the newest write and the longest gap
  // between two writes not yet taken by take_silence().
  std::vector<Clock::time_point> last_beat_;
  std::vector<Silence> longest_gap_;
  const Executor& executor_;
  Report report_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  bool stopping_ = false;
  bool realtime_ = false;
  std::thread thread_;
};

}  // namespace mtc::dds::detail
