#include "profiles.hpp"

#include <algorithm>
#include <vector>

#include "mtc/qos/presets.hpp"

namespace mtc::cli {

namespace {
std::vector<std::string> all_profile_names() {
  return {std::string(qos::kLoopbackParticipantProfile),
          std::string(qos::kLoopbackUdpParticipantProfile)};
}
}  // namespace

bool is_known_profile(const std::string& name) {
  const auto names = all_profile_names();
  return std::find(names.begin(), names.end(), name) != names.end();
}

std::optional<qos::Transport> participant_profile_transport(const std::string& name) {
  if (name == qos::kLoopbackParticipantProfile || name == qos::kLoopbackUdpParticipantProfile) {
    return qos::participant_config(name).transport;
  }
  return std::nullopt;
}

bool is_endpoint_preset(const std::string& name) {
  const auto presets = qos::preset_names();
  return std::find(presets.begin(), presets.end(), name) != presets.end();
}

std::string known_profiles_text() {
  std::string text;
  for (const auto& n : all_profile_names()) {
    text += (text.empty() ? "" : ", ") + n;
  }
  return text;
}

}  // namespace mtc::cli
