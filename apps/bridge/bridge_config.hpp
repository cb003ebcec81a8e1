// Configuration of the mtc-bridge process: an agent.cfg-style file
// (`Key = Value` lines, `#` comments, as MTConnect agents use) overridden by
// command-line flags. Every key and every flag goes through one validating
// table, so a bad value reads the same wherever it came from.
#pragma once

#include <chrono>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace mtc::bridge {

struct BridgeConfig {
  std::string devices_file;                // Devices: empty = DDS announcements only
  std::string server_ip = "127.0.0.1";     // ServerIp
  std::uint16_t port = 5000;               // Port
  unsigned buffer_size_exponent = 17;      // BufferSize: buffer holds 2^n observations
  std::string schema_version;              // SchemaVersion: empty = the agent's choice
  std::string sender = "mtc-bridge";       // Sender: Header@sender
  std::vector<int> domain_ids{0};          // DomainIds
  std::string qos_profile;                 // QosProfile: mtc::qos preset name
  std::vector<std::string> device_filter;  // DeviceFilter: uuids; empty = all
  unsigned io_threads = 1;                 // IoThreads (alias WorkerThreads)
  // DDS side: the heartbeat period of the observed devices and how many
  // may be missed; their product is the liveliness lease the observer asks
  // for (it must cover the longest lease of any device).
  std::chrono::milliseconds heartbeat{100};  // HeartbeatMs
  int missed_heartbeats = 3;                 // MissedHeartbeats
  std::string transport = "loopback";        // Transport: loopback | loopback-udp | network
  // HTTP side: heartbeat of a stream whose request names none.
  std::chrono::milliseconds stream_heartbeat{10000};  // StreamHeartbeatMs
  std::size_t max_connections = 256;                  // MaxConnections
  std::chrono::milliseconds header_timeout{10000};    // HeaderTimeoutMs
  std::chrono::milliseconds idle_timeout{30000};      // IdleTimeoutMs
  std::chrono::milliseconds write_timeout{30000};     // WriteTimeoutMs
};

// A configuration mistake: `what()` names the origin ("agent.cfg:7" or
// "--port") and says what is wrong. mtc-bridge exits with code 2.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Sets one key (as spelled in the file, case-sensitive) from its text.
// Throws ConfigError naming `origin` for an unknown key or a bad value.
void apply_config_value(BridgeConfig& config, std::string_view key, std::string_view value,
                        std::string_view origin);

// Parses the text of a configuration file onto `config`. `name` is used in
// messages ("agent.cfg:12: ..."). Throws ConfigError on the first bad line.
void parse_config_text(BridgeConfig& config, std::string_view text, std::string_view name);

// Reads and parses a file; a missing or unreadable file is a ConfigError.
void load_config_file(BridgeConfig& config, const std::string& path);

// What the command line asked for.
struct CommandLine {
  BridgeConfig config;
  bool help = false;
  std::string config_file;  // empty: none given
};

// Parses argv: `--config FILE` (or a lone FILE argument) is read first,
// then every flag overrides it, whatever the order on the line.
CommandLine parse_command_line(int argc, const char* const* argv);

// The --help text: every flag with its config key and default.
std::string usage_text(std::string_view program);

}  // namespace mtc::bridge
