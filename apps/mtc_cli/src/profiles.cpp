#include "profiles.hpp"

#include <algorithm>

#include "mtc/qos/presets.hpp"

namespace mtc::cli {

bool is_known_profile(const std::string& name) {
  const auto names = qos::preset_names();
  return std::find(names.begin(), names.end(), name) != names.end();
}

std::string known_profiles_text() {
  std::string text;
  for (const auto& n : qos::preset_names()) {
    text += (text.empty() ? "" : ", ") + n;
  }
  return text;
}

}  // namespace mtc::cli
