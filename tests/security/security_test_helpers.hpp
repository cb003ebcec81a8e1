// What the DDS-Security tests share beyond the PKI (security_pki.hpp): the
// timing of secured peers, and the text of an exception.
#pragma once

#include <chrono>
#include <exception>
#include <functional>
#include <string>

#include "mtc/qos/timing.hpp"

namespace mtc::security_test {

// A 1 s lease: security handshakes and crypto on 2 shared cores must not
// look like a lost peer.
inline qos::Timing secured_timing() {
  qos::Timing t;
  t.heartbeat = std::chrono::milliseconds(200);
  t.missed_heartbeats = 5;
  return t;
}

// The message of what `fn` throws, or "(no exception)".
inline std::string what_of(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no exception)";
}

}  // namespace mtc::security_test
