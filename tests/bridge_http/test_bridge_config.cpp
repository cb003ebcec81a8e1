// agent.cfg-style configuration and command-line flags: valid files, a
// table of malformed ones (each must name its line), and flag precedence.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "../support/param_name.hpp"
#include "bridge_config.hpp"
#include "mtc/dds/middleware.hpp"

namespace mtc::bridge {
namespace {

using namespace std::chrono_literals;

BridgeConfig parse(const std::string& text) {
  BridgeConfig config;
  parse_config_text(config, text, "agent.cfg");
  return config;
}

std::string error_of(const std::string& text) {
  try {
    parse(text);
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "(no error)";
}

TEST(BridgeConfig, DefaultsMatchTheDocumentation) {
  const BridgeConfig config;
  EXPECT_EQ(config.server.bind_address, "127.0.0.1");
  EXPECT_EQ(config.server.port, 5000);
  EXPECT_EQ(config.agent.buffer_size, 131072U);  // BufferSize = 17
  EXPECT_FALSE(config.agent.schema_version);     // the agent decides
  EXPECT_EQ(config.domain_ids, std::vector<int>{0});
  EXPECT_EQ(config.server.io_threads, 1U);
  EXPECT_EQ(config.observer.timing.heartbeat, 100ms);
  EXPECT_EQ(config.observer.timing.missed_heartbeats, 3);
  // The network, as the runtime's default (issue 10); start.sh and the tests
  // choose loopback.
  EXPECT_EQ(config.observer.transport, qos::Transport::Network);
  EXPECT_EQ(config.agent.stream_heartbeat, 10000ms);
}

TEST(BridgeConfig, TransportsAreNamedAsMtcQosNamesThem) {
  for (const qos::Transport transport : qos::kAllTransports) {
    const std::string name(qos::to_string(transport));
    EXPECT_EQ(parse("Transport = " + name).observer.transport, transport) << name;
  }
  EXPECT_NE(error_of("Transport = builtin")
                .find("Transport must be loopback, loopback-udp, test or network, not 'builtin'"),
            std::string::npos);
}

// Fast DDS unless the file says otherwise; Cyclone only where this build
// has it (the sanitizer builds do not), and told with the setting's origin
// when it has not.
TEST(BridgeConfig, MiddlewareIsFastDdsOrCycloneWhereBuiltIn) {
  EXPECT_EQ(parse("").observer.middleware, dds::Middleware::FastDds);
  EXPECT_EQ(parse("Middleware = fastdds").observer.middleware, dds::Middleware::FastDds);
  if (dds::middleware_available(dds::Middleware::Cyclone)) {
    EXPECT_EQ(parse("Middleware = cyclone").observer.middleware, dds::Middleware::Cyclone);
  } else {
    EXPECT_NE(error_of("Middleware = cyclone").find("configure with -DMTC_CYCLONE=ON"),
              std::string::npos);
  }
  EXPECT_NE(error_of("Middleware = opendds")
                .find("Middleware: unknown middleware 'opendds' (fastdds or cyclone)"),
            std::string::npos);
}

TEST(BridgeConfig, InlineStepsIsYesOrNoAndOnByDefault) {
  EXPECT_TRUE(parse("").observer.inline_steps);
  EXPECT_TRUE(parse("InlineSteps = yes").observer.inline_steps);
  EXPECT_TRUE(parse("InlineSteps = true").observer.inline_steps);
  EXPECT_FALSE(parse("InlineSteps = no").observer.inline_steps);
  EXPECT_NE(
      error_of("InlineSteps = sometimes").find("InlineSteps must be yes or no, not 'sometimes'"),
      std::string::npos);
}

TEST(BridgeConfig, HelpShowsTheDefaultsOfTheOptionsItHolds) {
  const auto text = usage_text("mtc-bridge");
  const BridgeConfig defaults;
  for (const std::string& expected : std::vector<std::string>{
           "Port: HTTP port, 0 = any free port (default " + std::to_string(defaults.server.port) +
               ")",
           "BufferSize: observation buffer holds 2^n entries (default 17)",
           "HeartbeatMs: DDS heartbeat period of the devices (default " +
               std::to_string(defaults.observer.timing.heartbeat.count()) + ")",
           "(default " + std::to_string(defaults.agent.stream_heartbeat.count()) + ")",
           // NOLINTNEXTLINE(bugprone-suspicious-missing-comma): one help line, wrapped
           "Transport: DDS transport: loopback, loopback-udp, test or network (default "
           "network)",
           "(default fastdds)"}) {
    EXPECT_NE(text.find(expected), std::string::npos) << expected << "\nin:\n" << text;
  }
}

TEST(BridgeConfig, ParsesAnAgentCfgStyleFile) {
  const auto config = parse(
      "# cell 3 bridge\n"
      "Devices = /etc/mtc/Devices.xml\n"
      "ServerIp = ::1\n"
      "Port = 5001   # next to the legacy agent\n"
      "BufferSize = 12\n"
      "SchemaVersion = 1.8\n"
      "Sender = \"cell #3\"\n"
      "\n"
      "   DomainIds = 3, 4 7\n"
      "DeviceFilter = robot-1,mill-2\n"
      "WorkerThreads = 2\r\n"
      "HeartbeatMs = 500\n"
      "MissedHeartbeats = 4\n"
      "Transport = loopback-udp\n"
      "StreamHeartbeatMs = 2000\n"
      "MaxConnections = 10\n"
      "HeaderTimeoutMs = 2000\n"
      "IdleTimeoutMs = 3000\n"
      "WriteTimeoutMs = 4000\n"
      "MaxConnectionsPerClient = 8\n"
      "MaxPendingBytes = 1048576\n"
      "DirectStreamWrites = 0\n"
      "MaxDocumentBytes = 65536\n"
      "PathMaxVisits = 50000\n"
      "MaxAnnouncedDevices = 12\n"
      "TlsCertificateChain = /etc/mtc/cert.pem\n"
      "TlsPrivateKey = /etc/mtc/key.pem");
  EXPECT_EQ(config.agent.devices_file, "/etc/mtc/Devices.xml");
  EXPECT_EQ(config.server.bind_address, "::1");
  EXPECT_EQ(config.server.port, 5001);
  EXPECT_EQ(config.agent.buffer_size, 4096U);
  EXPECT_EQ(config.agent.schema_version, SchemaVersion::V1_8);
  EXPECT_EQ(config.agent.sender, "cell #3");
  EXPECT_EQ(config.domain_ids, (std::vector<int>{3, 4, 7}));
  EXPECT_EQ(config.observer.device_filter, (std::vector<std::string>{"robot-1", "mill-2"}));
  EXPECT_EQ(config.server.io_threads, 2U);
  EXPECT_EQ(config.observer.timing.heartbeat, 500ms);
  EXPECT_EQ(config.observer.timing.missed_heartbeats, 4);
  EXPECT_EQ(config.observer.transport, qos::Transport::LoopbackUdp);
  EXPECT_EQ(config.agent.stream_heartbeat, 2000ms);
  EXPECT_EQ(config.agent.max_announced_devices, 12U);
  EXPECT_EQ(config.server.tls_certificate_file, "/etc/mtc/cert.pem");
  EXPECT_EQ(config.server.tls_private_key_file, "/etc/mtc/key.pem");
  EXPECT_EQ(config.server.max_connections, 10U);
  EXPECT_EQ(config.server.direct_stream_writes, 0U);
  EXPECT_EQ(config.server.header_timeout, 2000ms);
  EXPECT_EQ(config.server.idle_timeout, 3000ms);
  EXPECT_EQ(config.server.write_timeout, 4000ms);
  EXPECT_EQ(config.server.max_connections_per_client, 8U);
  EXPECT_EQ(config.server.max_pending_bytes, 1048576U);
  EXPECT_EQ(config.agent.max_document_bytes, 65536U);
  EXPECT_EQ(config.agent.path_limits.max_visits, 50000.0);
}

struct Malformed {
  const char* text;
  const char* expected;  // substring of the message, including the line
};

// What gtest lists for the parameter (see param_name.hpp).
void PrintTo(const Malformed& p, std::ostream* os) {
  *os << mtc::test::printable(p.text);
}

class MalformedConfig : public ::testing::TestWithParam<Malformed> {};

TEST_P(MalformedConfig, IsRejectedNamingTheLine) {
  const auto message = error_of(GetParam().text);
  EXPECT_NE(message.find(GetParam().expected), std::string::npos)
      << "message: " << message << "\nconfig: " << GetParam().text;
}

INSTANTIATE_TEST_SUITE_P(
    Table, MalformedConfig,
    ::testing::Values(
        Malformed{"Prot = 5000", "agent.cfg:1: unknown key 'Prot'"},
        Malformed{"Port = 5000\nPort 5001", "agent.cfg:2: expected 'Key = Value'"},
        Malformed{"Port = 70000", "agent.cfg:1: Port must be an integer from 0 to 65535"},
        Malformed{"Port = 50x", "agent.cfg:1: Port must be an integer"},
        Malformed{"Port = -1", "agent.cfg:1: Port"},
        Malformed{"Port =", "agent.cfg:1: empty value for Port"},
        Malformed{"= 5", "agent.cfg:1: missing key"},
        Malformed{"\n\nPort = 1\nPort = 2", "agent.cfg:4: Port is already set on line 3"},
        Malformed{"BufferSize = 0", "agent.cfg:1: BufferSize (exponent) must be"},
        Malformed{"BufferSize = 131072", "agent.cfg:1: BufferSize (exponent) must be"},
        // 2^30 observations would end in std::bad_alloc: refused by name.
        Malformed{"BufferSize = 30",
                  "agent.cfg:1: BufferSize (exponent) must be an integer "
                  "from 1 to 24, not '30'"},
        Malformed{"SchemaVersion = 2", "agent.cfg:1: SchemaVersion must be one of"},
        Malformed{"SchemaVersion = 7.0", "agent.cfg:1: SchemaVersion"},
        Malformed{"SchemaVersion = 1.4", "agent.cfg:1: SchemaVersion"},
        Malformed{"ServerIp = localhost", "agent.cfg:1: ServerIp must be an IPv4 or IPv6"},
        Malformed{"ServerIp = 300.1.1.1", "agent.cfg:1: ServerIp"},
        Malformed{"DomainIds = 1,,x", "agent.cfg:1: each of DomainIds"},
        Malformed{"DomainIds = 233",
                  "agent.cfg:1: each of DomainIds must be an integer from 0 to 232"},
        Malformed{"DomainIds = 4, 4", "agent.cfg:1: DomainIds lists 4 twice"},
        Malformed{"DomainIds = ,", "agent.cfg:1: DomainIds needs at least one"},
        // The observer's QoS derives from the heartbeat; no profile selects it.
        Malformed{"QosProfile = mtc.state", "agent.cfg:1: unknown key 'QosProfile'"},
        Malformed{"IoThreads = 0", "agent.cfg:1: IoThreads"},
        Malformed{"HeartbeatMs = 0", "agent.cfg:1: HeartbeatMs"},
        Malformed{"MissedHeartbeats = 1", "agent.cfg:1: MissedHeartbeats"},
        Malformed{"Transport = udp", "agent.cfg:1: Transport must be loopback"},
        Malformed{"StreamHeartbeatMs = 5", "agent.cfg:1: StreamHeartbeatMs"},
        Malformed{"MaxConnections = 0", "agent.cfg:1: MaxConnections"},
        Malformed{"MaxPendingBytes = 1000", "agent.cfg:1: MaxPendingBytes must be an integer"},
        Malformed{"DirectStreamWrites = -1",
                  "agent.cfg:1: DirectStreamWrites must be an integer from 0 to 4096"},
        Malformed{"PathMaxVisits = 1e6", "agent.cfg:1: PathMaxVisits must be an integer"},
        Malformed{"HeaderTimeoutMs = 10s", "agent.cfg:1: HeaderTimeoutMs"},
        Malformed{"MaxAnnouncedDevices = 0", "agent.cfg:1: MaxAnnouncedDevices"},
        // A security directory is checked when read, naming it.
        Malformed{"SecurityDir = /nonexistent/pki",
                  "agent.cfg:1: security directory /nonexistent/pki does not exist"},
        Malformed{"Agents {\n  A { Host = x }\n}", "agent.cfg:1: unknown block 'Agents'"},
        Malformed{"Port = 1\nAdapters {\n  A { Host = x }\n",
                  "agent.cfg:2: block 'Adapters' is never closed"},
        Malformed{"Port = 1 }", "agent.cfg:1: unexpected '}'"},
        Malformed{"# ok\nAllowPutt = true", "agent.cfg:2: unknown key 'AllowPutt'"},
        Malformed{"Sender = a\x01z", "agent.cfg:1: Sender contains control"},
        // Found by tests/fuzz (fuzz_bridge_config): it reached documents.
        Malformed{"Sender = cel\xA6 bridge", "agent.cfg:1: Sender is not UTF-8 text"}),
    [](const ::testing::TestParamInfo<Malformed>& param_info) {
      return mtc::test::param_name(param_info.index, param_info.param.text);
    });

// An integrator reuses the reference agent's agent.cfg: what mtc-bridge
// does not use is skipped with a warning naming the line, the rest applies.
TEST(BridgeConfig, ReferenceAgentKeysAndBlocksAreAcceptedWithAWarning) {
  BridgeConfig config;
  const auto warnings = parse_config_text(config,
                                          "PidFile = /var/run/agent.pid\n"
                                          "Port = 5001\n"
                                          "AllowPut = true\n"
                                          "Adapters {\n"
                                          "  Mazak {\n"
                                          "    Host = 10.0.0.2  # { in a comment\n"
                                          "    Port = 7878\n"
                                          "  }\n"
                                          "}\n"
                                          "logger_config { logging_level = debug }\n"
                                          "BufferSize = 16\n",
                                          "agent.cfg");
  EXPECT_EQ(config.server.port, 5001);  // the adapter's Port is not the bridge's
  EXPECT_EQ(config.agent.buffer_size, 65536U);
  ASSERT_EQ(warnings.size(), 4U);
  EXPECT_EQ(warnings[0],
            "agent.cfg:1: PidFile is a key of the reference agent that mtc-bridge does not use; "
            "ignored");
  EXPECT_EQ(warnings[1].rfind("agent.cfg:3: AllowPut", 0), 0U) << warnings[1];
  EXPECT_EQ(warnings[2].rfind("agent.cfg:4: block 'Adapters'", 0), 0U) << warnings[2];
  EXPECT_EQ(warnings[3].rfind("agent.cfg:10: block 'logger_config'", 0), 0U) << warnings[3];
}

TEST(BridgeConfig, EndlessHugeAndDirectoryFilesAreClearErrors) {
  BridgeConfig config;
  const std::string huge = ::testing::TempDir() + "bridge_huge_agent.cfg";
  {
    std::ofstream out(huge);
    for (std::size_t i = 0; i * 20 <= kMaxConfigBytes; ++i) out << "# padding comment ..\n";
  }
  const std::string too_large =
      "config file is larger than " + std::to_string(kMaxConfigBytes) + " bytes";
  for (const std::string& path : {std::string("/dev/zero"), huge}) {
    try {
      load_config_file(config, path);
      ADD_FAILURE() << path << " accepted";
    } catch (const ConfigError& error) {
      std::string expected = path;
      expected += ": ";
      expected += too_large;
      EXPECT_EQ(std::string(error.what()), expected);
    }
  }
  std::remove(huge.c_str());
  try {
    load_config_file(config, ::testing::TempDir());
    ADD_FAILURE() << "a directory accepted";
  } catch (const ConfigError& error) {
    EXPECT_NE(std::string(error.what()).find("config file is a directory"), std::string::npos);
  }
}

TEST(BridgeConfig, BinaryDataIsRejected) {
  EXPECT_NE(error_of(std::string("Port = 5\0\x7f\n", 10)).find("agent.cfg:1: binary data"),
            std::string::npos);
}

TEST(BridgeConfig, MissingFileIsAClearError) {
  BridgeConfig config;
  try {
    load_config_file(config, "/nonexistent/agent.cfg");
    FAIL() << "no error";
  } catch (const ConfigError& error) {
    EXPECT_STREQ(error.what(),
                 "/nonexistent/agent.cfg: cannot open config file: No such file or directory");
  }
}

class CommandLineTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // One file per test: ctest runs the cases of this fixture in parallel
    // processes, and one's TearDown must not remove another's file (seen in
    // CI: "cannot open config file" in a case whose file had just gone).
    path_ = ::testing::TempDir() + "bridge_cli_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name() + "_" +
            std::to_string(::getpid()) + ".cfg";
    std::ofstream(path_) << "Port = 6000\nDomainIds = 81\nSender = file\n";
  }
  void TearDown() override { std::remove(path_.c_str()); }

  static CommandLine run(std::vector<const char*> args) {
    args.insert(args.begin(), "mtc-bridge");
    return parse_command_line(static_cast<int>(args.size()), args.data());
  }
  std::string path_;
};

TEST_F(CommandLineTest, FlagsOverrideTheFileWhateverTheOrder) {
  const auto line = run({"--port", "6001", "--config", path_.c_str(), "--sender=flag"});
  EXPECT_EQ(line.config_file, path_);
  EXPECT_EQ(line.config.server.port, 6001);
  EXPECT_EQ(line.config.agent.sender, "flag");
  EXPECT_EQ(line.config.domain_ids, std::vector<int>{81});
}

TEST_F(CommandLineTest, TheTransportIsTheNetworkUnlessChosen) {
  EXPECT_EQ(run({}).config.observer.transport, qos::Transport::Network);
  EXPECT_EQ(run({"--config", path_.c_str()}).config.observer.transport, qos::Transport::Network);
  EXPECT_EQ(run({"--transport", "loopback"}).config.observer.transport, qos::Transport::Loopback);
}

TEST_F(CommandLineTest, ALoneArgumentIsTheConfigFile) {
  EXPECT_EQ(run({path_.c_str()}).config.server.port, 6000);
  EXPECT_EQ(run({"--bind", "127.0.0.2", path_.c_str()}).config.server.bind_address, "127.0.0.2");
}

TEST_F(CommandLineTest, HelpNeedsNoValidConfig) {
  EXPECT_TRUE(run({"--help", "--config", "/nonexistent"}).help);
  const auto text = usage_text("mtc-bridge");
  for (const char* flag : {"--port", "--server-ip", "--domain-ids", "--devices", "--io-threads",
                           "--heartbeat-ms", "--config"}) {
    EXPECT_NE(text.find(flag), std::string::npos) << flag;
  }
}

TEST_F(CommandLineTest, BadFlagsNameTheFlag) {
  auto message_of = [](std::vector<const char*> args) -> std::string {
    try {
      run(std::move(args));
    } catch (const ConfigError& error) {
      return error.what();
    }
    return "(no error)";
  };
  EXPECT_EQ(message_of({"--prot", "1"}), "--prot: unknown option (see --help)");
  EXPECT_EQ(message_of({"--port"}), "--port: needs a value");
  EXPECT_EQ(message_of({"--port", "x"}),
            "--port: Port must be an integer from 0 to 65535, not 'x'");
  EXPECT_EQ(message_of({"a.cfg", "b.cfg"}), "b.cfg: only one config file may be given");
}

// SHDR is plain TCP: with DDS-Security or HTTPS configured, the adapter may
// only listen on loopback, whichever order the settings come in.
TEST_F(CommandLineTest, ASecuredBridgeKeepsThePlainShdrAdapterOnLoopback) {
  auto message_of = [](std::vector<const char*> args) -> std::string {
    try {
      run(std::move(args));
    } catch (const ConfigError& error) {
      return error.what();
    }
    return "(no error)";
  };
  const std::string refused =
      "ShdrIp: the SHDR adapter speaks plain TCP, so a secured bridge (SecurityDir or "
      "TlsCertificateChain) binds it to a loopback address only, not '";
  EXPECT_EQ(message_of({"--shdr-ip", "0.0.0.0", "--tls-certificate", "c.pem", "--tls-private-key",
                        "k.pem"}),
            refused + "0.0.0.0'");
  EXPECT_EQ(message_of({"--tls-certificate", "c.pem", "--shdr-ip", "::"}), refused + "::'");
  EXPECT_EQ(message_of({"--tls-certificate", "c.pem", "--shdr-ip", "10.1.2.3"}),
            refused + "10.1.2.3'");
  for (const char* loopback : {"127.0.0.1", "127.0.0.2", "::1", "::ffff:127.0.0.1"}) {
    const auto line = run({"--tls-certificate", "c.pem", "--shdr-ip", loopback});
    EXPECT_EQ(line.config.shdr.bind_address, loopback);
  }
  // Unsecured, any address is the operator's call; the default is loopback.
  EXPECT_EQ(run({"--shdr-ip", "0.0.0.0"}).config.shdr.bind_address, "0.0.0.0");
  EXPECT_EQ(run({"--tls-certificate", "c.pem", "--shdr-adapter", "yes"}).config.shdr.bind_address,
            "127.0.0.1");
}

}  // namespace
}  // namespace mtc::bridge
