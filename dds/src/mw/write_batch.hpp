// Internal: writes made on one thread in a burst, sent together.
//
// Cyclone DDS packs the samples a writer was given into one RTPS message
// when it is told to hold them (its WriteBatch setting) and sends them on
// dds_write_flush: one sendmsg, and one recvmsg at each reader, for a burst
// of samples instead of one each. On this machine a system call is the
// costliest thing a handshake does (issue 9, section 4). The executor opens a
// WriteBatch around each batch of work it runs; a write made outside any
// batch is sent at once, as before.
#pragma once

#include <cstdint>

namespace mtc::dds::mw {

class WriteBatch {
 public:
  using Flush = void (*)(std::int64_t handle) noexcept;

  WriteBatch() noexcept;
  // The outermost batch of the thread sends what its writes left queued.
  ~WriteBatch();
  WriteBatch(const WriteBatch&) = delete;
  WriteBatch& operator=(const WriteBatch&) = delete;
  WriteBatch(WriteBatch&&) = delete;
  WriteBatch& operator=(WriteBatch&&) = delete;

  // For a writer that holds what it writes: true while a batch is open on
  // this thread, and flush(handle) will then be called once when it ends;
  // false: nothing is open, and the caller must send now.
  static bool defer(Flush flush, std::int64_t handle);
  // Sends what the open batch holds so far, and keeps it open: before an
  // application callback that runs with a step, so that what the step
  // wrote is on the wire before the callback (which may block) runs.
  static void send_now();
};

}  // namespace mtc::dds::mw
