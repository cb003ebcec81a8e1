// Names of the QoS profiles of mtc::qos that --qos-profile accepts (endpoint
// presets and participant profiles, as in the XML profiles file), so a typo
// is a usage error (exit 2) instead of a DDS failure deep in the runtime.
#pragma once

#include <optional>
#include <string>

#include "mtc/qos/participant.hpp"

namespace mtc::cli {

bool is_known_profile(const std::string& name);
// The transport of a participant profile name, nullopt for other names.
std::optional<qos::Transport> participant_profile_transport(const std::string& name);
// "a, b, c" for help texts and error messages.
std::string known_profiles_text();

}  // namespace mtc::cli
