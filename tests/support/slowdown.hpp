// How much slower than a plain build the programs under test run:
// MTC_TEST_SLOWDOWN, which scripts/test.sh sets for the sanitizer phases
// (ASan 2, TSan 3) and leaves unset (1) otherwise. Only for the few waits
// whose premise is "a process starts within X" (a pairing settle window,
// say), never for the bounds a test asserts about the runtime: a TSan
// process takes seconds to start on two busy cores, which a window sized
// for the plain build does not cover.
#pragma once

#include <chrono>
#include <cstdlib>
#include <string>

namespace mtc::test {

inline int test_slowdown() {
  const char* text = std::getenv("MTC_TEST_SLOWDOWN");  // NOLINT(concurrency-mt-unsafe)
  if (text == nullptr) return 1;
  char* end = nullptr;
  const long factor = std::strtol(text, &end, 10);
  if (end == text || *end != '\0' || factor < 1) return 1;
  return factor > 10 ? 10 : static_cast<int>(factor);
}

inline std::chrono::milliseconds slowed(std::chrono::milliseconds plain) {
  return plain * test_slowdown();
}

// A duration as `mtc` options take it ("2500ms").
inline std::string as_option(std::chrono::milliseconds d) {
  return std::to_string(d.count()) + "ms";
}

}  // namespace mtc::test
