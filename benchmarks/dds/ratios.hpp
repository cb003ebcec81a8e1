// Every series of one run read against the baselines of the same run: the
// raw Fast DDS round trip with the echo written from the listener (the
// fastest ping-pong the library offers) over the same transport, the raw
// UDP round trip (the machine's limit) and Cyclone DDS's round trip; and
// issue 9's section 2 targets, met or not.
#pragma once

#include <cstdio>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "latency_stats.hpp"

namespace mtc::bench {

struct Reference {
  double p50 = 0, p99 = 0;
};

inline std::optional<Reference> reference(const std::vector<Series>& all, const std::string& name) {
  for (const auto& s : all) {
    if (s.name == name && !s.samples_us.empty()) {
      const Summary sum = summarize(s.samples_us);
      return Reference{sum.p50, sum.p99};
    }
  }
  return std::nullopt;
}

inline std::string ratio_text(double value, const std::optional<Reference>& ref, bool p99) {
  if (!ref || (p99 ? ref->p99 : ref->p50) <= 0) {
    return "null";
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", value / (p99 ? ref->p99 : ref->p50));
  return buf;
}

inline std::string listener_name(const std::string& transport) {
  return "raw_fastdds_listener_round_trip_" + transport + "_2proc";
}

// [{"series":...,"p50_vs_fastdds_listener_rtt":...,...}, ...]; a series
// compares with the listener round trip over its own transport.
inline std::string ratios_json(const std::vector<Series>& all, std::optional<Reference> cyclone) {
  const auto udp = reference(all, "udp_round_trip_2proc");
  std::ostringstream json;
  json << "[";
  bool first = true;
  for (const auto& s : all) {
    if (s.samples_us.empty()) {
      continue;
    }
    const Summary sum = summarize(s.samples_us);
    const auto listener = reference(all, listener_name(s.transport));
    json << (first ? "\n  " : ",\n  ") << "{\"series\":\"" << s.name
         << "\",\"p50_vs_fastdds_listener_rtt\":" << ratio_text(sum.p50, listener, false)
         << ",\"p99_vs_fastdds_listener_rtt\":" << ratio_text(sum.p99, listener, true)
         << ",\"p50_vs_udp_rtt\":" << ratio_text(sum.p50, udp, false)
         << ",\"p99_vs_udp_rtt\":" << ratio_text(sum.p99, udp, true)
         << ",\"p50_vs_cyclone_rtt\":" << ratio_text(sum.p50, cyclone, false)
         << ",\"p99_vs_cyclone_rtt\":" << ratio_text(sum.p99, cyclone, true) << "}";
    first = false;
  }
  json << "\n]";
  return json.str();
}

// Issue 9 section 3: both ends on Cyclone DDS, two processes, handshake
// p50 <= 60 us and p99 <= 250 us. Absolute figures, set when ddsperf's round
// trip was 11 us here: also printed as ratios to this run's Cyclone round
// trip, so a slower machine can be read against them.
inline std::string cyclone_target_json(const std::vector<Series>& all,
                                       const std::optional<Reference>& cyclone,
                                       const std::string& mode) {
  const auto handshake = reference(all, "mtc_handshake_cyclone_udp_loopback_2proc" + mode);
  if (!handshake) {
    return "";
  }
  constexpr double kP50MaxUs = 60;
  constexpr double kP99MaxUs = 250;
  std::ostringstream json;
  json << "\"cyclone_udp_loopback" << mode << "\":{\"handshake_p50_max_us\":" << kP50MaxUs
       << ",\"handshake_p50_us\":" << handshake->p50
       << ",\"handshake_p50_met\":" << (handshake->p50 <= kP50MaxUs ? "true" : "false")
       << ",\"handshake_p99_max_us\":" << kP99MaxUs << ",\"handshake_p99_us\":" << handshake->p99
       << ",\"handshake_p99_met\":" << (handshake->p99 <= kP99MaxUs ? "true" : "false")
       << ",\"handshake_p50_vs_cyclone_rtt\":" << ratio_text(handshake->p50, cyclone, false)
       << ",\"handshake_p99_vs_cyclone_rtt\":" << ratio_text(handshake->p99, cyclone, true) << "}";
  return json.str();
}

// "mtc_<metric>_<transport>_2proc<mode>", mode "", "_executor", "_inline" or
// "_inline_packed".
inline std::string two_process_series(const char* metric, const std::string& transport,
                                      const std::string& mode) {
  std::string name = "mtc_";
  name.append(metric).append("_").append(transport).append("_2proc").append(mode);
  return name;
}

// One transport's section 2 targets: "<transport>":{...}.
inline std::string transport_target_json(const std::string& key, const Reference& listener,
                                         const Reference& transition, const Reference& handshake) {
  const bool transition_ok = transition.p50 <= 1.15 * listener.p50 / 2;
  const bool handshake_p50_ok = handshake.p50 <= 2.3 * listener.p50;
  const bool handshake_p99_ok = handshake.p99 <= 3 * listener.p99;
  std::ostringstream json;
  json << "\"" << key << "\":{\"transition_p50_max_us\":" << 1.15 * listener.p50 / 2
       << ",\"transition_p50_us\":" << transition.p50
       << ",\"transition_p50_met\":" << (transition_ok ? "true" : "false")
       << ",\"handshake_p50_max_us\":" << 2.3 * listener.p50
       << ",\"handshake_p50_us\":" << handshake.p50
       << ",\"handshake_p50_vs_listener_rtt\":" << ratio_text(handshake.p50, listener, false)
       << ",\"handshake_p50_met\":" << (handshake_p50_ok ? "true" : "false")
       << ",\"handshake_p99_max_us\":" << 3 * listener.p99
       << ",\"handshake_p99_us\":" << handshake.p99
       << ",\"handshake_p99_met\":" << (handshake_p99_ok ? "true" : "false") << "}";
  return json.str();
}

// Issue 9 section 2, two processes, per transport: transition p50 <= 1.15x
// half the listener round trip; handshake p50 <= 2.3x and p99 <= 3x it. And
// section 3's Cyclone target, when that series ran. Per stepping mode that
// ran: "shm_udp" is the runtime's default, "shm_udp_executor" with
// steps_on_executor, "shm_udp_inline" with inline_steps, "shm_udp_inline_packed"
// with pack_callback_writes too.
inline std::string targets_json(const std::vector<Series>& all,
                                const std::optional<Reference>& cyclone) {
  std::ostringstream json;
  json << "{";
  bool first = true;
  for (const std::string mode : {"", "_executor", "_inline", "_inline_packed"}) {
    for (const std::string transport : {"shm_udp", "udp_loopback"}) {
      const auto listener = reference(all, listener_name(transport));
      const auto transition = reference(all, two_process_series("transition", transport, mode));
      const auto handshake = reference(all, two_process_series("handshake", transport, mode));
      if (!listener || !transition || !handshake) {
        continue;
      }
      json << (first ? "" : ",")
           << transport_target_json(transport + mode, *listener, *transition, *handshake);
      first = false;
    }
    if (const auto c = cyclone_target_json(all, cyclone, mode); !c.empty()) {
      json << (first ? "" : ",") << c;
      first = false;
    }
  }
  json << "}";
  return json.str();
}

}  // namespace mtc::bench
