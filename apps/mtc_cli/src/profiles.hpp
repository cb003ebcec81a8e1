// Names of the QoS presets of mtc::qos that --qos-profile accepts, so a typo
// is a usage error (exit 2) instead of a DDS failure deep in the runtime.
#pragma once

#include <string>

namespace mtc::cli {

bool is_known_profile(const std::string& name);
// "a, b, c" for help texts and error messages.
std::string known_profiles_text();

}  // namespace mtc::cli
