// Timing record of one handshake as one side saw it, and its rendering:
// every transition of the request and the response with its time since the
// handshake began and, for the counterpart's samples, the source -> reception
// latency; then the outcome. Shared by `mtc request` and `mtc respond`.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "link_events.hpp"
#include "output.hpp"

namespace mtc::cli {

std::string_view to_string(Result r);
int exit_code(Result r);

class HandshakeTrace {
 public:
  HandshakeTrace(Output& out, bool json, core::Role own_role)
      : out_(out), json_(json), role_(own_role) {}

  // Starts a new handshake (number n) now.
  void begin(std::uint64_t n, core::Service service);
  // Restarts the clock (t = 0) without a new number: the requester measures
  // from the moment it issues the request, not from when it began waiting.
  void restart_clock() {
    start_ = std::chrono::steady_clock::now();
    waiting_ = false;
  }
  // Requester: between begin() and restart_clock() it waits for READY.
  void set_waiting() { waiting_ = true; }
  std::uint64_t number() const { return n_; }
  core::Service service() const { return service_; }
  bool active() const { return n_ != 0; }
  // Prints a state change of our item (own = true) or the counterpart's.
  void transition(bool own, const LinkEvent& event);
  // Milliseconds since begin() at which `side:state` was first seen, if it was.
  std::optional<double> first_ms(bool own, core::InteractionState s) const;
  double elapsed_ms() const;
  // Prints the outcome line.
  void outcome(Result result, const std::string& reason);
  // Prints a free-form event line (peer_lost, inject, ...) tagged with the handshake.
  void note(const std::string& event, const std::string& detail);

 private:
  struct Step {
    bool own;
    core::InteractionState state;
    double t_ms;
  };
  std::string side(bool own) const;

  Output& out_;
  bool json_;
  core::Role role_;
  std::uint64_t n_ = 0;
  core::Service service_ = core::Service::MaterialLoad;
  std::chrono::steady_clock::time_point start_{};
  bool waiting_ = false;
  std::vector<Step> steps_;
};

}  // namespace mtc::cli
