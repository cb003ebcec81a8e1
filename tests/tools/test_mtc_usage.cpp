// The `mtc` tool's contract with users and scripts that needs no peer:
// --help for every command, exit code 2 with a clear message for every kind
// of bad input. These start no DDS participant (bad input is rejected first).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "child_process.hpp"

namespace mtc::test {
namespace {

constexpr milliseconds kExitTimeout{20000};

struct MtcRun {
  int code;
  std::string out;
  std::string err;
};

// transport-guard: usage errors and --help only, refused before any
// participant exists; the argument lists stay exactly as written.
MtcRun run_mtc(std::vector<std::string> args) {
  args.insert(args.begin(), MTC_CLI_PATH);
  ChildProcess child(args);
  const auto code = child.wait_exit(kExitTimeout);
  std::string out;
  for (const auto& l : child.lines()) {
    out += l + "\n";
  }
  return {code.value_or(-1), out, child.stderr_text()};
}

TEST(CliUsage, OverviewListsEveryCommandAndExitCodes) {
  const MtcRun r = run_mtc({"--help"});
  EXPECT_EQ(r.code, 0);
  for (const char* word : {"watch", "list", "request", "respond", "Exit codes"}) {
    EXPECT_NE(r.out.find(word), std::string::npos) << word << "\n" << r.out;
  }
}

TEST(CliUsage, NoCommandIsAUsageError) {
  const MtcRun r = run_mtc({});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("Usage: mtc <command>"), std::string::npos) << r.err;
}

TEST(CliUsage, EveryCommandHasHelpWithExamples) {
  for (const char* command : {"watch", "list", "request", "respond"}) {
    const MtcRun r = run_mtc({command, "--help"});
    EXPECT_EQ(r.code, 0) << command;
    EXPECT_NE(r.out.find(std::string("Usage: mtc ") + command), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("--domain"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("--qos-profile"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("Examples:"), std::string::npos) << r.out;
  }
}

// Every command takes --security; a directory that is not there is bad
// input (exit 2, named), found before any participant exists.
TEST(CliUsage, EveryCommandRefusesAMissingSecurityDirectoryNamingIt) {
  const std::vector<std::vector<std::string>> commands = {
      {"watch"},
      {"list"},
      {"request", "--device", "cnc-1", "--interface", "mh1", "--service", "MATERIAL_LOAD",
       "--counterpart", "robot-1"},
      {"respond", "--device", "robot-1", "--interface", "mh1", "--service", "MATERIAL_LOAD"}};
  for (auto args : commands) {
    args.insert(args.end(), {"--security", "/nonexistent/pki"});
    const MtcRun r = run_mtc(args);
    EXPECT_EQ(r.code, 2) << args[0] << "\n" << r.err;
    EXPECT_NE(r.err.find("/nonexistent/pki"), std::string::npos) << args[0] << "\n" << r.err;
  }
}

TEST(CliUsage, UnknownCommandExits2) {
  const MtcRun r = run_mtc({"frobnicate"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("unknown command 'frobnicate'"), std::string::npos) << r.err;
}

TEST(CliUsage, UnknownOptionExits2AndNamesIt) {
  const MtcRun r = run_mtc({"watch", "--colour"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("unknown option '--colour'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("mtc watch --help"), std::string::npos) << r.err;
}

TEST(CliUsage, MissingValueExits2) {
  const MtcRun r = run_mtc({"list", "--domain"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("needs a value"), std::string::npos) << r.err;
}

TEST(CliUsage, OutOfRangeDomainExits2) {
  const MtcRun r = run_mtc({"list", "--domain", "300"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--domain expects an integer in [0, 232]"), std::string::npos) << r.err;
}

TEST(CliUsage, UnknownQosProfileExits2AndListsKnownOnes) {
  const MtcRun r = run_mtc({"watch", "--qos-profile", "fast-please"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("unknown QoS profile 'fast-please'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("mtc.participant.loopback_udp"), std::string::npos) << r.err;
}

TEST(CliUsage, BadDurationExits2) {
  const MtcRun r = run_mtc({"watch", "--duration", "soon"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("duration like 500ms"), std::string::npos) << r.err;
}

TEST(CliUsage, UnknownServiceExits2AndListsTheTen) {
  const MtcRun r = run_mtc({"request", "--device", "robot-1", "--interface", "mh", "--service",
                            "MATERIAL_TELEPORT", "--counterpart", "machine-1"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("unknown service 'MATERIAL_TELEPORT'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("CLOSE_CHUCK"), std::string::npos) << r.err;
}

TEST(CliUsage, RequestWithoutRequiredFlagsExits2) {
  const MtcRun r = run_mtc({"request", "--service", "MATERIAL_LOAD"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--device"), std::string::npos) << r.err;
}

TEST(CliUsage, RespondRejectsBadFailureInjection) {
  MtcRun r = run_mtc({"respond", "--device", "m", "--interface", "mh", "--service", "MATERIAL_LOAD",
                      "--fail-at", "lunch"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--fail-at"), std::string::npos) << r.err;
  r = run_mtc({"respond", "--device", "m", "--interface", "mh", "--service", "MATERIAL_LOAD",
               "--fail-rate", "1.5"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--fail-rate expects a number in [0, 1]"), std::string::npos) << r.err;
}

TEST(CliUsage, BadTransportAndProfileForRequestExit2) {
  MtcRun r = run_mtc({"request", "--device", "robot-1", "--interface", "mh", "--service",
                      "MATERIAL_LOAD", "--counterpart", "machine-1", "--transport", "pigeon"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--transport expects loopback, loopback-udp, test or network"),
            std::string::npos)
      << r.err;
  r = run_mtc({"request", "--device", "robot-1", "--interface", "mh", "--service", "MATERIAL_LOAD",
               "--counterpart", "machine-1", "--qos-profile", "mtc.device_description"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("is an endpoint preset"), std::string::npos) << r.err;
}

TEST(CliUsage, InvalidDeviceOrInterfaceIdExits2WithTheRule) {
  // Rejected by the runtime's validation before anything touches the network.
  MtcRun r = run_mtc({"request", "--device", "robot 1", "--interface", "mh", "--service",
                      "MATERIAL_LOAD", "--counterpart", "machine-1"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("may only contain"), std::string::npos) << r.err;
  r = run_mtc({"respond", "--device", "m", "--interface", "1mh", "--service", "MATERIAL_LOAD"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("must not start with a digit"), std::string::npos) << r.err;
  // Its data item ids must fit the wire's 64 characters too.
  r = run_mtc({"respond", "--device", "m", "--interface", std::string(39, 'i'), "--service",
               "MATERIAL_RETRACT"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("at most 38 leave room for its data item ids"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace mtc::test
