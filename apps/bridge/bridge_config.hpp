// Configuration of the mtc-bridge process: an agent.cfg-style file
// (`Key = Value` lines, `#` comments, as MTConnect agents use) overridden by
// command-line flags. Every key and every flag goes through one validating
// table, so a bad value reads the same wherever it came from.
//
// The configuration holds the options of the parts it configures (agent,
// HTTP server, DDS observer); their defaults are written there only, and
// --help prints them from there.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "mtc/bridge/http_server.hpp"
#include "mtc/bridge/mtconnect_agent.hpp"
#include "mtc/bridge/shdr_adapter.hpp"
#include "mtc/dds/domain_observer.hpp"

namespace mtc::bridge {

struct BridgeConfig {
  // Devices, BufferSize (2^n observations), SchemaVersion, Sender, MaxAnnouncedDevices,
  // StreamHeartbeatMs, MaxDocumentBytes, PathMaxVisits.
  AgentOptions agent;
  // ServerIp, Port, IoThreads (WorkerThreads), TlsCertificateChain,
  // TlsPrivateKey, MaxConnections,
  // MaxConnectionsPerClient, MaxPendingBytes, HeaderTimeoutMs,
  // IdleTimeoutMs, WriteTimeoutMs.
  ServerOptions server;
  // DeviceFilter, Transport, Middleware, InlineSteps, SecurityDir, and in `timing` HeartbeatMs and
  // MissedHeartbeats: the DDS heartbeat of the observed devices and how many
  // may be missed; their product is the liveliness lease the observer asks
  // for (it must cover the longest lease of any device). domain_id is set
  // per entry of domain_ids. InlineSteps is on unless configured off: the
  // bridge's callbacks are the agent's appends, which never block, so a
  // value goes to the agent on the receive thread that read it, without a
  // thread hand-off (docs/bridge.md).
  dds::DomainObserverOptions observer = [] {
    dds::DomainObserverOptions o;
    o.inline_steps = true;
    return o;
  }();
  std::vector<int> domain_ids{0};  // DomainIds
  // ShdrAdapter (yes/no), ShdrPort, ShdrIp: the bridge as an SHDR adapter
  // for existing MTConnect agents; off unless one of them is given.
  bool shdr_enabled = false;
  ShdrOptions shdr;
};

// A configuration mistake: `what()` names the origin ("agent.cfg:7" or
// "--port") and says what is wrong. mtc-bridge exits with code 2.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// True for a key mtc-bridge reads (as spelled in the file, case-sensitive).
bool is_config_key(std::string_view key);

// Sets one key (as spelled in the file, case-sensitive) from its text.
// Throws ConfigError naming `origin` for an unknown key or a bad value.
void apply_config_value(BridgeConfig& config, std::string_view key, std::string_view value,
                        std::string_view origin);

// Parses the text of a configuration file onto `config`. `name` is used in
// messages ("agent.cfg:12: ..."). Throws ConfigError on the first bad line.
// Keys and blocks of the reference agent's agent.cfg that mtc-bridge does
// not use are skipped; the returned warnings name each one with its line.
std::vector<std::string> parse_config_text(BridgeConfig& config, std::string_view text,
                                           std::string_view name);

// Largest configuration file read (agent.cfg files are a few KiB).
inline constexpr std::size_t kMaxConfigBytes = std::size_t{1} << 20;

// Reads and parses a file (parse_config_text); a missing, unreadable or
// larger than kMaxConfigBytes file (/dev/zero) is a ConfigError.
std::vector<std::string> load_config_file(BridgeConfig& config, const std::string& path);

// What the command line asked for.
struct CommandLine {
  BridgeConfig config;
  bool help = false;
  std::string config_file;            // empty: none given
  std::vector<std::string> warnings;  // from the config file, for stderr
};

// Parses argv: `--config FILE` (or a lone FILE argument) is read first,
// then every flag overrides it, whatever the order on the line. Settings
// valid alone but not together are refused last (a secured bridge with its
// plain-TCP SHDR adapter off loopback: ConfigError naming ShdrIp).
CommandLine parse_command_line(int argc, const char* const* argv);

// The --help text: every flag with its config key and default.
std::string usage_text(std::string_view program);

}  // namespace mtc::bridge
