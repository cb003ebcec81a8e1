// What the `mtc request` / `mtc respond` loops learn from the runtime, as
// plain values in one queue. Runtime callbacks only push here; the command's
// main thread pops and decides, so all of a command's logic runs on one
// thread and never inside a middleware callback.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <string>

#include "mtc/core/result.hpp"
#include "mtc/core/vocabulary.hpp"

namespace mtc::cli {

// How one handshake ended, as the tool reports it.
// Excluded: the responder interface serves another requester (its pairing).
enum class Result : std::uint8_t {
  Complete,
  Fail,
  Timeout,
  CommsLost,
  NotReady,
  Interrupted,
  Excluded
};

struct LinkEvent {
  enum class Kind : std::uint8_t {
    OwnState,             // our data item changed (state)
    CounterpartState,     // the counterpart's data item changed (state)
    CounterpartLost,      // heartbeat / liveliness lost (scenario 6)
    CounterpartRestored,  // first value after a loss
    Notice,               // anything else the runtime reports (notice, reason)
    RequestObserved,      // responder: the request went ACTIVE, accept() or not
    RequestDone,          // requester: the runtime's outcome of request()
    Aborted,              // responder: the service in progress ended without complete()
    Excluded,             // the counterpart is paired with another (detail says with whom)
    Readmitted,           // it names us (or nobody) again
  };
  Kind kind = Kind::Notice;
  core::Service service = core::Service::MaterialLoad;
  core::InteractionState state = core::InteractionState::Unavailable;
  core::Notice notice = core::Notice::None;
  core::Reason reason = core::Reason::None;
  std::int64_t source_time_ns = 0;     // writer's clock, counterpart samples only
  std::uint64_t sequence_number = 0;   // counterpart samples: writer's change counter
  bool redelivered = false;            // the last known value again, after a loss
  std::int64_t reception_time_ns = 0;  // local wall clock when it happened
  Result result = Result::Fail;        // RequestDone
  std::string detail;                  // cause of a loss, diagnostics
};

class EventQueue {
 public:
  void push(LinkEvent event);
  // Next event, or nullopt when the deadline passes or wake() was called.
  std::optional<LinkEvent> pop_until(std::chrono::steady_clock::time_point deadline);
  // Makes a waiting pop_until return (shutdown requested).
  void wake();

 private:
  std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<LinkEvent> events_;
  std::uint64_t wakes_ = 0;
};

}  // namespace mtc::cli
