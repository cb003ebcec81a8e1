// A test's hand on the wall clock. Linked into a test executable (a shared
// library ahead of libc in the lookup order), it interposes clock_gettime,
// gettimeofday and time and adds an offset the test sets: CLOCK_REALTIME
// then steps under the running process, Fast DDS included, as it does on a
// shop floor when NTP corrects a drifted controller, an operator sets the
// time, or a VM restored from a snapshot jumps ahead. Every other clock
// (CLOCK_MONOTONIC above all) passes through untouched, and the kernel's
// clock never moves: nothing outside this process sees the step.
#include "realtime_shift.hpp"

#include <dlfcn.h>
#include <sys/time.h>
#include <time.h>

#include <atomic>
#include <cstdint>

namespace {

std::atomic<std::int64_t> g_offset_ns{0};

using ClockGettime = int (*)(clockid_t, timespec*);

// libc's own (or a sanitizer's interceptor of it); found once, on first use.
ClockGettime next_clock_gettime() noexcept {
  static const auto next = reinterpret_cast<ClockGettime>(dlsym(RTLD_NEXT, "clock_gettime"));
  return next;
}

bool is_realtime(clockid_t id) noexcept {
  return id == CLOCK_REALTIME || id == CLOCK_REALTIME_COARSE;
}

void shift(timespec& ts, std::int64_t offset_ns) noexcept {
  constexpr std::int64_t kNsPerS = 1000000000;
  std::int64_t ns = static_cast<std::int64_t>(ts.tv_nsec) + offset_ns % kNsPerS;
  std::int64_t s = static_cast<std::int64_t>(ts.tv_sec) + offset_ns / kNsPerS;
  if (ns < 0) {
    ns += kNsPerS;
    --s;
  } else if (ns >= kNsPerS) {
    ns -= kNsPerS;
    ++s;
  }
  ts.tv_sec = static_cast<time_t>(s);
  ts.tv_nsec = static_cast<long>(ns);
}

int real_now(timespec& ts) noexcept {
  const auto next = next_clock_gettime();
  if (next == nullptr) return -1;
  const int rc = next(CLOCK_REALTIME, &ts);
  if (rc == 0) shift(ts, g_offset_ns.load(std::memory_order_relaxed));
  return rc;
}

}  // namespace

extern "C" {

void mtc_test_shift_realtime(std::int64_t offset_ns) noexcept {
  g_offset_ns.fetch_add(offset_ns, std::memory_order_relaxed);
}

std::int64_t mtc_test_realtime_offset() noexcept {
  return g_offset_ns.load(std::memory_order_relaxed);
}

// NOLINTBEGIN(readability-inconsistent-declaration-parameter-name): libc's names
int clock_gettime(clockid_t id, timespec* ts) noexcept {
  const auto next = next_clock_gettime();
  if (next == nullptr) return -1;
  const int rc = next(id, ts);
  if (rc == 0 && is_realtime(id)) shift(*ts, g_offset_ns.load(std::memory_order_relaxed));
  return rc;
}

int gettimeofday(timeval* tv, void* /*tz: obsolete, never set by callers here*/) noexcept {
  timespec ts{};
  const int rc = real_now(ts);
  if (rc == 0) {  // glibc declares tv nonnull
    tv->tv_sec = ts.tv_sec;
    tv->tv_usec = static_cast<suseconds_t>(ts.tv_nsec / 1000);
  }
  return rc;
}

time_t time(time_t* out) noexcept {
  timespec ts{};
  if (real_now(ts) != 0) return static_cast<time_t>(-1);
  if (out != nullptr) *out = ts.tv_sec;
  return ts.tv_sec;
}
// NOLINTEND(readability-inconsistent-declaration-parameter-name)

}  // extern "C"
