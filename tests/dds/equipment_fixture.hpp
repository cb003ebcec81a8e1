// Shared helpers of the Equipment tests: a thread-safe recorder of every
// callback, and waits on its condition variable (never sleeps).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <vector>

#include "mtc/dds/equipment.hpp"
#include "transport.hpp"

namespace mtc::dds::testing {

using namespace std::chrono_literals;
using core::InteractionState;
using core::Service;

// Generous: CI runs on 2 shared cores.
inline constexpr auto kTimeout = 15s;

// What a recorder of callbacks holds: a change made through add() (under
// the mutex) wakes whoever waits on cv_ for it.
class Guarded {
 protected:
  template <typename Fn>
  void add(Fn fn) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      fn();
    }
    cv_.notify_all();
  }
  std::mutex mutex_;
  std::condition_variable cv_;
};

class Recorder : private Guarded {
 public:
  EquipmentCallbacks callbacks() {
    EquipmentCallbacks cb;
    cb.on_transition = [this](const TransitionEvent& e) {
      add([&] { transitions_.push_back(e); });
    };
    cb.on_link = [this](const LinkEvent& e) { add([&] { links_.push_back(e); }); };
    cb.on_counterpart_value = [this](const ObservedValue& v) {
      add([&] { values_.push_back(v); });
    };
    cb.on_diagnostic = [this](const std::string& d) { add([&] { diagnostics_.push_back(d); }); };
    return cb;
  }
  // Wakes waiters; for callbacks the test installs itself.
  void notify() {
    add([] {});
  }

  template <typename Pred>
  bool wait(Pred pred, std::chrono::milliseconds timeout = kTimeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    return cv_.wait_for(lock, timeout, [&] { return pred(); });
  }
  bool wait_state(const ServiceHandle& h, InteractionState s,
                  std::chrono::milliseconds timeout = kTimeout) {
    return wait([&] { return h.state() == s; }, timeout);
  }
  // Until the link is `s` and its on_link said so: by default callbacks run
  // after the step that the snapshot (link_state) already shows, and a
  // test that reads links() next must find the event there.
  bool wait_link(const Equipment& e, const std::string& itf, LinkState s,
                 std::chrono::milliseconds timeout = kTimeout) {
    return wait([&] { return e.link_state(itf) == s && last_link_locked(itf) == s; }, timeout);
  }
  std::vector<TransitionEvent> transitions() {
    std::lock_guard<std::mutex> lock(mutex_);
    return transitions_;
  }
  std::vector<LinkEvent> links() {
    std::lock_guard<std::mutex> lock(mutex_);
    return links_;
  }
  // Every counterpart value handed to the application, in order.
  std::vector<ObservedValue> values() {
    std::lock_guard<std::mutex> lock(mutex_);
    return values_;
  }
  // Everything seen, for failure messages.
  std::string dump() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::string out;
    for (const auto& l : links_) {
      out += "  link " + l.interface_id + " " + std::string(to_string(l.previous)) + " -> " +
             std::string(to_string(l.current)) + " (" + l.cause + ")\n";
    }
    for (const auto& e : transitions_) {
      out += "  " + std::string(core::to_string(e.step.service)) + "/" +
             std::string(core::to_string(e.step.role)) + " " +
             std::string(core::to_string(e.step.event)) + ": " +
             std::string(core::to_string(e.step.previous)) + " -> " +
             std::string(core::to_string(e.step.current)) + " " +
             std::string(core::to_string(e.step.notice)) + "/" +
             std::string(core::to_string(e.step.reason)) + "\n";
    }
    for (const auto& d : diagnostics_) out += "  diag " + d + "\n";
    return out;
  }
  // Waits for a diagnostic (EquipmentCallbacks::on_diagnostic) containing `text`.
  bool wait_diagnostic(const std::string& text, std::chrono::milliseconds timeout = kTimeout) {
    return wait(
        [&] {
          return std::any_of(diagnostics_.begin(), diagnostics_.end(), [&](const std::string& d) {
            return d.find(text) != std::string::npos;
          });
        },
        timeout);
  }
  // Waits for a transition that `match` accepts (called under the lock:
  // it must not call the Recorder).
  template <typename Match>
  bool wait_transition(Match match, std::chrono::milliseconds timeout = kTimeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    return cv_.wait_for(lock, timeout, [&] {
      return std::any_of(transitions_.begin(), transitions_.end(), match);
    });
  }
  // Waits until `done` accepts the values seen so far (called under the
  // lock: it must not call the Recorder).
  template <typename Done>
  bool wait_values(Done done, std::chrono::milliseconds timeout = kTimeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    return cv_.wait_for(lock, timeout, [&] { return done(values_); });
  }
  bool saw_notice(core::Notice n, core::Reason r) {
    std::lock_guard<std::mutex> lock(mutex_);
    return saw_notice_locked(n, r);
  }
  bool wait_notice(core::Notice n, core::Reason r, std::chrono::milliseconds timeout = kTimeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    return cv_.wait_for(lock, timeout, [&] { return saw_notice_locked(n, r); });
  }

 private:
  LinkState last_link_locked(const std::string& itf) const {
    for (auto l = links_.rbegin(); l != links_.rend(); ++l) {
      if (l->interface_id == itf) return l->current;
    }
    return LinkState::Unpaired;
  }
  bool saw_notice_locked(core::Notice n, core::Reason r) const {
    return std::any_of(transitions_.begin(), transitions_.end(), [&](const TransitionEvent& e) {
      return e.step.notice == n && e.step.reason == r;
    });
  }
  std::vector<TransitionEvent> transitions_;
  std::vector<LinkEvent> links_;
  std::vector<ObservedValue> values_;
  std::vector<std::string> diagnostics_;
};

// On the test middleware (MTC_TEST_MIDDLEWARE), like loopback<T>(): the
// cyclone phase of .ci/run must run these cases on Cyclone DDS, not only
// their observers. Fault injection (LoopbackTest) is Fast DDS's own
// transport, so those cases stay on Fast DDS; a case that means one
// middleware sets it after this.
inline EquipmentOptions options(int domain, const std::string& uuid,
                                qos::Transport transport = qos::Transport::Loopback) {
  auto o = mtc::test::loopback<EquipmentOptions>();
  o.domain_id = domain;
  o.device_uuid = uuid;
  o.transport = transport;
  if (transport == qos::Transport::LoopbackTest) o.middleware = Middleware::FastDds;
  return o;
}

}  // namespace mtc::dds::testing
