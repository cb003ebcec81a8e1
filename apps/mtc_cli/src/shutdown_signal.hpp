// SIGINT/SIGTERM handling for the `mtc` tool without work in a signal
// handler: the signals are blocked in every thread (the mask is set before
// any other thread exists, so DDS threads inherit it) and one dedicated
// thread takes them with sigwait() and notifies waiters through a condition
// variable. Commands wait on wait_for()/wait_until() instead of sleeping.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>

namespace mtc::cli {

class ShutdownSignal {
 public:
  // Must be constructed in main() before any thread is started.
  ShutdownSignal();
  ~ShutdownSignal();
  ShutdownSignal(const ShutdownSignal&) = delete;
  ShutdownSignal& operator=(const ShutdownSignal&) = delete;

  bool requested() const noexcept { return requested_.load(); }
  // The signal number that asked us to stop (0 if none).
  int signal_number() const noexcept { return signal_number_.load(); }

  // Blocks until a shutdown is requested or the time passes; true if requested.
  bool wait_for(std::chrono::milliseconds timeout);
  bool wait_until(std::chrono::steady_clock::time_point deadline);
  // Lets other code (e.g. a finished handshake) wake waiters early.
  void request(int signal_number = 0);
  // Wakes waiters without requesting shutdown, so they can re-check their own
  // condition (e.g. a runtime callback delivered an outcome).
  void poke();
  // Called (from the signal thread) after a shutdown request, e.g. to wake an
  // event queue that waits on its own condition variable. Set before use;
  // replacing it waits for a call in progress to return.
  void set_listener(std::function<void()> listener);

 private:
  void run();

  std::atomic<bool> requested_{false};
  std::atomic<int> signal_number_{0};
  std::atomic<bool> closing_{false};
  std::mutex mutex_;
  std::condition_variable cv_;
  std::uint64_t pokes_ = 0;
  std::mutex listener_mutex_;  // held while the listener runs or is replaced
  std::function<void()> listener_;
  std::thread thread_;
};

}  // namespace mtc::cli
