// Where both ends of a benchmark's pairs step their machines
// (mtc::dds::EquipmentOptions): the runtime's default (on the thread that
// brings a value, callbacks on the executor thread), steps_on_executor, or
// inline_steps (steps and callbacks on the thread that brought the step),
// also with pack_callback_writes (a step's writes leave with its callbacks').
// Shared by mtc-bench-dds-latency and mtc-bench-scale, so that a mode has
// one name in every JSON and one flag for every forked peer.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mtc/dds/equipment.hpp"

namespace mtc::bench {

enum class Stepping { Default, Executor, Inline, InlinePacked };

// The JSON value: "default", "executor", "inline", "inline_packed".
inline const char* to_string(Stepping s) noexcept {
  switch (s) {
    case Stepping::Executor:
      return "executor";
    case Stepping::Inline:
      return "inline";
    case Stepping::InlinePacked:
      return "inline_packed";
    case Stepping::Default:
      break;
  }
  return "default";
}

// The mode a JSON name (to_string) stands for; Default for any other text.
inline Stepping stepping_named(std::string_view name) noexcept {
  for (const auto s : {Stepping::Executor, Stepping::Inline, Stepping::InlinePacked}) {
    if (name == to_string(s)) return s;
  }
  return Stepping::Default;
}

inline constexpr const char* kPackNeedsInlineSteps = "--pack-callback-writes needs --inline-steps";

// The mode the single-mode flags (--steps-on-executor, --inline-steps,
// --pack-callback-writes) ask for: the latest in Stepping's order that one
// of them names. nullopt when --pack-callback-writes comes without
// --inline-steps (kPackNeedsInlineSteps; the runtime's ConfigError).
inline std::optional<Stepping> stepping_from_flags(bool on_executor, bool inline_steps,
                                                   bool pack) noexcept {
  if (pack && !inline_steps) return std::nullopt;
  if (pack) return Stepping::InlinePacked;
  if (inline_steps) return Stepping::Inline;
  return on_executor ? Stepping::Executor : Stepping::Default;
}

inline void apply(Stepping s, mtc::dds::EquipmentOptions& o) noexcept {
  o.steps_on_executor = s == Stepping::Executor;
  o.inline_steps = s == Stepping::Inline || s == Stepping::InlinePacked;
  o.pack_callback_writes = s == Stepping::InlinePacked;
}

// The flag a forked peer is started with, if any.
inline void append_peer_flag(Stepping s, std::vector<std::string>& args) {
  if (s == Stepping::Executor) args.emplace_back("--steps-on-executor");
  if (s == Stepping::Inline || s == Stepping::InlinePacked) args.emplace_back("--inline-steps");
  if (s == Stepping::InlinePacked) args.emplace_back("--pack-callback-writes");
}

}  // namespace mtc::bench
