// mtc-bridge: an MTConnect agent that mirrors the Part 5 interfaces published
// on DDS into standard probe/current/sample XML over HTTP.
//
// Exit codes: 0 clean stop, 1 runtime failure (port busy, DDS error),
// 2 bad configuration (config file, flags, Devices file, QoS profile).
#include <iostream>
#include <system_error>

#include "bridge_app.hpp"
#include "mtc/dds/error.hpp"

namespace {

constexpr int kExitRuntime = 1;
constexpr int kExitConfig = 2;

}  // namespace

int main(int argc, char** argv) {
  using mtc::bridge::BridgeApp;
  using mtc::bridge::CommandLine;
  using mtc::bridge::ConfigError;
  using mtc::bridge::ModelError;
  using mtc::bridge::parse_command_line;
  using mtc::bridge::usage_text;
  CommandLine line;
  try {
    line = parse_command_line(argc, argv);
  } catch (const ConfigError& error) {
    std::cerr << "mtc-bridge: " << error.what() << "\n";
    return kExitConfig;
  }
  if (line.help) {
    std::cout << usage_text("mtc-bridge");
    return 0;
  }
  for (const std::string& warning : line.warnings) {
    std::cerr << "mtc-bridge: warning: " << warning << "\n";
  }
  try {
    BridgeApp app(line.config);
    app.run(std::cout);
    return 0;
  } catch (const ModelError& error) {
    std::cerr << "mtc-bridge: Devices file: " << error.what() << "\n";
    return kExitConfig;
  } catch (const mtc::dds::ConfigError& error) {
    std::cerr << "mtc-bridge: DDS configuration: " << error.what() << "\n";
    return kExitConfig;
  } catch (const std::invalid_argument& error) {
    std::cerr << "mtc-bridge: configuration: " << error.what() << "\n";
    return kExitConfig;
  } catch (const std::system_error& error) {
    std::cerr << "mtc-bridge: " << error.what() << "\n";
    return kExitRuntime;
  } catch (const std::exception& error) {
    std::cerr << "mtc-bridge: " << error.what() << "\n";
    return kExitRuntime;
  }
}
