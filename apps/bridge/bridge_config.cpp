#include "bridge_config.hpp"

#include <arpa/inet.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <sstream>

#include "config_values.hpp"
#include "mtc/bridge/schema_version.hpp"
#include "mtc/bridge/xml_text.hpp"
#include "mtc/dds/middleware.hpp"
#include "mtc/qos/participant.hpp"

namespace mtc::bridge {
namespace {

using config_values::fail;
using config_values::is_printable;
using config_values::parse_int;
using config_values::parse_ms;
using config_values::split_list;

using Setter = void (*)(BridgeConfig&, std::string_view value, const std::string& origin);
// The setting's value in a configuration, as --help shows the default;
// nullptr when the help text says what the default means.
using Shower = std::string (*)(const BridgeConfig&);

// One row per setting: file key, command-line flag, help text.
struct Setting {
  std::string_view key;
  std::string_view flag;
  std::string_view help;
  Setter set;
  Shower show = nullptr;
};

// BufferSize is an exponent, as in cppagent: the buffer holds 2^n.
unsigned buffer_exponent(std::size_t buffer_size) {
  unsigned n = 0;
  while ((std::size_t{2} << n) <= buffer_size) {
    ++n;
  }
  return n;
}

std::string show_ms(std::chrono::milliseconds ms) {
  return std::to_string(ms.count());
}

void set_devices(BridgeConfig& c, std::string_view v, const std::string&) {
  c.agent.devices_file = std::string(v);
}

void set_server_ip(BridgeConfig& c, std::string_view v, const std::string& origin) {
  const std::string text(v);
  std::array<unsigned char, 16> bytes{};
  if (inet_pton(AF_INET, text.c_str(), bytes.data()) != 1 &&
      inet_pton(AF_INET6, text.c_str(), bytes.data()) != 1) {
    fail(origin, "ServerIp must be an IPv4 or IPv6 address, not '" + text + "'");
  }
  c.server.bind_address = text;
}

void set_port(BridgeConfig& c, std::string_view v, const std::string& origin) {
  c.server.port = parse_int<std::uint16_t>(v, 0, 65535, origin, "Port");
}

// 2^24 observations is AgentOptions' limit (about 1 GiB); cppagent's
// default is 17.
constexpr unsigned kMaxBufferExponent = 24;
static_assert((std::size_t{1} << kMaxBufferExponent) == kMaxBufferSize);

void set_buffer_size(BridgeConfig& c, std::string_view v, const std::string& origin) {
  const auto exponent =
      parse_int<unsigned>(v, 1, kMaxBufferExponent, origin, "BufferSize (exponent)");
  c.agent.buffer_size = std::size_t{1} << exponent;
}

void set_schema_version(BridgeConfig& c, std::string_view v, const std::string& origin) {
  const auto version = parse_schema_version(v);
  if (!version) {
    fail(origin, "SchemaVersion must be one of 1.3, 1.6, 1.8, 2.0, not '" + std::string(v) + "'");
  }
  c.agent.schema_version = version;
}

void set_sender(BridgeConfig& c, std::string_view v, const std::string& origin) {
  if (!is_printable(v)) {
    fail(origin, "Sender contains control characters");
  }
  // It goes into every document's Header (and the 2.0 Agent's uuid).
  if (find_unfit_xml_char(v) != std::string_view::npos) {
    fail(origin, "Sender is not UTF-8 text that XML allows");
  }
  c.agent.sender = std::string(v);
}

void set_domain_ids(BridgeConfig& c, std::string_view v, const std::string& origin) {
  std::vector<int> ids;
  for (auto item : split_list(v)) {
    const int id = parse_int<int>(item, 0, qos::kMaxDomainId, origin, "each of DomainIds");
    if (std::find(ids.begin(), ids.end(), id) != ids.end()) {
      fail(origin, "DomainIds lists " + std::to_string(id) + " twice");
    }
    ids.push_back(id);
  }
  if (ids.empty()) {
    fail(origin, "DomainIds needs at least one domain id");
  }
  c.domain_ids = std::move(ids);
}

void set_device_filter(BridgeConfig& c, std::string_view v, const std::string&) {
  c.observer.device_filter.clear();
  for (auto item : split_list(v)) {
    c.observer.device_filter.emplace_back(item);
  }
}

void set_io_threads(BridgeConfig& c, std::string_view v, const std::string& origin) {
  c.server.io_threads = parse_int<unsigned>(v, 1, 64, origin, "IoThreads");
}

void set_heartbeat(BridgeConfig& c, std::string_view v, const std::string& origin) {
  c.observer.timing.heartbeat = parse_ms(v, 1, 600000, origin, "HeartbeatMs");
}

void set_missed_heartbeats(BridgeConfig& c, std::string_view v, const std::string& origin) {
  c.observer.timing.missed_heartbeats = parse_int<int>(v, 2, 100, origin, "MissedHeartbeats");
}

void set_transport(BridgeConfig& c, std::string_view v, const std::string& origin) {
  const auto transport = qos::parse_transport(v);
  if (!transport) {
    std::string names;
    for (std::size_t i = 0; i < qos::kAllTransports.size(); ++i) {
      names += i == 0 ? "" : i + 1 == qos::kAllTransports.size() ? " or " : ", ";
      names += qos::to_string(qos::kAllTransports[i]);
    }
    fail(origin, "Transport must be " + names + ", not '" + std::string(v) + "'");
  }
  c.observer.transport = *transport;
}

void set_middleware(BridgeConfig& c, std::string_view v, const std::string& origin) {
  auto choice = dds::choose_middleware(v);
  if (!choice.middleware) fail(origin, "Middleware: " + choice.problem);
  c.observer.middleware = *choice.middleware;
}

// Checked here so that a bad directory is told with the origin of the
// setting, before any DDS entity exists.
void set_security_dir(BridgeConfig& c, std::string_view v, const std::string& origin) {
  const std::string dir(v);
  if (auto problem = qos::check_security_dir(dir)) fail(origin, *problem);
  c.observer.security_dir = dir;
}

void set_max_announced(BridgeConfig& c, std::string_view v, const std::string& origin) {
  c.agent.max_announced_devices =
      parse_int<std::size_t>(v, 1, 1000000, origin, "MaxAnnouncedDevices");
}

// Read when the server starts (HttpServer names a file it cannot use).
void set_tls_certificate(BridgeConfig& c, std::string_view v, const std::string&) {
  c.server.tls_certificate_file = std::string(v);
}

void set_tls_private_key(BridgeConfig& c, std::string_view v, const std::string&) {
  c.server.tls_private_key_file = std::string(v);
}

void set_stream_heartbeat(BridgeConfig& c, std::string_view v, const std::string& origin) {
  c.agent.stream_heartbeat = parse_ms(v, 10, 3600000, origin, "StreamHeartbeatMs");
}

void set_max_connections(BridgeConfig& c, std::string_view v, const std::string& origin) {
  c.server.max_connections = parse_int<std::size_t>(v, 1, 100000, origin, "MaxConnections");
}

void set_header_timeout(BridgeConfig& c, std::string_view v, const std::string& origin) {
  c.server.header_timeout = parse_ms(v, 100, 3600000, origin, "HeaderTimeoutMs");
}

void set_idle_timeout(BridgeConfig& c, std::string_view v, const std::string& origin) {
  c.server.idle_timeout = parse_ms(v, 100, 3600000, origin, "IdleTimeoutMs");
}

void set_write_timeout(BridgeConfig& c, std::string_view v, const std::string& origin) {
  c.server.write_timeout = parse_ms(v, 100, 3600000, origin, "WriteTimeoutMs");
}

void set_max_per_client(BridgeConfig& c, std::string_view v, const std::string& origin) {
  c.server.max_connections_per_client =
      parse_int<std::size_t>(v, 1, 100000, origin, "MaxConnectionsPerClient");
}

void set_max_pending(BridgeConfig& c, std::string_view v, const std::string& origin) {
  c.server.max_pending_bytes = parse_int<std::size_t>(v, std::size_t{1} << 16, std::size_t{1} << 40,
                                                      origin, "MaxPendingBytes");
}

void set_direct_streams(BridgeConfig& c, std::string_view v, const std::string& origin) {
  c.server.direct_stream_writes = parse_int<std::size_t>(v, 0, 4096, origin, "DirectStreamWrites");
}

void set_max_document(BridgeConfig& c, std::string_view v, const std::string& origin) {
  c.agent.max_document_bytes = parse_int<std::size_t>(v, std::size_t{1} << 12, std::size_t{1} << 31,
                                                      origin, "MaxDocumentBytes");
}

void set_path_visits(BridgeConfig& c, std::string_view v, const std::string& origin) {
  c.agent.path_limits.max_visits = static_cast<double>(
      parse_int<std::uint64_t>(v, 1000, std::uint64_t{1} << 40, origin, "PathMaxVisits"));
}

bool parse_yes_no(std::string_view v, const std::string& origin, const char* key) {
  if (v != "yes" && v != "no" && v != "true" && v != "false") {
    fail(origin, std::string(key) + " must be yes or no, not '" + std::string(v) + "'");
  }
  return v == "yes" || v == "true";
}

void set_shdr_adapter(BridgeConfig& c, std::string_view v, const std::string& origin) {
  c.shdr_enabled = parse_yes_no(v, origin, "ShdrAdapter");
}

void set_inline_steps(BridgeConfig& c, std::string_view v, const std::string& origin) {
  c.observer.inline_steps = parse_yes_no(v, origin, "InlineSteps");
}

void set_shdr_port(BridgeConfig& c, std::string_view v, const std::string& origin) {
  c.shdr.port = parse_int<std::uint16_t>(v, 0, 65535, origin, "ShdrPort");
  c.shdr_enabled = true;
}

void set_shdr_ip(BridgeConfig& c, std::string_view v, const std::string& origin) {
  const std::string text(v);
  std::array<unsigned char, 16> bytes{};
  if (inet_pton(AF_INET, text.c_str(), bytes.data()) != 1 &&
      inet_pton(AF_INET6, text.c_str(), bytes.data()) != 1) {
    fail(origin, "ShdrIp must be an IPv4 or IPv6 address, not '" + text + "'");
  }
  c.shdr.bind_address = text;
  c.shdr_enabled = true;
}

const std::array<Setting, 32> kSettings{{
    {"Devices", "--devices", "Devices.xml describing the devices (default: from DDS announcements)",
     set_devices},
    {"ServerIp", "--server-ip", "address to listen on", set_server_ip,
     [](const BridgeConfig& c) { return c.server.bind_address; }},
    {"Port", "--port", "HTTP port, 0 = any free port", set_port,
     [](const BridgeConfig& c) { return std::to_string(c.server.port); }},
    {"BufferSize", "--buffer-size", "observation buffer holds 2^n entries", set_buffer_size,
     [](const BridgeConfig& c) { return std::to_string(buffer_exponent(c.agent.buffer_size)); }},
    {"SchemaVersion", "--schema-version",
     "1.3, 1.6, 1.8 or 2.0 (default: the Devices file's, else 1.6)", set_schema_version},
    {"Sender", "--sender", "Header sender name", set_sender,
     [](const BridgeConfig& c) { return c.agent.sender; }},
    {"DomainIds", "--domain-ids", "DDS domain ids to observe, e.g. 0,1", set_domain_ids,
     [](const BridgeConfig& c) {
       std::string ids;
       for (const int id : c.domain_ids) {
         ids += (ids.empty() ? "" : ",") + std::to_string(id);
       }
       return ids;
     }},
    {"DeviceFilter", "--device-filter", "only these device uuids (default: all)",
     set_device_filter},
    {"IoThreads", "--io-threads", "HTTP io threads", set_io_threads,
     [](const BridgeConfig& c) { return std::to_string(c.server.io_threads); }},
    {"WorkerThreads", "", "cppagent's name for IoThreads", set_io_threads},
    {"HeartbeatMs", "--heartbeat-ms", "DDS heartbeat period of the devices", set_heartbeat,
     [](const BridgeConfig& c) { return show_ms(c.observer.timing.heartbeat); }},
    {"MissedHeartbeats", "--missed-heartbeats",
     "heartbeats missed before a device's items read UNAVAILABLE", set_missed_heartbeats,
     [](const BridgeConfig& c) { return std::to_string(c.observer.timing.missed_heartbeats); }},
    {"Transport", "--transport", "DDS transport: loopback, loopback-udp, test or network",
     set_transport,
     [](const BridgeConfig& c) { return std::string(qos::to_string(c.observer.transport)); }},
    {"Middleware", "--middleware", "DDS implementation: fastdds or cyclone", set_middleware,
     [](const BridgeConfig& c) { return std::string(dds::to_string(c.observer.middleware)); }},
    {"InlineSteps", "--inline-steps",
     "yes: a DDS value is handed to the agent on the middleware's receive thread (one thread "
     "hand-off less per change); no: on the observer's dispatch thread",
     set_inline_steps,
     [](const BridgeConfig& c) { return std::string(c.observer.inline_steps ? "yes" : "no"); }},
    {"TlsCertificateChain", "--tls-certificate",
     "HTTPS: PEM certificate chain (with TlsPrivateKey; default: plain HTTP)", set_tls_certificate},
    {"TlsPrivateKey", "--tls-private-key", "HTTPS: PEM private key of the certificate",
     set_tls_private_key},
    {"MaxAnnouncedDevices", "--max-announced-devices",
     "devices accepted from DDS announcements; a new one beyond takes a departed one's place",
     set_max_announced,
     [](const BridgeConfig& c) { return std::to_string(c.agent.max_announced_devices); }},
    {"SecurityDir", "--security",
     "DDS-Security identity directory, read-only (scripts/security/make-pki.sh; default: "
     "unsecured)",
     set_security_dir},
    {"StreamHeartbeatMs", "--stream-heartbeat-ms",
     "HTTP stream heartbeat when a request names none", set_stream_heartbeat,
     [](const BridgeConfig& c) { return show_ms(c.agent.stream_heartbeat); }},
    {"MaxConnections", "--max-connections",
     "open connections; a new one replaces the longest-waiting idle one, else gets 503",
     set_max_connections,
     [](const BridgeConfig& c) { return std::to_string(c.server.max_connections); }},
    {"MaxConnectionsPerClient", "--max-connections-per-client",
     "open connections from one client address", set_max_per_client,
     [](const BridgeConfig& c) { return std::to_string(c.server.max_connections_per_client); }},
    {"MaxPendingBytes", "--max-pending-bytes",
     "answer bytes waiting for clients that do not read; a large answer beyond gets 503",
     set_max_pending,
     [](const BridgeConfig& c) { return std::to_string(c.server.max_pending_bytes); }},
    {"DirectStreamWrites", "--direct-stream-writes",
     "streams open up to which the DDS thread writes an idle stream's part itself (0: never)",
     set_direct_streams,
     [](const BridgeConfig& c) { return std::to_string(c.server.direct_stream_writes); }},
    {"MaxDocumentBytes", "--max-document-bytes",
     "largest /sample document; a larger one stops early (nextSequence goes on)", set_max_document,
     [](const BridgeConfig& c) { return std::to_string(c.agent.max_document_bytes); }},
    {"PathMaxVisits", "--path-max-visits",
     "estimated node visits a path filter may cost; more is refused (INVALID_PATH)",
     set_path_visits,
     [](const BridgeConfig& c) {
       return std::to_string(static_cast<std::uint64_t>(c.agent.path_limits.max_visits));
     }},
    {"HeaderTimeoutMs", "--header-timeout-ms",
     "time to send a request header (the first: from the connection)", set_header_timeout,
     [](const BridgeConfig& c) { return show_ms(c.server.header_timeout); }},
    {"IdleTimeoutMs", "--idle-timeout-ms", "keep-alive idle time before closing", set_idle_timeout,
     [](const BridgeConfig& c) { return show_ms(c.server.idle_timeout); }},
    {"WriteTimeoutMs", "--write-timeout-ms", "time a client may take to read a write",
     set_write_timeout, [](const BridgeConfig& c) { return show_ms(c.server.write_timeout); }},
    {"ShdrAdapter", "--shdr-adapter",
     "yes: also serve SHDR to MTConnect agents (an adapter), on ShdrIp:ShdrPort", set_shdr_adapter,
     [](const BridgeConfig& c) { return std::string(c.shdr_enabled ? "yes" : "no"); }},
    {"ShdrPort", "--shdr-port", "SHDR adapter port (implies ShdrAdapter = yes), 0 = any free",
     set_shdr_port, [](const BridgeConfig& c) { return std::to_string(c.shdr.port); }},
    {"ShdrIp", "--shdr-ip", "SHDR adapter address (implies ShdrAdapter = yes)", set_shdr_ip,
     [](const BridgeConfig& c) { return c.shdr.bind_address; }},
}};

const Setting* find_key(std::string_view key) {
  for (const auto& setting : kSettings) {
    if (setting.key == key) {
      return &setting;
    }
  }
  return nullptr;
}

const Setting* find_flag(std::string_view flag) {
  if (flag == "--bind") {
    flag = "--server-ip";
  }
  for (const auto& setting : kSettings) {
    if (!setting.flag.empty() && setting.flag == flag) {
      return &setting;
    }
  }
  return nullptr;
}

// True for 127.0.0.0/8, ::1 and ::ffff:127.x.y.z (set_shdr_ip checked the
// syntax).
bool is_loopback(const std::string& address) {
  std::array<unsigned char, 16> bytes{};
  if (inet_pton(AF_INET, address.c_str(), bytes.data()) == 1) return bytes[0] == 127;
  if (inet_pton(AF_INET6, address.c_str(), bytes.data()) != 1) return false;
  static constexpr std::array<unsigned char, 16> kLoopback6{0, 0, 0, 0, 0, 0, 0, 0,
                                                            0, 0, 0, 0, 0, 0, 0, 1};
  const bool v4_mapped =
      std::all_of(bytes.begin(), bytes.begin() + 10, [](auto b) { return b == 0; }) &&
      bytes[10] == 0xFF && bytes[11] == 0xFF;
  return bytes == kLoopback6 || (v4_mapped && bytes[12] == 127);
}

// Settings that are each valid but not together. SHDR is plain TCP (the
// reference agent reads its adapters that way): a bridge that encrypts its
// DDS traffic or serves HTTPS would hand the same values out in clear text
// on any other address, so there the adapter stays on loopback, where only
// an agent on the same host reads it (docs/security.md).
void check_combination(const BridgeConfig& c) {
  const bool secured = !c.observer.security_dir.empty() || !c.server.tls_certificate_file.empty();
  if (c.shdr_enabled && secured && !is_loopback(c.shdr.bind_address)) {
    fail("ShdrIp",
         "the SHDR adapter speaks plain TCP, so a secured bridge (SecurityDir or "
         "TlsCertificateChain) binds it to a loopback address only, not '" +
             c.shdr.bind_address + "'");
  }
}

}  // namespace

bool is_config_key(std::string_view key) {
  return find_key(key) != nullptr;
}

void apply_config_value(BridgeConfig& config, std::string_view key, std::string_view value,
                        std::string_view origin) {
  const std::string where(origin);
  const Setting* setting = find_key(key);
  if (setting == nullptr) {
    fail(where, "unknown key '" + std::string(key) + "'");
  }
  if (value.empty()) {
    fail(where, "empty value for " + std::string(key));
  }
  setting->set(config, value, where);
}

CommandLine parse_command_line(int argc, const char* const* argv) {
  CommandLine result;
  std::vector<std::pair<const Setting*, std::string>> overrides;
  for (int i = 1; i < argc; ++i) {
    std::string_view arg = argv[i];
    if (arg == "-h" || arg == "--help") {
      result.help = true;
      continue;
    }
    if (arg.substr(0, 2) != "--") {
      if (!result.config_file.empty()) {
        fail(std::string(arg), "only one config file may be given");
      }
      result.config_file = std::string(arg);
      continue;
    }
    std::string_view flag = arg;
    std::string value;
    bool has_value = false;
    if (const auto eq = arg.find('='); eq != std::string_view::npos) {
      flag = arg.substr(0, eq);
      value = std::string(arg.substr(eq + 1));
      has_value = true;
    }
    const Setting* setting = flag == "--config" ? nullptr : find_flag(flag);
    if (flag != "--config" && setting == nullptr) {
      fail(std::string(flag), "unknown option (see --help)");
    }
    if (!has_value) {
      if (i + 1 >= argc) {
        fail(std::string(flag), "needs a value");
      }
      value = argv[++i];
    }
    if (setting == nullptr) {
      if (!result.config_file.empty()) {
        fail("--config", "only one config file may be given");
      }
      result.config_file = value;
    } else {
      overrides.emplace_back(setting, std::move(value));
    }
  }
  if (result.help) {
    return result;
  }
  if (!result.config_file.empty()) {
    result.warnings = load_config_file(result.config, result.config_file);
  }
  for (const auto& [setting, value] : overrides) {
    apply_config_value(result.config, setting->key, value, setting->flag);
  }
  check_combination(result.config);
  return result;
}

std::string usage_text(std::string_view program) {
  std::ostringstream out;
  out << "usage: " << program << " [--config agent.cfg] [options]\n\n"
      << "Serves MTConnect probe/current/sample (HTTP, XML) for the MTConnect Part 5\n"
      << "interfaces published on DDS. Options override the config file; each one\n"
      << "matches a `Key = Value` line of the file.\n\n";
  const BridgeConfig defaults;
  for (const auto& setting : kSettings) {
    if (setting.flag.empty()) {
      continue;
    }
    std::string left = "  " + std::string(setting.flag) + " VALUE";
    left.resize(std::max<std::size_t>(left.size() + 1, 32), ' ');
    out << left << std::string(setting.key) << ": " << setting.help;
    if (setting.show != nullptr) {
      out << " (default " << setting.show(defaults) << ")";
    }
    out << "\n";
  }
  out << "  --config FILE                 agent.cfg-style file (`Key = Value`, # comments)\n"
      << "  --bind VALUE                  same as --server-ip\n"
      << "  -h, --help                    this text\n\n"
      << "Exit codes: 0 clean stop (SIGINT/SIGTERM), 1 runtime failure, 2 bad configuration.\n";
  return out.str();
}

}  // namespace mtc::bridge
