// Steps CLOCK_REALTIME of this process (tests/support/realtime_shift.cpp).
// Only a test executable linked with mtc_test_realtime_shift has these.
#pragma once

#include <cstdint>

extern "C" {
// Moves the wall clock by `offset_ns` (negative: back), on top of earlier steps.
void mtc_test_shift_realtime(std::int64_t offset_ns) noexcept;
// The sum of the steps so far.
std::int64_t mtc_test_realtime_offset() noexcept;
}
