// The agent.cfg file format: `Key = Value` lines, `#` comments, and the
// reference agent's `Name { ... }` blocks, which mtc-bridge skips. Values go
// through the settings table of bridge_config.cpp (apply_config_value).
#include <map>
#include <optional>
#include <string>
#include <utility>

#include "bridge_config.hpp"
#include "mtc/bridge/bounded_file.hpp"

namespace mtc::bridge {
namespace {

[[noreturn]] void fail(const std::string& origin, const std::string& message) {
  throw ConfigError(origin + ": " + message);
}

std::string_view trim(std::string_view text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) {
    return {};
  }
  const auto last = text.find_last_not_of(" \t\r");
  return text.substr(first, last - first + 1);
}

// Drops a '#' comment; a '#' inside a double-quoted value is kept.
std::string_view strip_comment(std::string_view line) {
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    if (line[i] == '"') {
      quoted = !quoted;
    }
    if (line[i] == '#' && !quoted) {
      return line.substr(0, i);
    }
  }
  return line;
}

// Keys of the reference agent's agent.cfg (cppagent 2.x) that mtc-bridge
// has no use for: accepted with a warning, so that an integrator can reuse
// their file. Anything else unknown is still an error (a typo must not go
// unnoticed).
constexpr std::string_view kReferenceAgentKeys =
    "AgentDeviceUUID AllowPut AllowPutFrom AutoAvailable CheckpointFrequency ConversionRequired "
    "CreateUniqueIds DisableAgentDevice FilterDuplicates Heartbeat HttpHeaders IgnoreTimestamps "
    "JsonVersion LegacyTimeout LogStreams MaxAssets MaxCachedFileSize MinCompressFileSize "
    "MinimumConfigReloadAge MonitorConfigFiles MonitorInterval MqttHost MqttPort MqttTls PidFile "
    "PreserveUUID Pretty ReconnectInterval RelativeTime ServiceName ShdrVersion SuppressIPAddress "
    "TlsCertificatePassword TlsClientCAs TlsDHKey TlsOnly TlsVerifyClientCertificate "
    "UpcaseDataItemValue VersionDeviceXmlUpdates";
// Its blocks (`Name { ... }`, nested): adapters, sinks, file serving, logging.
constexpr std::string_view kReferenceAgentBlocks =
    "Adapters Sinks Sources Files Directories logger_config Ruby";

// True when `name` is one of the space-separated words of `names`.
bool listed(std::string_view names, std::string_view name) {
  if (name.empty()) {
    return false;
  }
  for (std::size_t at = names.find(name); at != std::string_view::npos;
       at = names.find(name, at + 1)) {
    const std::size_t end = at + name.size();
    if ((at == 0 || names[at - 1] == ' ') && (end == names.size() || names[end] == ' ')) {
      return true;
    }
  }
  return false;
}

// A `Name {` ... `}` block of the reference agent being skipped.
struct OpenBlock {
  std::string name;
  std::size_t line = 0;
  int depth = 0;  // braces open
};

// Braces outside double quotes: +1 per '{', -1 per '}'.
int brace_balance(std::string_view line) {
  int balance = 0;
  bool quoted = false;
  for (const char c : line) {
    if (c == '"') {
      quoted = !quoted;
    } else if (!quoted && c == '{') {
      ++balance;
    } else if (!quoted && c == '}') {
      --balance;
    }
  }
  return balance;
}

// Handles a line that opens a block; returns the block to skip.
OpenBlock open_block(std::string_view line, std::size_t number, const std::string& where,
                     std::vector<std::string>& warnings) {
  const auto brace = line.find('{');
  if (brace == std::string_view::npos || brace == 0) {
    fail(where, "unexpected '" + std::string(1, line[line.find_first_of("{}")]) + "'");
  }
  const std::string name(trim(line.substr(0, brace)));
  if (!listed(kReferenceAgentBlocks, name)) {
    fail(where, "unknown block '" + name + "' (mtc-bridge reads no blocks; it skips those of " +
                    "the reference agent)");
  }
  warnings.push_back(where + ": block '" + name +
                     "' of the reference agent is not used by mtc-bridge; ignored");
  return OpenBlock{name, number, brace_balance(line)};
}

// `Key = Value`, the value unquoted.
std::pair<std::string_view, std::string_view> split_key_value(std::string_view line,
                                                              const std::string& where) {
  const auto eq = line.find('=');
  if (eq == std::string_view::npos) {
    fail(where, "expected 'Key = Value', got '" + std::string(line) + "'");
  }
  const auto key = trim(line.substr(0, eq));
  auto value = trim(line.substr(eq + 1));
  if (key.empty()) {
    fail(where, "missing key before '='");
  }
  if (value.size() >= 2 && value.front() == '"' && value.back() == '"') {
    value = value.substr(1, value.size() - 2);
  }
  return {key, value};
}

}  // namespace

std::vector<std::string> parse_config_text(BridgeConfig& config, std::string_view text,
                                           std::string_view name) {
  std::vector<std::string> warnings;
  std::map<std::string, std::size_t, std::less<>> seen;  // key -> line
  std::optional<OpenBlock> block;
  std::size_t number = 0;
  std::size_t start = 0;
  while (start < text.size()) {
    auto end = text.find('\n', start);
    if (end == std::string_view::npos) {
      end = text.size();
    }
    std::string_view line = text.substr(start, end - start);
    start = end + 1;
    ++number;
    const std::string where = std::string(name) + ":" + std::to_string(number);
    if (line.find('\0') != std::string_view::npos) {
      fail(where, "binary data in config file");
    }
    line = trim(strip_comment(line));
    if (block) {
      block->depth += brace_balance(line);
      if (block->depth <= 0) {
        block.reset();
      }
      continue;
    }
    if (line.empty()) {
      continue;
    }
    if (line.find_first_of("{}") != std::string_view::npos) {
      block = open_block(line, number, where, warnings);
      if (block->depth <= 0) {  // `Name { ... }` on one line
        block.reset();
      }
      continue;
    }
    const auto [key, value] = split_key_value(line, where);
    if (auto it = seen.find(key); it != seen.end()) {
      fail(where, std::string(key) + " is already set on line " + std::to_string(it->second));
    }
    seen.emplace(std::string(key), number);
    if (!is_config_key(key) && listed(kReferenceAgentKeys, key)) {
      warnings.push_back(where + ": " + std::string(key) +
                         " is a key of the reference agent that mtc-bridge does not use; ignored");
      continue;
    }
    apply_config_value(config, key, value, where);
  }
  if (block) {
    fail(std::string(name) + ":" + std::to_string(block->line),
         "block '" + block->name + "' is never closed");
  }
  return warnings;
}

std::vector<std::string> load_config_file(BridgeConfig& config, const std::string& path) {
  std::string error;
  const auto text = read_bounded_file(path, kMaxConfigBytes, "config file", error);
  if (!text) {
    throw ConfigError(path + ": " + error);
  }
  return parse_config_text(config, *text, path);
}

}  // namespace mtc::bridge
