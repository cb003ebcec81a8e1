#include <string>

#include "commands.hpp"
#include "profiles.hpp"

namespace mtc::cli {

void add_common_options(CommandSpec& spec) {
  spec.options.push_back({"domain", "N", "DDS domain id (0-232)", "0"});
  spec.options.push_back(
      {"qos-profile", "NAME",
       "participant QoS profile, which selects the transport (" + known_profiles_text() + ")",
       "none: --transport"});
  spec.options.push_back({"security", "DIR",
                          "DDS-Security identity directory (scripts/security/make-pki.sh)",
                          "unsecured"});
  spec.options.push_back({"json", "", "print one JSON object per line (for scripts)", ""});
}

CommonOptions parse_common_options(const ParsedArgs& args) {
  CommonOptions common;
  if (auto d = args.value("domain")) {
    common.domain = static_cast<int>(to_int("domain", *d, 0, 232));
  }
  if (auto p = args.value("qos-profile")) {
    if (is_endpoint_preset(*p)) {
      throw UsageError("--qos-profile '" + *p +
                       "' is an endpoint preset, which the runtime picks per topic from "
                       "--heartbeat-ms / --missed-heartbeats; give a participant profile (" +
                       known_profiles_text() + ")");
    }
    if (!is_known_profile(*p)) {
      throw UsageError("unknown QoS profile '" + *p + "' (known: " + known_profiles_text() + ")");
    }
    common.profile_transport = participant_profile_transport(*p);
  }
  common.json = args.has("json");
  common.security_dir = args.value_or("security", "");
  return common;
}

}  // namespace mtc::cli
