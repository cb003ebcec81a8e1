#include "shutdown_signal.hpp"

#include <pthread.h>
#include <signal.h>

#include <system_error>

namespace mtc::cli {

namespace {

// SIGUSR2 only wakes the sigwait() thread when the object is destroyed; it
// is blocked in every thread, so no other thread can be hit by it.
constexpr int kWakeSignal = SIGUSR2;

sigset_t handled_signals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, kWakeSignal);
  return set;
}

}  // namespace

ShutdownSignal::ShutdownSignal() {
  // A closed stdout pipe (e.g. `mtc watch | head`) must not kill us silently
  // mid-write; the write fails and the command ends normally instead.
  ::signal(SIGPIPE, SIG_IGN);
  sigset_t set = handled_signals();
  if (int rc = pthread_sigmask(SIG_BLOCK, &set, nullptr); rc != 0) {
    throw std::system_error(rc, std::generic_category(), "pthread_sigmask");
  }
  thread_ = std::thread([this] { run(); });
}

ShutdownSignal::~ShutdownSignal() {
  closing_ = true;
  // Wake the sigwait() thread with a signal aimed only at it.
  pthread_kill(thread_.native_handle(), kWakeSignal);
  thread_.join();
}

void ShutdownSignal::run() {
  const sigset_t set = handled_signals();
  while (true) {
    int sig = 0;
    if (sigwait(&set, &sig) != 0) {
      continue;
    }
    if (closing_) {
      return;
    }
    if (sig != kWakeSignal) {
      request(sig);
    }
  }
}

void ShutdownSignal::request(int signal_number) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!requested_) {
      signal_number_ = signal_number;
    }
    requested_ = true;
  }
  cv_.notify_all();
  // Called under listener_mutex_, so set_listener() (a guard going out of
  // scope) waits for a call in progress: the listener's target (an event
  // queue on the caller's stack) outlives every call (TSan saw a wake()
  // still running while the queue was destroyed).
  std::lock_guard<std::mutex> lock(listener_mutex_);
  if (listener_) {
    listener_();
  }
}

void ShutdownSignal::set_listener(std::function<void()> listener) {
  std::lock_guard<std::mutex> lock(listener_mutex_);
  listener_ = std::move(listener);
}

void ShutdownSignal::poke() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++pokes_;
  }
  cv_.notify_all();
}

bool ShutdownSignal::wait_for(std::chrono::milliseconds timeout) {
  return wait_until(std::chrono::steady_clock::now() + timeout);
}

bool ShutdownSignal::wait_until(std::chrono::steady_clock::time_point deadline) {
  std::unique_lock<std::mutex> lock(mutex_);
  const std::uint64_t pokes = pokes_;
  cv_.wait_until(lock, deadline, [&] { return requested_.load() || pokes_ != pokes; });
  return requested_;
}

}  // namespace mtc::cli
