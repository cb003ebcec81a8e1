// Names of the QoS profiles of mtc::qos that --qos-profile accepts: the
// participant profiles of the XML profiles file, which select the transport.
// Endpoint presets are not selectable: every topic's QoS follows from its
// role and the heartbeat flags. A typo is a usage error (exit 2).
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
// True for the name of an endpoint preset ("mtc.state"), to explain why it
// is refused.
bool is_endpoint_preset(const std::string& name);

}  // namespace mtc::cli
